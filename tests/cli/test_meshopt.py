"""EXT_meshopt_compression inputs (the form gltfpack writes): every mode and filter decodes, and the
geometry read equals the uncompressed source's within gltfpack's quantisation (compare's
Hausdorff distance); KHR_meshopt_compression, which Debian's meshoptimizer 0.18 cannot decode, and
a corrupt stream are one-line exit-2 errors."""
import json
import os
import shutil
import struct
import unittest

import lodbake_test as lt

# gltfpack's default 14-bit positions: half a quantisation step of the bounding box is
# 1/32766 ~ 3.1e-5 of an axis; the diagonal is longer than any axis.
MAX_REL_HAUSDORFF = 6e-5

NPM_GLTFPACK = os.path.join(lt.NODE_MODULES, ".bin", "gltfpack")


def glb_json(path):
    with open(path, "rb") as f:
        b = f.read()
    n = struct.unpack_from("<I", b, 12)[0]
    return json.loads(b[20:20 + n])


def meshopt_kinds(path):
    """{(mode, filter)} of the file's compressed bufferViews (EXT or KHR)."""
    return {(e["mode"], e.get("filter", "NONE")) for v in glb_json(path).get("bufferViews", [])
            for e in v.get("extensions", {}).values()}


class Meshopt(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if shutil.which("gltfpack") is None:
            lt.skip("gltfpack is missing (apt-get install gltfpack; scripts/setup-debian.sh)")
        cls.dir = lt.work_dir("meshopt")
        lt.make_samples(cls.dir)

    def pack(self, src, name, *flags, gltfpack="gltfpack"):
        out = os.path.join(self.dir, name)
        lt.run([gltfpack, "-i", src, "-o", out] + list(flags))
        return out

    def assert_same_geometry(self, original, packed):
        r = lt.run([lt.tool("compare"), original, packed, "--views", "0", "--samples", "20000", "--json"])
        rel = json.loads(r.stdout)["geometry"]["relHausdorff"]
        self.assertLess(rel, MAX_REL_HAUSDORFF, packed)

    def test_debian_gltfpack_c_and_cc(self):
        """gltfpack 0.18 -c (ATTRIBUTES, TRIANGLES) and -cc (+ OCTAHEDRAL) on two samples, GLB and .gltf."""
        for s in ("seamball", "pbrscene"):
            src = os.path.join(self.dir, s + ".glb")
            for flag in ("-c", "-cc"):
                with self.subTest(sample=s, flag=flag):
                    out = self.pack(src, "%s%s.glb" % (s, flag), flag)
                    self.assertIn("EXT_meshopt_compression", glb_json(out)["extensionsRequired"])
                    self.assert_same_geometry(src, out)
                    if flag == "-cc":
                        self.assertIn(("ATTRIBUTES", "OCTAHEDRAL"), meshopt_kinds(out))
        # .gltf + .bin: the fallback buffer has neither uri nor data.
        self.assert_same_geometry(os.path.join(self.dir, "seamball.glb"),
                                  self.pack(os.path.join(self.dir, "seamball.glb"), "seamball-c.gltf", "-c"))

    def test_quaternion_filter(self):
        """CesiumMilkTruck -cc: its animation's rotations use the QUATERNION filter."""
        assets = lt.require_assets()
        out = self.pack(assets["CesiumMilkTruck"], "truck-cc.glb", "-cc")
        self.assertIn(("ATTRIBUTES", "QUATERNION"), meshopt_kinds(out))
        self.assert_same_geometry(assets["CesiumMilkTruck"], out)

    def test_box_meshopt_chain(self):
        """../shared/assets/BoxMeshopt (quantized, compressed) is the box of BoxTextured; simplify and
        parameterize read it."""
        assets = lt.require_assets()
        box = os.path.join(lt.ASSETS, "BoxMeshopt/BoxMeshopt.glb")
        if not os.path.exists(box):
            self.skipTest("../shared/assets/BoxMeshopt is absent")
        self.assert_same_geometry(assets["BoxTextured"], box)
        mr = os.path.join(self.dir, "box.mr.glb")
        lt.run([lt.tool("simplify"), "-i", box, "-o", mr, "--ratio", "0.5", "--quiet"])
        lt.run([lt.tool("parameterize"), "-i", mr, "-o", os.path.join(self.dir, "box.uv.glb"), "--quiet"])

    def test_npm_gltfpack_exponential_and_khr(self):
        """The newer npm gltfpack: -vpf positions use the EXPONENTIAL filter; -ce khr writes
        KHR_meshopt_compression, an exit-2 one-line error naming it."""
        if not os.path.exists(NPM_GLTFPACK):
            self.skipTest("scripts/node/node_modules/.bin/gltfpack is missing (cd scripts/node && npm ci)")
        src = os.path.join(self.dir, "seamball.glb")
        out = self.pack(src, "seamball-vpf.glb", "-cc", "-vpf", gltfpack=NPM_GLTFPACK)
        self.assertIn(("ATTRIBUTES", "EXPONENTIAL"), meshopt_kinds(out))
        self.assert_same_geometry(src, out)
        khr = self.pack(src, "seamball-khr.glb", "-cc", "-ce", "khr", gltfpack=NPM_GLTFPACK)
        dst = os.path.join(self.dir, "khr.mr.glb")
        p = lt.run([lt.tool("simplify"), "-i", khr, "-o", dst, "--ratio", "0.5"], check=False)
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertEqual(len(p.stderr.strip().splitlines()), 1, p.stderr)
        self.assertIn("KHR_meshopt_compression", p.stderr)
        self.assertIn(khr, p.stderr)
        self.assertFalse(os.path.exists(dst))

    def test_corrupt_stream(self):
        """A compressed view whose byteLength cuts its stream short: exit 2, one line naming the view."""
        src = self.pack(os.path.join(self.dir, "seamball.glb"), "cut-src.glb", "-c")
        with open(src, "rb") as f:
            glb = f.read()

        def cut(doc):
            for v in doc["bufferViews"]:
                e = v.get("extensions", {}).get("EXT_meshopt_compression")
                if e and e["mode"] == "ATTRIBUTES":
                    e["byteLength"] = 8
                    return

        bad = os.path.join(self.dir, "cut.glb")
        with open(bad, "wb") as f:
            f.write(lt.glb_with_json(glb, cut))
        dst = os.path.join(self.dir, "cut.mr.glb")
        p = lt.run([lt.tool("simplify"), "-i", bad, "-o", dst, "--ratio", "0.5"], check=False)
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertEqual(len(p.stderr.strip().splitlines()), 1, p.stderr)
        self.assertIn("EXT_meshopt_compression", p.stderr)
        self.assertFalse(os.path.exists(dst))


if __name__ == "__main__":
    lt.main([Meshopt])
