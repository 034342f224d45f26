"""KHR_materials_variants survive the chain (issue 30 item 5).

The `variants` sample (make-samples: a checkerboard ball on a grey pedestal; variants "red" = red
ball, "blue" = blue checkerboard ball and red pedestal, "gold" = gold pedestal, "classic" = both
parts mapped to their default materials) through `lodbake --ratio 0.5,0.1` and through the
separate tools (simplify, parameterize, texture-refine, pack). Checks: the output keeps the root
variant names in order; every level's primitive maps every variant to a material of the file,
LOD0 to its own baked material per variant that changes a part LOD0 shows, "classic" to the
level's default material (nothing baked twice); images equal between a variant's material and the default's are stored once;
the pack report lists the variants per level; glTF-Validator finds no error; and three.js renders
LOD0 with each variant selected (scripts/render_three.py FILE#node=0&variant=NAME applies the
mappings) at >= 35 dB PSNR against the original with the same variant selected, the default too,
while the original's variants differ visibly from its default (the selection does something).
"""
import json
import os
import subprocess
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import lodbake_test as lt  # noqa: E402

RENDER = os.path.join(lt.SOURCE, "scripts/render_three.py")
VARIANTS = ["red", "blue", "gold", "classic"]
CHANGING = ["red", "blue", "gold"]  # "classic" is the default look
# lodbake's defaults otherwise: LOD0 then holds the original's texels one to one (source texels),
# the variants' too where their textures share the default's texel grid (the blue ball's does).
FLAGS = ["--ratio", "0.5,0.1", "--quiet"]
LOD0_PSNR_MIN = 35.0      # dB: every variant at LOD0, as three.js selects it, indistinguishable from the original
DIFFERENT_PSNR_MAX = 30.0  # dB: a variant of the original against its default looks different


def pack_levels(report):
    for stage in report.get("stages", [report]):
        if stage.get("tool") == "pack":
            return stage["levels"]
    raise AssertionError("no pack levels in the report")


class Variants(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        lt.require_tools("lodbake", "make-samples", "simplify", "parameterize", "texture-refine", "pack")
        cls.dir = lt.work_dir("variants")
        samples = lt.make_samples(os.path.join(cls.dir, "samples"))
        cls.src = os.path.join(samples, "variants.glb")
        cls.out = os.path.join(cls.dir, "variants.lod.glb")
        rep = cls.out + ".json"
        p = lt.run([lt.tool("lodbake"), "-i", cls.src, "-o", cls.out, "--report", rep] + FLAGS)
        cls.stderr = p.stderr
        with open(rep) as f:
            cls.report = json.load(f)
        cls.gltf = lt.Gltf(cls.out).json

    def level_primitives(self, j):
        """(node index, primitive) of every level: node 0 and its MSFT_lod ids."""
        ids = [0] + j["nodes"][0].get("extensions", {}).get("MSFT_lod", {}).get("ids", [])
        return [(n, j["meshes"][j["nodes"][n]["mesh"]]["primitives"][0]) for n in ids]

    def check_chain(self, j):
        self.assertIn("KHR_materials_variants", j.get("extensionsUsed", []))
        self.assertEqual([v["name"] for v in j["extensions"]["KHR_materials_variants"]["variants"]], VARIANTS)
        levels = self.level_primitives(j)
        self.assertGreaterEqual(len(levels), 3)
        for k, (node, prim) in enumerate(levels):
            with self.subTest(level=k):
                mappings = prim["extensions"]["KHR_materials_variants"]["mappings"]
                mapped = sorted(v for m in mappings for v in m["variants"])
                self.assertEqual(mapped, list(range(len(VARIANTS))), "every variant mapped once")
                for m in mappings:
                    self.assertLess(m["material"], len(j["materials"]))
                material = {v: m["material"] for m in mappings for v in m["variants"]}
                self.assertEqual(material[VARIANTS.index("classic")], prim["material"])
                if k == 0:  # the others change a part LOD0 shows: each its own material
                    own = {material[VARIANTS.index(v)] for v in CHANGING}
                    self.assertEqual(len(own), len(CHANGING))
                    self.assertNotIn(prim["material"], own)
                    for v in CHANGING:
                        self.assertEqual(j["materials"][material[VARIANTS.index(v)]]["name"], "LOD0_" + v)

    def test_lodbake_output(self):
        self.assertNotIn("is not carried", self.stderr)
        self.check_chain(self.gltf)

    def test_identical_images_are_shared(self):
        # The "gold" variant changes the pedestal only: where the ball's texels dominate a page,
        # images may still differ; but no two images of the file may hold the same bytes.
        g = lt.Gltf(self.out)
        seen = {}
        for i, img in enumerate(self.gltf["images"]):
            view = self.gltf["bufferViews"][img["bufferView"]]
            data = g.bin[view.get("byteOffset", 0):view.get("byteOffset", 0) + view["byteLength"]]
            self.assertNotIn(data, seen, "images %s and %d hold the same bytes" % (seen.get(data), i))
            seen[data] = i

    def test_report_lists_variants(self):
        levels = pack_levels(self.report)
        for k, level in enumerate(levels):
            with self.subTest(level=k):
                self.assertEqual([v["name"] for v in level["variants"]], VARIANTS)
                for v in level["variants"]:
                    self.assertIn("baseColor", " ".join(v["channels"]) + " baseColor" * (v["material"] < 0))
        self.assertEqual([v["material"] >= 0 for v in levels[0]["variants"]], [v in CHANGING for v in VARIANTS])
        for level in levels:
            self.assertEqual(level["variants"][VARIANTS.index("classic")]["material"], -1)
        try:
            import test_report_schemas as schemas
        except ImportError:
            return
        if schemas.jsonschema is None:
            self.skipTest("python3-jsonschema is missing: the report is not checked against docs/schemas")
        self.assertEqual(schemas.errors(schemas.load_schemas(), "lodbake", self.report), [])

    def test_separate_tools(self):
        d = lt.work_dir("variants_tools")
        mr, uv, tex, lod = (os.path.join(d, "variants." + e) for e in ("mr.glb", "uv.glb", "tex.glb", "lod.glb"))
        lt.run([lt.tool("simplify"), "-i", self.src, "-o", mr, "--ratio", "0.5,0.1", "--quiet"])
        for path in (mr,):  # the intermediates keep the original's mappings and the names
            j = lt.Gltf(path).json
            self.assertEqual([v["name"] for v in j["extensions"]["KHR_materials_variants"]["variants"]], VARIANTS)
        lt.run([lt.tool("parameterize"), "-i", mr, "-o", uv, "--size", "256", "--quiet"])
        lt.run([lt.tool("texture-refine"), "-i", uv, "-o", tex, "--size", "256", "--sizes", "128,256", "--quiet"])
        lt.run([lt.tool("pack"), "-i", tex, "-o", lod, "--max-size", "512", "--quiet"])
        self.check_chain(lt.Gltf(lod).json)
        lt.assert_no_validator_errors(self, [mr, lod])

    def test_validator(self):
        lt.assert_no_validator_errors(self, [self.src, self.out])

    def test_threejs_variants(self):
        lt.require_browser_chain(("three", "playwright-core"))
        d = lt.work_dir("variants_three")
        groups = [{"reference": self.src, "out": os.path.join(d, "default"),
                   "candidates": ["%s#node=0" % self.out] + ["%s#variant=%s" % (self.src, v) for v in VARIANTS]}]
        for v in VARIANTS:
            groups.append({"reference": "%s#variant=%s" % (self.src, v), "out": os.path.join(d, v),
                           "candidates": ["%s#node=0&variant=%s" % (self.out, v)]})
        batch, out_json = os.path.join(d, "batch.json"), os.path.join(d, "results.json")
        with open(batch, "w") as f:
            json.dump(groups, f, indent=1)
        p = subprocess.run([sys.executable, RENDER, "--batch", batch, "--views", "8", "--size", "256", "--json", out_json],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=1800,
                           env=dict(os.environ, CHROMIUM=lt.CHROMIUM))
        print(p.stdout)
        self.assertEqual(p.returncode, 0, p.stderr[-3000:])
        with open(out_json) as f:
            results = json.load(f)
        lod0 = results[0]["candidates"][0]
        with self.subTest(variant="default"):
            self.assertTrue(lod0["loaded"], lod0["errors"])
            self.assertGreaterEqual(lod0["psnr"], LOD0_PSNR_MIN)
        for v, original in zip(VARIANTS, results[0]["candidates"][1:]):
            with self.subTest(original_variant=v):
                self.assertTrue(original["loaded"], original["errors"])
                if v in CHANGING:
                    self.assertLess(original["psnr"], DIFFERENT_PSNR_MAX, "selecting %s changes nothing" % v)
                else:
                    self.assertEqual(original["psnr"], 100.0, "the default look, mapped explicitly")
        for v, r in zip(VARIANTS, results[1:]):
            c = r["candidates"][0]
            with self.subTest(variant=v):
                self.assertTrue(r["reference"]["loaded"], r["reference"]["errors"])
                self.assertTrue(c["loaded"], c["errors"])
                print("LOD0 variant %-5s PSNR %.2f dB (foreground %.2f), SSIM %.4f" % (v, c["psnr"], c["psnr_fg"], c["ssim"]))
                self.assertGreaterEqual(c["psnr"], LOD0_PSNR_MIN)


if __name__ == "__main__":
    lt.main([Variants])
