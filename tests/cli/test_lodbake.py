"""lodbake, the one-command chain: its LOD chain is byte-identical to running simplify ->
parameterize -> texture-refine -> pack with the same flags (and to simplify -> parameterize -> pack
with --no-texture-refine), whatever --threads; --keep-intermediates writes the tools' intermediates
byte for byte and nothing is written between the stages without it; the report has one section per
stage (each tool's own report) plus the total time; parameterize's atlas image, which nothing
downstream reads, is baked only into a kept .uv.glb; bad flags and inputs give the documented exit
codes, a one-line error and no output file."""
import json
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
from lodbake_test import (ASSETS, SOURCE, Gltf, assert_no_validator_errors, make_samples, run, skip,  # noqa: E402
                          tool, work_dir)

SAMPLE = "colors"
SIMPLIFY = ["--ratio", "0.5,0.1"]
PARAMETERIZE = ["--size", "128"]
REFINE = ["--size", "128", "--sizes", "64,128"]
PACK = ["--max-size", "128", "--samples", "16"]
# lodbake's names for the same flags: texture-refine's --size is --refine-size there.
CHAIN = SIMPLIFY + PARAMETERIZE + ["--refine-size", "128", "--sizes", "64,128"] + PACK


def read(path):
    with open(path, "rb") as f:
        return f.read()


class Lodbake(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if not os.path.exists(tool("lodbake")):
            skip("lodbake is not built")
        cls.dir = work_dir("lodbake")
        cls.src = os.path.join(make_samples(os.path.join(cls.dir, "samples")), SAMPLE + ".glb")

    def tools_chain(self, out, refine=True):
        """The separate tools, one file each, --threads 1; returns the final chain's path."""
        mr, uv, tex, lod = (os.path.join(out, SAMPLE + s) for s in (".mr.glb", ".uv.glb", ".tex.glb", ".lod.glb"))
        one = ["--threads", "1", "-q"]
        run([tool("simplify"), "-i", self.src, "-o", mr] + SIMPLIFY + one)
        run([tool("parameterize"), "-i", mr, "-o", uv] + PARAMETERIZE + one)
        if refine:
            run([tool("texture-refine"), "-i", uv, "-o", tex] + REFINE + one)
        run([tool("pack"), "-i", tex if refine else uv, "-o", lod] + PACK + one)
        return lod

    def test_same_bytes_as_the_tools(self):
        tools_dir = os.path.join(self.dir, "tools")
        os.makedirs(tools_dir, exist_ok=True)
        expected = self.tools_chain(tools_dir)

        out = os.path.join(self.dir, "chain")
        keep = os.path.join(self.dir, "keep")
        os.makedirs(out, exist_ok=True)
        os.makedirs(keep, exist_ok=True)
        lod, report = os.path.join(out, SAMPLE + ".lod.glb"), os.path.join(out, SAMPLE + ".json")
        run([tool("lodbake"), "-i", self.src, "-o", lod, "--report", report, "--threads", "2", "-q"] + CHAIN)
        self.assertEqual(read(lod), read(expected), "lodbake's chain differs from the tools'")
        self.assertEqual(sorted(os.listdir(out)), sorted([SAMPLE + ".lod.glb", SAMPLE + ".json"]),
                         "lodbake wrote intermediates without --keep-intermediates")

        rep = json.load(open(report))
        self.assertEqual(rep["tool"], "lodbake")
        self.assertEqual([s["tool"] for s in rep["stages"]], ["simplify", "parameterize", "texture-refine", "pack"])
        self.assertEqual(rep["stages"][0]["input"]["path"], self.src)
        self.assertEqual(rep["stages"][-1]["output"]["path"], lod)
        self.assertEqual(len(rep["stages"][-1]["levels"]), 3)  # LOD0 + two simplified levels
        self.assertGreater(rep["time"]["total"], 0)
        self.assertEqual(rep["intermediates"], [])
        # Nothing downstream reads parameterize's atlas image: the chain bakes it only when kept
        # (the bytes above show pack's output does not depend on it).
        self.assertFalse(rep["stages"][1]["total"]["imageBaked"])
        self.assertEqual(rep["stages"][1]["total"]["coveredTexels"], 0)

        # --keep-intermediates: the tools' files, byte for byte; -v: each stage's statistics.
        lod2 = os.path.join(out, SAMPLE + ".keep.lod.glb")
        report2 = os.path.join(out, SAMPLE + ".keep.json")
        p = run([tool("lodbake"), "-i", self.src, "-o", lod2, "--keep-intermediates", keep, "-v", "-q", "--report", report2]
                + CHAIN)
        self.assertEqual(read(lod2), read(expected))
        self.assertTrue(json.load(open(report2))["stages"][1]["total"]["imageBaked"])
        for suffix in (".mr.glb", ".uv.glb", ".tex.glb"):
            with self.subTest(intermediate=suffix):
                self.assertEqual(read(os.path.join(keep, SAMPLE + suffix)), read(os.path.join(tools_dir, SAMPLE + suffix)))
        for stage in ("simplify:", "parameterize:", "texture-refine:", "pack:"):
            self.assertIn("\n" + stage + "\n", "\n" + p.stdout)
        self.assertEqual(p.stderr, "")

        # A valid MSFT_lod chain.
        g = Gltf(lod)
        self.assertIn("MSFT_lod", g.json["extensionsUsed"])
        self.assertEqual(len(g.json["nodes"][0]["extensions"]["MSFT_lod"]["ids"]), 2)
        assert_no_validator_errors(self, [lod])

    def test_no_texture_refine(self):
        tools_dir = os.path.join(self.dir, "tools-norefine")
        os.makedirs(tools_dir, exist_ok=True)
        expected = self.tools_chain(tools_dir, refine=False)
        lod, report = os.path.join(self.dir, "norefine.lod.glb"), os.path.join(self.dir, "norefine.json")
        run([tool("lodbake"), "-i", self.src, "-o", lod, "--no-texture-refine", "--report", report, "-q"] + CHAIN)
        self.assertEqual(read(lod), read(expected))
        self.assertEqual([s["tool"] for s in json.load(open(report))["stages"]], ["simplify", "parameterize", "pack"])

    def test_bad_flags_and_inputs(self):
        out = os.path.join(self.dir, "bad.lod.glb")
        cases = [
            (["-i", self.src, self.src, "-o", out], 1, "need -o DIR/"),
            (["-i", self.src, "-o", out, "--ratio", "0.5", "--refine-split", "1"], 1, "--refine-split must be >= 2"),
            (["-i", self.src, "-o", out, "--ratio", "0.5", "--split", "3"], 2, "3: no such file"),  # 3: an input
            (["-i", self.src, "-o", out, "--ratio", "0.5", "--bogus"], 1, "unrecognized option '--bogus'"),
            (["-i", os.path.join(self.dir, "missing.glb"), "-o", out, "--ratio", "0.5"], 2, "no such file"),
            (["-i", self.src, "-o", out, "--ratio", "0.5", "--keep-intermediates", os.path.join(self.dir, "nope")], 2,
             "folder does not exist"),
        ]
        for args, code, message in cases:
            with self.subTest(args=" ".join(args[4:])):
                p = run([tool("lodbake")] + args, check=False)
                self.assertEqual(p.returncode, code, p.stderr)
                self.assertIn(message, p.stderr)
                self.assertEqual(len(p.stderr.strip().splitlines()), 1, p.stderr)
                self.assertTrue(p.stderr.startswith("lodbake error: "), p.stderr)
                self.assertFalse(os.path.exists(out))

    def lodbake_asset(self, src, name, threads="2"):
        """lodbake (the small CHAIN flags) on `src`; returns (process, output path)."""
        out = os.path.join(self.dir, name + ".lod.glb")
        p = run([tool("lodbake"), "-i", src, "-o", out, "--threads", threads, "-q"] + CHAIN, check=False)
        return p, out

    def assert_clean_stderr(self, stderr):
        """Every stderr line is lodbake's own: no glog or CHOLMOD line gets through."""
        for line in stderr.splitlines():
            self.assertTrue(line.startswith(("lodbake warning: ", "lodbake error: ")), "foreign stderr line: %r" % line)

    def test_required_specular_glossiness(self):
        # A file that requires KHR_materials_pbrSpecularGlossiness (converted on reading) goes through.
        src_dir = "/usr/share/assimp/models/glTF2/BoxTextured-glTF-pbrSpecularGlossiness"
        if not os.path.isdir(src_dir):
            self.skipTest("assimp-testmodels is not installed")
        d = os.path.join(self.dir, "specgloss")
        os.makedirs(d, exist_ok=True)
        for f in os.listdir(src_dir):
            with open(os.path.join(src_dir, f), "rb") as i, open(os.path.join(d, f), "wb") as o:
                o.write(i.read())
        path = os.path.join(d, "BoxTextured.gltf")
        with open(path) as f:
            doc = json.load(f)
        doc["extensionsRequired"] = ["KHR_materials_pbrSpecularGlossiness"]
        with open(path, "w") as f:
            json.dump(doc, f)
        p, out = self.lodbake_asset(path, "specgloss")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assert_clean_stderr(p.stderr)
        assert_no_validator_errors(self, [out])

    def test_clean_stderr_on_assets(self):
        # Assets whose charts made Ceres log linear solver failures through glog (and CHOLMOD
        # print its "not positive definite" warning) before lodbake silenced them.
        names = [n for n in ("NegativeScaleTest/NegativeScaleTest.glb", "SpecularTest/SpecularTest.glb")
                 if os.path.exists(os.path.join(ASSETS, n))]
        if not names:
            self.skipTest("../shared/assets is absent")
        for n in names:
            with self.subTest(asset=n):
                p, _ = self.lodbake_asset(os.path.join(ASSETS, n), os.path.basename(n).split(".")[0])
                self.assertEqual(p.returncode, 0, p.stderr)
                self.assert_clean_stderr(p.stderr)

    def test_instances_lights_and_cameras(self):
        # EXT_mesh_gpu_instancing: LOD0 holds every instance (125 cubes x 12 triangles);
        # KHR_lights_punctual and cameras: as many lights, cameras and their nodes as the input.
        cases = [("SimpleInstancing/SimpleInstancing.glb", 125 * 12, 0, 0),
                 ("LightsPunctualLamp/LightsPunctualLamp.gltf", None, 5, 0),
                 ("MultiUVTest/MultiUVTest.glb", None, 0, 1)]
        cases = [c for c in cases if os.path.exists(os.path.join(ASSETS, c[0]))]
        if not cases:
            self.skipTest("../shared/assets is absent")
        for name, triangles, lights, cameras in cases:
            with self.subTest(asset=name):
                p, out = self.lodbake_asset(os.path.join(ASSETS, name), os.path.basename(name).split(".")[0])
                self.assertEqual(p.returncode, 0, p.stderr)
                self.assert_clean_stderr(p.stderr)
                g = Gltf(out)
                if triangles is not None:
                    self.assertEqual(g.mesh_triangle_count(0), triangles)
                doc = g.json
                self.assertEqual(len(doc.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])), lights)
                self.assertEqual(len(doc.get("cameras", [])), cameras)
                scene = doc["scenes"][doc.get("scene", 0)]["nodes"]
                light_nodes = [n for n in scene if "KHR_lights_punctual" in doc["nodes"][n].get("extensions", {})]
                camera_nodes = [n for n in scene if "camera" in doc["nodes"][n]]
                self.assertEqual(len(light_nodes), lights)
                self.assertEqual(len(camera_nodes), cameras)
                if lights:
                    self.assertIn("KHR_lights_punctual", doc["extensionsUsed"])
                assert_no_validator_errors(self, [out])

    def test_defaults(self):
        """`lodbake IN` writes IN's stem + .lod.glb beside it, `-o DIR/` into DIR, and without a level
        flag the chain has the default levels 0.5, 0.1, 0.02 (the report says so)."""
        d = os.path.join(self.dir, "defaults")
        os.makedirs(os.path.join(d, "into"), exist_ok=True)
        src = os.path.join(d, SAMPLE + ".glb")
        with open(src, "wb") as f:
            f.write(read(self.src))
        small = ["--size", "128", "--refine-size", "128", "--sizes", "64,128", "--max-size", "128", "-q"]
        report = os.path.join(d, "beside.json")
        run([tool("lodbake"), src, "--report", report] + small)
        beside = os.path.join(d, SAMPLE + ".lod.glb")
        self.assertTrue(os.path.exists(beside))
        self.assertEqual(len(Gltf(beside).json["meshes"]), 4)  # LOD0 + the three default levels
        simplify = json.load(open(report))["stages"][0]
        self.assertIn("default", simplify["levelsChosen"])
        self.assertEqual([lv["target"]["ratio"] for lv in simplify["levels"]], [0.5, 0.1, 0.02])
        run([tool("lodbake"), "-i", src, "-o", os.path.join(d, "into") + "/"] + small)
        self.assertEqual(read(os.path.join(d, "into", SAMPLE + ".lod.glb")), read(beside))

    def test_batch(self):
        """Several inputs or a folder: a chain per file, -j 2 at a time, the same bytes as a
        single-file run; a malformed file fails alone (its row names the error, exit 2) and the
        summary report matches docs/schemas/lodbake-batch.schema.json."""
        d = os.path.join(self.dir, "batch")
        src, elsewhere = os.path.join(d, "in"), os.path.join(d, "elsewhere")
        os.makedirs(src, exist_ok=True)
        os.makedirs(elsewhere, exist_ok=True)
        # A symlinked subfolder is walked, and its chain still goes under -o, never beside the target.
        if not os.path.islink(os.path.join(src, "sub")):
            os.symlink(elsewhere, os.path.join(src, "sub"))
        samples = os.path.dirname(self.src)
        for name, dst in (("colors.glb", os.path.join(src, "colors.glb")), ("wall5.glb", os.path.join(elsewhere, "wall5.glb"))):
            with open(dst, "wb") as f:
                f.write(read(os.path.join(samples, name)))
        with open(os.path.join(src, "broken.glb"), "wb") as f:
            f.write(b"glTF\x02\x00\x00\x00not a binary glTF")
        out, summary = os.path.join(d, "out"), os.path.join(d, "summary.json")
        p = run([tool("lodbake"), "-i", src, "-o", out + "/", "-j", "2", "--report", summary] + CHAIN, check=False)
        self.assertEqual(p.returncode, 2, p.stderr)
        errors = [l for l in p.stderr.splitlines() if " error: " in l]
        self.assertEqual(len(errors), 1, p.stderr)
        self.assertTrue(all(l.startswith("lodbake ") for l in p.stderr.splitlines()), p.stderr)
        rep = json.load(open(summary))
        rows = {os.path.relpath(r["input"], src): r for r in rep["files"]}
        self.assertEqual(sorted(rows), ["broken.glb", "colors.glb", os.path.join("sub", "wall5.glb")])
        self.assertEqual((rep["succeeded"], rep["failed"], rep["jobs"]), (2, 1, 2))
        self.assertEqual(rows["broken.glb"]["exit"], 2)
        self.assertIn("broken.glb", rows["broken.glb"]["error"])
        self.assertFalse(os.path.exists(os.path.join(out, "broken.lod.glb")))
        single = os.path.join(d, "colors.single.lod.glb")
        run([tool("lodbake"), "-i", self.src, "-o", single, "-q"] + CHAIN)
        self.assertEqual(read(os.path.join(out, "colors.lod.glb")), read(single))
        wall = rows[os.path.join("sub", "wall5.glb")]
        self.assertEqual((wall["exit"], wall["levels"], wall["output"]), (0, 3, os.path.join(out, "sub", "wall5.lod.glb")))
        self.assertEqual(wall["bytes"], os.path.getsize(wall["output"]))
        self.assertEqual(len(wall["triangles"]), 3)
        self.assertEqual(os.listdir(elsewhere), ["wall5.glb"])
        try:
            import jsonschema
        except ImportError:
            return
        schema = json.load(open(os.path.join(SOURCE, "docs/schemas/lodbake-batch.schema.json")))
        jsonschema.Draft202012Validator(schema).validate(rep)

    def test_help_lists_every_stage(self):
        h = run([tool("lodbake"), "--help"]).stdout
        for flag in ("--ratio", "--size", "--refine-size", "--sizes", "--pixel-error", "--split", "--refine-split",
                     "--keep-intermediates", "--no-texture-refine", "--threads", "--report"):
            self.assertRegex(h, r"\n  (-\w, )?%s[ ,\n]" % flag)
        for stage in ("simplify", "parameterize", "texture-refine", "pack"):
            self.assertIn("\n%s (docs/%s.md" % (stage, stage), h)


if __name__ == "__main__":
    unittest.main()
