"""KHR_materials_* extensions survive the whole chain (`lodbake`, issue 30).

`lodbake -i ASSET -o out.glb --ratio 0.5,0.1` on the `materials` sample (sheen cloth, clearcoat
paint, transmission + volume glass, specular colour, and a floor without extensions) and on the
shared SheenCloth, ClearCoatCarPaint and TransmissionTest assets (skipped when ../shared/assets
is absent). Per run: no "is not carried" warning; every level's material has the extensions the
input uses; channels that vary over the input are textures (the sample's, whose ground truth the
test knows); the report lists those channels; glTF-Validator finds no error. Every level draws
the sample's glass as its own primitive, the only one whose material transmits, so that viewers
refract the rest through it; with the glass at another ior too, that part's material has the
glass's exact ior, and --max-draws 1 merges both parts into one with a warning.
"""
import json
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import lodbake_test as lt  # noqa: E402

FLAGS = ["--ratio", "0.5,0.1", "--max-size", "256", "--quiet"]

SHARED = {
    "SheenCloth": ("SheenCloth/SheenCloth.gltf", {"KHR_materials_sheen"}),
    "ClearCoatCarPaint": ("ClearCoatCarPaint/ClearCoatCarPaint.glb", {"KHR_materials_clearcoat"}),
    "TransmissionTest": ("TransmissionTest/TransmissionTest.glb", {"KHR_materials_transmission"}),
}


def chain(src, out):
    """Runs lodbake on src; returns (out, stderr, report)."""
    rep = out + ".json"
    p = lt.run([lt.tool("lodbake"), "-i", src, "-o", out, "--report", rep] + FLAGS)
    with open(rep) as f:
        return out, p.stderr, json.load(f)


def pack_levels(report):
    """The per-level entries of the pack stage in lodbake's report."""
    if "levels" in report:
        return report["levels"]
    for stage in report.get("stages", []):
        if stage.get("tool") == "pack":
            return stage["levels"]
    raise AssertionError("no pack levels in the report")


class MaterialExtensions(unittest.TestCase):
    def check_extensions(self, path, expected):
        """Every level's materials together carry `expected`."""
        j = lt.Gltf(path).json
        for name in expected:
            self.assertIn(name, j.get("extensionsUsed", []))
        for i, node in enumerate(j["nodes"]):
            if "mesh" not in node:
                continue
            with self.subTest(level=i):
                carried = set()
                for prim in j["meshes"][node["mesh"]]["primitives"]:
                    carried |= set(j["materials"][prim["material"]].get("extensions", {}))
                for name in expected:
                    self.assertIn(name, carried, "level %d lacks %s" % (i, name))
        return j

    def test_sample(self):
        lt.require_tools("lodbake", "make-samples")
        d = lt.work_dir("material_extensions_sample")
        lt.make_samples(d)
        out, err, report = chain(os.path.join(d, "materials.glb"), os.path.join(d, "materials.lod.glb"))
        self.assertNotIn("is not carried", err)
        expected = {"KHR_materials_sheen", "KHR_materials_clearcoat", "KHR_materials_transmission", "KHR_materials_volume",
                    "KHR_materials_specular", "KHR_materials_ior"}
        j = self.check_extensions(out, expected)
        # The glass is the only part that transmits: it is drawn on its own, and the other part's
        # material (same pages) drops transmission and volume, so viewers refract it.
        levels = pack_levels(report)
        for k, node in enumerate(n for n in j["nodes"] if "mesh" in n):
            with self.subTest(level=k):
                prims = j["meshes"][node["mesh"]]["primitives"]
                self.assertEqual(len(prims), 2)
                exts = [j["materials"][p["material"]].get("extensions", {}) for p in prims]
                self.assertEqual(sorted("KHR_materials_transmission" in e for e in exts), [False, True])
                solid = next(e for e in exts if "KHR_materials_transmission" not in e)
                self.assertNotIn("KHR_materials_volume", solid)
                self.assertIn("KHR_materials_sheen", solid)
                self.assertEqual(levels[k]["drawCalls"], 2)
                self.assertEqual(levels[k]["splitBy"], ["transmission"])
        # Ground truth of the sample: every extension covers only part of the surface, so each
        # varying channel is a texture; the glass's properties are the only ones (no warning).
        lod0 = j["meshes"][j["nodes"][next(i for i, n in enumerate(j["nodes"]) if "mesh" in n)]["mesh"]]["primitives"]
        mat = next(e for e in (j["materials"][p["material"]]["extensions"] for p in lod0) if "KHR_materials_transmission" in e)
        self.assertIn("sheenColorTexture", mat["KHR_materials_sheen"])
        # Roughness matters only under sheen / a coat: the cloth's and the paint's, as factors.
        self.assertNotIn("sheenRoughnessTexture", mat["KHR_materials_sheen"])
        self.assertAlmostEqual(mat["KHR_materials_sheen"]["sheenRoughnessFactor"], 0.5)
        self.assertNotIn("clearcoatRoughnessTexture", mat["KHR_materials_clearcoat"])
        self.assertAlmostEqual(mat["KHR_materials_clearcoat"]["clearcoatRoughnessFactor"], 0.05)
        self.assertIn("clearcoatTexture", mat["KHR_materials_clearcoat"])
        self.assertIn("transmissionTexture", mat["KHR_materials_transmission"])
        self.assertIn("thicknessTexture", mat["KHR_materials_volume"])
        self.assertAlmostEqual(mat["KHR_materials_volume"]["thicknessFactor"], 0.8)
        self.assertAlmostEqual(mat["KHR_materials_volume"]["attenuationDistance"], 0.5)
        self.assertAlmostEqual(mat["KHR_materials_ior"]["ior"], 1.5)
        self.assertIn("specularColorTexture", mat["KHR_materials_specular"])
        self.assertNotIn("specularTexture", mat["KHR_materials_specular"], "specular 1 everywhere: a factor")
        channels = pack_levels(report)[0]["channels"]
        for c in ("clearcoat", "sheenColor", "transmission", "thickness", "specularColor"):
            self.assertIn(c, channels)
        lt.assert_no_validator_errors(self, [out])

    def test_disagreeing_ior_splits_the_draws(self):
        """The sample with its glass at ior 1.33 (the rest 1.5): every level is two primitives on the
        same pages and vertices, their materials carrying the inputs' exact iors; --max-draws 1
        gives one primitive with the area-weighted ior and a warning naming the property."""
        lt.require_tools("lodbake", "make-samples")
        d = lt.work_dir("material_extensions_draws")
        lt.make_samples(d)
        with open(os.path.join(d, "materials.glb"), "rb") as f:
            glb = f.read()

        def water_glass(doc):
            for m in doc["materials"]:
                if m.get("name") == "glass":
                    m["extensions"]["KHR_materials_ior"]["ior"] = 1.33
        src = os.path.join(d, "water.glb")
        with open(src, "wb") as f:
            f.write(lt.glb_with_json(glb, water_glass))
        flags = ["--ratio", "0.1", "--max-size", "128", "--quiet"]
        out, rep = os.path.join(d, "water.lod.glb"), os.path.join(d, "water.json")
        lt.run([lt.tool("lodbake"), "-i", src, "-o", out, "--report", rep] + flags)
        j = lt.Gltf(out).json
        with open(rep) as f:
            levels = pack_levels(json.load(f))
        for k, node in enumerate(n for n in j["nodes"] if "mesh" in n):
            with self.subTest(level=k):
                prims = j["meshes"][node["mesh"]]["primitives"]
                self.assertEqual(len(prims), 2)
                self.assertEqual(prims[0]["attributes"], prims[1]["attributes"], "one vertex set")
                mats = [j["materials"][p["material"]] for p in prims]
                glass = next(m for m in mats if "KHR_materials_transmission" in m["extensions"])
                self.assertEqual(glass["extensions"]["KHR_materials_ior"]["ior"], 1.33)
                self.assertEqual(sorted(m["extensions"]["KHR_materials_ior"]["ior"] for m in mats), [1.33, 1.5])
                for key in ("baseColorTexture",):
                    self.assertEqual(mats[0]["pbrMetallicRoughness"][key], mats[1]["pbrMetallicRoughness"][key], "one set of pages")
                self.assertEqual(levels[k]["drawCalls"], 2)
                self.assertEqual(levels[k]["splitBy"], ["ior", "transmission"])
        one, rep1 = os.path.join(d, "water.one.glb"), os.path.join(d, "water.one.json")
        lt.run([lt.tool("lodbake"), "-i", src, "-o", one, "--report", rep1, "--max-draws", "1"] + flags)
        j1 = lt.Gltf(one).json
        for node in (n for n in j1["nodes"] if "mesh" in n):
            prims = j1["meshes"][node["mesh"]]["primitives"]
            self.assertEqual(len(prims), 1)
            ior = j1["materials"][prims[0]["material"]]["extensions"]["KHR_materials_ior"]["ior"]
            self.assertTrue(1.33 < ior < 1.5, ior)
        with open(rep1) as f:
            report1 = json.load(f)
        warnings = report1.get("warnings", []) + [w for s in report1.get("stages", []) for w in s.get("warnings", [])]
        self.assertTrue(any("materials disagree on KHR_materials_ior ior (spread 0.17)" in w for w in warnings), warnings)
        self.assertTrue(any("transmissive and solid parts" in w for w in warnings), warnings)
        self.assertTrue(all(l["drawCalls"] == 1 and "splitBy" not in l for l in pack_levels(report1)))
        lt.assert_no_validator_errors(self, [out, one])

    def test_variant_ior_splits_the_draws(self):
        """The variants sample with its gold pedestal at ior 1.8: the default materials agree, the
        "gold" variant does not, so every level is two primitives and each maps "gold" to a
        material with its part's exact ior (ball 1.5, pedestal 1.8)."""
        lt.require_tools("lodbake", "make-samples")
        d = lt.work_dir("material_extensions_variant_draws")
        lt.make_samples(d)
        with open(os.path.join(d, "variants.glb"), "rb") as f:
            glb = f.read()

        def gold_ior(doc):
            for m in doc["materials"]:
                if m.get("name") == "gold":
                    m.setdefault("extensions", {})["KHR_materials_ior"] = {"ior": 1.8}
            doc["extensionsUsed"] = sorted(set(doc.get("extensionsUsed", []) + ["KHR_materials_ior"]))
        src, out = os.path.join(d, "gold.glb"), os.path.join(d, "gold.lod.glb")
        with open(src, "wb") as f:
            f.write(lt.glb_with_json(glb, gold_ior))
        lt.run([lt.tool("lodbake"), "-i", src, "-o", out, "--ratio", "0.5", "--max-size", "128", "--quiet"])
        j = lt.Gltf(out).json
        gold = [v["name"] for v in j["extensions"]["KHR_materials_variants"]["variants"]].index("gold")
        for node in (n for n in j["nodes"] if "mesh" in n):
            prims = j["meshes"][node["mesh"]]["primitives"]
            self.assertEqual(len(prims), 2)
            iors = []
            for p in prims:
                m = next(m["material"] for m in p["extensions"]["KHR_materials_variants"]["mappings"] if gold in m["variants"])
                iors.append(j["materials"][m].get("extensions", {}).get("KHR_materials_ior", {}).get("ior", 1.5))
            self.assertEqual(sorted(iors), [1.5, 1.8])
        lt.assert_no_validator_errors(self, [out])

    def test_shared_assets(self):
        lt.require_tools("lodbake")
        if not os.path.isdir(lt.ASSETS):
            self.skipTest("../shared/assets is absent: SheenCloth, ClearCoatCarPaint and TransmissionTest cannot be run")
        d = lt.work_dir("material_extensions_assets")
        outs = []
        for name, (rel, expected) in SHARED.items():
            with self.subTest(asset=name):
                out, err, _ = chain(os.path.join(lt.ASSETS, rel), os.path.join(d, name + ".lod.glb"))
                # Other content may still be named (TransmissionTest's root KHR_xmp), never a material extension.
                self.assertEqual([l for l in err.splitlines() if "is not carried" in l and "KHR_materials" in l], [])
                self.check_extensions(out, expected)
                outs.append(out)
        lt.assert_no_validator_errors(self, outs)


if __name__ == "__main__":
    lt.main([MaterialExtensions])
