"""KHR_materials_* extensions survive the whole chain (`lodbake`, issue 30).

`lodbake -i ASSET -o out.glb --ratio 0.5,0.1` on the `materials` sample (sheen cloth, clearcoat
paint, transmission + volume glass, specular colour, and a floor without extensions) and on the
shared SheenCloth, ClearCoatCarPaint and TransmissionTest assets (skipped when ../shared/assets
is absent). Per run: no "is not carried" warning; every level's material has the extensions the
input uses; channels that vary over the input are textures (the sample's, whose ground truth the
test knows); the report lists those channels; glTF-Validator finds no error.
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
        j = lt.Gltf(path).json
        for name in expected:
            self.assertIn(name, j.get("extensionsUsed", []))
        for i, node in enumerate(j["nodes"]):
            if "mesh" not in node:
                continue
            with self.subTest(level=i):
                mat = j["materials"][j["meshes"][node["mesh"]]["primitives"][0]["material"]]
                for name in expected:
                    self.assertIn(name, mat.get("extensions", {}), "level %d lacks %s" % (i, name))
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
        # Ground truth of the sample: every extension covers only part of the surface, so each
        # varying channel is a texture; the glass's properties are the only ones (no warning).
        mat = j["materials"][0]["extensions"]
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
