"""Every tool under AddressSanitizer + UndefinedBehaviorSanitizer (cmake -DLODBAKE_SANITIZE=ON;
registered only in such a build tree, with the ctest label `sanitize`): the whole chain and
compare on the generated samples and the small shared assets, the bad-input tests, and a short
fixed-seed mutation fuzz of .gltf text with external files. A run passes when it exits with a
code of the README's table and no sanitizer report (halt_on_error: the first report aborts).

Usage: test_sanitize.py CLASS... (Samples, Assets, BadInputs, Fuzz); none = all.
"""
import os
import subprocess
import sys
import unittest

import lodbake_test as lt

sys.path.insert(0, os.path.join(lt.SOURCE, "scripts"))
import fuzz_inputs  # noqa: E402  (scripts/fuzz_inputs.py: sanitizer settings and the fuzzer)

ENV = fuzz_inputs.sanitizer_environment()
THREADS = ["--threads", "2"]
# Small settings so the chain stays quick under the sanitizers; every code path still runs.
SIMPLIFY = ["--ratio", "0.5,0.1,0.02"]
AGSPHERE = ["--ratio", "0.5,0.1"]
PARAMETERIZE = ["--size", "256", "--iterations", "20"]
REFINE = ["--size", "128", "--sizes", "64,128"]
PACK = ["--max-size", "128", "--samples", "2000"]
COMPARE = ["--views", "2", "--resolution", "64", "--samples", "2000"]
# The small shared assets (BoxMeshopt: a required extension the project may not read yet).
ASSETS = {"BoxTextured": "BoxTextured/BoxTextured.glb", "Duck": "Duck/Duck.glb",
          "Avocado": "Avocado/Avocado.gltf", "BoxMeshopt": "BoxMeshopt/BoxMeshopt.glb"}
TABLE = (0, 1, 2, 3, 4)


class SanitizedRuns(unittest.TestCase):
    def sanitized(self, args, codes=(0,), timeout=900):
        """Runs a tool under the sanitizers; fails on a report, a signal or an exit code outside
        `codes`; returns the CompletedProcess."""
        p = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=timeout, env=ENV)
        report = fuzz_inputs.sanitizer_report(p.stderr)
        self.assertIsNone(report, "%s: sanitizer report:\n%s" % (" ".join(args), p.stderr[-6000:]))
        self.assertIn(p.returncode, codes, "%s: exit %d\n%s" % (" ".join(args), p.returncode, p.stderr[-3000:]))
        return p

    def chain(self, name, src, out_dir, codes=(0,)):
        """simplify, agsphere-build, parameterize, texture-refine, pack and compare on one input;
        stops after the first step that does not exit 0 (allowed only when `codes` says so)."""
        base = os.path.join(out_dir, name)
        steps = [
            [lt.tool("agsphere-build"), "-i", src, "-o", base + ".ag.glb"] + AGSPHERE,
            [lt.tool("simplify"), "-i", src, "-o", base + ".mr.glb", "--report", base + ".mr.json"] + SIMPLIFY,
            [lt.tool("parameterize"), "-i", base + ".mr.glb", "-o", base + ".uv.glb"] + PARAMETERIZE,
            [lt.tool("texture-refine"), "-i", base + ".uv.glb", "-o", base + ".tex.glb"] + REFINE,
            [lt.tool("pack"), "-i", base + ".tex.glb", "-o", base + ".lod.glb", "--report", base + ".lod.json"] + PACK,
        ]
        for step in steps:
            with self.subTest(input=name, tool=os.path.basename(step[0])):
                if self.sanitized(step + THREADS + ["--quiet"], codes).returncode != 0:
                    return False
        with self.subTest(input=name, tool="compare"):
            self.sanitized([lt.tool("compare"), src, base + ".lod.glb", "--lod", "2", "--json"] + COMPARE + THREADS)
        return True


class Samples(SanitizedRuns):
    """The chain on every sample of make-samples, and the output variants on one of them."""

    def test_samples(self):
        d = lt.work_dir("samples")
        self.sanitized([lt.tool("make-samples"), d])
        names = sorted(f[:-4] for f in os.listdir(d) if f.endswith(".glb"))
        self.assertGreaterEqual(len(names), 5)
        for n in names:
            self.chain(n, os.path.join(d, n + ".glb"), d)

    def test_output_variants(self):
        d = lt.work_dir("variants")
        self.sanitized([lt.tool("make-samples"), d])
        src = os.path.join(d, "seamball.glb")
        self.sanitized([lt.tool("simplify"), "-i", src, "-o", os.path.join(d, "s.mr.gltf")] + SIMPLIFY + THREADS)
        self.sanitized([lt.tool("parameterize"), "-i", os.path.join(d, "s.mr.gltf"), "-o", os.path.join(d, "s.uv.glb")]
                       + PARAMETERIZE + THREADS)
        uv = os.path.join(d, "s.uv.glb")
        for name, extra in (("draco.glb", ["--draco", "--image-format", "jpeg"]),
                            ("ext.gltf", ["--external-images", "--layout-bake", "--base-color-only"]),
                            ("split.glb", ["--split", "--normal-maps", "always", "--pot"])):
            with self.subTest(variant=name):
                out = os.path.join(d, "s." + name)
                self.sanitized([lt.tool("pack"), "-i", uv, "-o", out] + PACK + extra + THREADS)
        self.sanitized([lt.tool("compare"), src, os.path.join(d, "s.draco.glb"), "--lod", "1", "--json",
                        "--sheet", os.path.join(d, "sheet.png")] + COMPARE + THREADS)
        # A Draco chain read back: every tool's reader decodes it.
        self.sanitized([lt.tool("simplify"), "-i", os.path.join(d, "s.draco.glb"), "-o", os.path.join(d, "s.again.glb"),
                        "--ratio", "0.5"] + THREADS)


class Assets(SanitizedRuns):
    """The chain on the small shared assets; any exit code of the table is accepted (BoxMeshopt
    exits 2 while EXT_meshopt_compression is unsupported), a sanitizer report is not."""

    def test_assets(self):
        d = lt.work_dir("assets")
        for name, rel in sorted(ASSETS.items()):
            src = os.path.join(lt.ASSETS, rel)
            if not os.path.exists(src):
                print("note: %s is absent" % rel)
                continue
            self.chain(name, src, d, TABLE)


class BadInputs(SanitizedRuns):
    """test_bad_inputs.py's cases (its own files and ../shared/bad-inputs) on the sanitized tools,
    plus compare on each bad input."""

    def test_bad_inputs_suite(self):
        env = dict(ENV, LODBAKE_WORK=os.path.join(lt.WORK, "bad-inputs"))
        p = subprocess.run([sys.executable, os.path.join(os.path.dirname(__file__), "test_bad_inputs.py")],
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env, timeout=1800)
        self.assertIsNone(fuzz_inputs.sanitizer_report(p.stdout), p.stdout[-6000:])
        self.assertIn(p.returncode, (0, lt.SKIP), p.stdout[-6000:])

    def test_compare_bad_inputs(self):
        if not os.path.isdir(lt.BAD_INPUTS):
            self.skipTest("../shared/bad-inputs is absent")
        d = lt.work_dir("compare-bad")
        self.sanitized([lt.tool("make-samples"), d])
        good = os.path.join(d, "colors.glb")
        for name in sorted(os.listdir(lt.BAD_INPUTS)):
            if name.endswith((".gltf", ".glb")):
                with self.subTest(case=name):
                    bad = os.path.join(lt.BAD_INPUTS, name)
                    p = self.sanitized([lt.tool("compare"), good, bad] + COMPARE, (2, 3))
                    self.assertEqual(len(p.stderr.strip().splitlines()), 1, p.stderr)


class Fuzz(SanitizedRuns):
    """scripts/fuzz_inputs.py, fixed seeds, a few rounds per tool on .gltf text with an external
    .bin and PNG (BoxTextured split out of its GLB) and on the GLB itself."""

    ROUNDS = {"simplify": 60, "agsphere-build": 40, "parameterize": 30, "texture-refine": 20, "pack": 20,
              "compare": 30}
    FLAGS = {"simplify": ["--ratio", "0.5"], "agsphere-build": ["--ratio", "0.5"], "parameterize": ["--size", "64"],
             "texture-refine": ["--sizes", "32,64", "--size", "64"], "pack": ["--max-size", "64", "--samples", "500"],
             "compare": ["--views", "1", "--resolution", "32", "--samples", "500"]}

    def test_fuzz(self):
        d = lt.work_dir("fuzz")
        self.sanitized([lt.tool("make-samples"), d])
        box = os.path.join(lt.ASSETS, "BoxTextured/BoxTextured.glb")
        src = os.path.join(d, "colors.glb")
        mr = os.path.join(d, "src.mr.glb")
        uv = os.path.join(d, "src.uv.glb")
        if os.path.exists(box):
            src = box
        self.sanitized([lt.tool("simplify"), "-i", src, "-o", mr, "--ratio", "0.5"])
        self.sanitized([lt.tool("parameterize"), "-i", mr, "-o", uv, "--size", "64"])
        # The stage each tool reads: any glTF for the first two, a parameterized file for the rest.
        inputs = {"simplify": src, "agsphere-build": src, "compare": src, "parameterize": mr, "texture-refine": uv,
                  "pack": uv}
        for seed, (name, rounds) in enumerate(sorted(self.ROUNDS.items())):
            with self.subTest(tool=name):
                work = os.path.join(d, name)
                p = subprocess.run([sys.executable, fuzz_inputs.__file__, lt.tool(name), str(seed + 1), str(rounds),
                                    "--split-glb", inputs[name], "--"] + self.FLAGS[name],
                                   stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                   env=dict(ENV, DIR=work, TIMEOUT="120"), timeout=3600)
                print(p.stdout.strip().splitlines()[-1] if p.stdout.strip() else "")
                self.assertEqual(p.returncode, 0, p.stdout[-4000:])


if __name__ == "__main__":
    classes = {c.__name__: c for c in (Samples, Assets, BadInputs, Fuzz)}
    chosen = sys.argv[1:] or list(classes)
    if chosen == ["Assets"] and not os.path.isdir(lt.ASSETS):
        lt.skip("../shared/assets is absent; the Samples test covers every tool")
    lt.main([classes[n] for n in chosen])
