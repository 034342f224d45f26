"""Install rules and the Debian package. `cmake --install` into a temporary prefix puts every tool
in PREFIX/bin, the documentation in PREFIX/share/doc/lodbake and the man page in PREFIX/share/man/man1, and the installed `lodbake` builds
a valid MSFT_lod chain from a generated sample; `cpack -G DEB` makes a package whose contents list
the same files, with Depends derived by dpkg-shlibdeps, and whose tools run after `dpkg -x` (the
test never installs into the system)."""
import json
import os
import shutil
import subprocess
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
from lodbake_test import BIN, Gltf, assert_no_validator_errors, make_samples, run, skip, work_dir  # noqa: E402

BUILD = os.path.dirname(os.path.abspath(BIN))
TOOLS = ["simplify", "agsphere-build", "parameterize", "texture-refine", "pack", "compare", "make-samples", "lodbake"]
DOCS = ["README.md", "lodbake.md", "simplify.md", "parameterize.md", "texture-refine.md", "pack.md", "compare.md"]
SCHEMAS = ["simplify", "agsphere-build", "parameterize", "texture-refine", "pack", "compare", "lodbake"]
SMALL_CHAIN = ["--ratio", "0.5,0.1", "--size", "128", "--refine-size", "128", "--sizes", "64,128", "--max-size", "128",
               "--samples", "16"]


def check_tree(tc, root, prefix):
    """Every tool, page and schema is under root/prefix."""
    for t in TOOLS:
        path = os.path.join(root, prefix, "bin", t)
        tc.assertTrue(os.access(path, os.X_OK), path)
    for d in DOCS:
        tc.assertTrue(os.path.isfile(os.path.join(root, prefix, "share/doc/lodbake", d)), d)
    for s in SCHEMAS:
        tc.assertTrue(os.path.isfile(os.path.join(root, prefix, "share/doc/lodbake/schemas", s + ".schema.json")), s)
    tc.assertTrue(os.path.isfile(os.path.join(root, prefix, "share/man/man1/lodbake.1")), "lodbake.1")


class Install(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if not os.path.isfile(os.path.join(BUILD, "CMakeCache.txt")):
            skip("no CMake build folder above " + BIN)
        if not os.path.exists(os.path.join(BIN, "lodbake")):
            skip("lodbake is not built")
        cls.dir = work_dir("install")

    def test_install_prefix_and_chain(self):
        prefix = os.path.join(self.dir, "prefix")
        run(["cmake", "--install", BUILD, "--prefix", prefix])
        check_tree(self, prefix, "")
        samples = make_samples(os.path.join(self.dir, "samples"))
        out = os.path.join(self.dir, "colors.lod.glb")
        report = os.path.join(self.dir, "colors.json")
        # The installed tools only: a PATH without the build folder.
        env = dict(os.environ, PATH=os.path.join(prefix, "bin") + ":/usr/bin:/bin")
        p = subprocess.run(["lodbake", "-i", os.path.join(samples, "colors.glb"), "-o", out, "--report", report, "-q"]
                           + SMALL_CHAIN, env=env, capture_output=True, text=True)
        self.assertEqual(p.returncode, 0, p.stderr)
        g = Gltf(out)
        self.assertIn("MSFT_lod", g.json["extensionsUsed"])
        self.assertEqual(len(g.json["nodes"][0]["extensions"]["MSFT_lod"]["ids"]), 2)
        self.assertEqual(len(json.load(open(report))["stages"][-1]["levels"]), 3)
        assert_no_validator_errors(self, [out])

    def test_debian_package(self):
        for exe in ("cpack", "dpkg-deb", "dpkg-shlibdeps"):
            if shutil.which(exe) is None:
                self.skipTest(exe + " is missing (apt-get install dpkg-dev; scripts/setup-debian.sh)")
        pkgdir = os.path.join(self.dir, "deb")
        run(["cpack", "-G", "DEB", "--config", os.path.join(BUILD, "CPackConfig.cmake"), "-B", pkgdir])
        debs = [f for f in os.listdir(pkgdir) if f.endswith(".deb")]
        self.assertEqual(len(debs), 1, debs)
        deb = os.path.join(pkgdir, debs[0])

        listing = run(["dpkg-deb", "-c", deb]).stdout
        files = {line.split()[-1].lstrip(".") for line in listing.splitlines()}
        for t in TOOLS:
            self.assertIn("/usr/bin/" + t, files)
        for d in DOCS:
            self.assertIn("/usr/share/doc/lodbake/" + d, files)
        depends = run(["dpkg-deb", "-f", deb, "Depends"]).stdout
        for lib in ("libc6", "libstdc++6", "libopenimageio", "libdraco"):
            self.assertIn(lib, depends)

        root = os.path.join(self.dir, "unpacked")
        run(["dpkg-deb", "-x", deb, root])
        check_tree(self, root, "usr")
        samples = make_samples(os.path.join(self.dir, "deb-samples"))
        mr = os.path.join(self.dir, "wall5.mr.glb")
        for t in TOOLS:
            self.assertEqual(run([os.path.join(root, "usr/bin", t), "--version"]).stdout.strip(), t + " (lodbake) 0.1.0")
        run([os.path.join(root, "usr/bin/simplify"), "-i", os.path.join(samples, "wall5.glb"), "-o", mr, "--ratio",
             "0.5", "-q"])
        self.assertIn("LODBAKE_multires", Gltf(mr).json["extensionsUsed"])


if __name__ == "__main__":
    unittest.main()
