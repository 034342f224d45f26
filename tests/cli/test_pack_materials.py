"""Every material channel survives the chain: simplify -> parameterize -> pack on `pbrscene`.

The sample has a dome with base colour, metallic-roughness, occlusion (TEXCOORD_1), emissive and
normal maps, a plate whose bumps exist only in its normal map, and an alpha-masked double-sided
panel. Checks, per level of the chain: one material with base colour + alpha (RGBA), one ORM
texture serving both metallicRoughnessTexture and occlusionTexture, emissive and normal maps,
TANGENT with unit xyz and w = +-1, MASK with the input's cutoff, single-sided with back faces
for the double-sided panel; gltf-validator finds no error; compare's lit PBR render scores every
level at least as high as the same level baked base-colour-only (--base-color-only); a texture
constant over the asset is a factor (colors: no ORM, emissive or normal texture on LOD0).
"""
import json
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import lodbake_test as lt  # noqa: E402

FAST = ["--max-size", "512", "--samples", "20000", "--lod0-density", "--quiet"]


class PackMaterials(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        lt.require_tools("simplify", "parameterize", "pack", "compare", "make-samples")
        cls.dir = lt.work_dir("pack_materials")
        cls.uv = lt.parameterized_samples(cls.dir, ("pbrscene", "colors"))
        cls.full, cls.full_report = cls.pack("pbrscene", "pbrscene.lod.glb")
        cls.bc, _ = cls.pack("pbrscene", "pbrscene.bc.glb", "--base-color-only")

    @classmethod
    def pack(cls, name, out, *extra):
        return lt.pack(cls.uv[name], os.path.join(cls.dir, out), FAST + list(extra))

    def test_every_channel_on_every_level(self):
        g = lt.Gltf(self.full)
        j = g.json
        for i, node in enumerate(j["nodes"]):
            with self.subTest(lod=i):
                mat = j["materials"][i]
                pbr = mat["pbrMetallicRoughness"]
                for key in ("baseColorTexture", "metallicRoughnessTexture"):
                    self.assertIn(key, pbr)
                for key in ("occlusionTexture", "emissiveTexture", "normalTexture"):
                    self.assertIn(key, mat)
                self.assertEqual(pbr["metallicRoughnessTexture"]["index"], mat["occlusionTexture"]["index"], "one ORM texture")
                self.assertEqual(mat["alphaMode"], "MASK")
                self.assertAlmostEqual(mat["alphaCutoff"], 0.5)
                self.assertNotIn("doubleSided", mat, "mixed sidedness: back faces, not a double-sided material")
                prim = j["meshes"][node["mesh"]]["primitives"][0]
                tangents = g.accessor(prim["attributes"]["TANGENT"])
                for v in range(0, len(tangents), 4):
                    x, y, z, w = tangents[v:v + 4]
                    self.assertAlmostEqual(math.sqrt(x * x + y * y + z * z), 1, places=3)
                    self.assertIn(w, (-1.0, 1.0))
        with open(self.full_report) as f:
            r = json.load(f)
        self.assertIn("baseColorAlpha", r["levels"][0]["channels"])
        self.assertTrue(any("double-sided" in w for w in r["warnings"]), r["warnings"])
        if lt.validator_available():
            v = lt.validate(self.full)
            self.assertEqual(v["errors"], 0, v)

    def test_lit_render_beats_base_colour_only(self):
        levels = len(lt.Gltf(self.full).json["nodes"])
        src = os.path.join(self.dir, "pbrscene.glb")
        for k in range(levels):
            with self.subTest(lod=k):
                scores = []
                for chain in (self.full, self.bc):
                    p = lt.run([lt.tool("compare"), src, chain, "--lod", str(k), "--json", "--no-geometry", "--views", "6"])
                    scores.append(json.loads(p.stdout)["images"]["pbr"]["psnr"])
                print("pbrscene LOD%d pbr PSNR: every channel %.2f dB, base colour only %.2f dB" % (k, scores[0], scores[1]))
                self.assertGreater(scores[0], scores[1])

    def test_constant_channels_are_factors(self):
        out, _ = self.pack("colors", "colors.lod.glb")
        mat = lt.Gltf(out).json["materials"][0]
        self.assertIn("baseColorTexture", mat["pbrMetallicRoughness"])  # six colours: a texture
        self.assertNotIn("metallicRoughnessTexture", mat["pbrMetallicRoughness"])
        self.assertAlmostEqual(mat["pbrMetallicRoughness"]["roughnessFactor"], 0.6)
        self.assertAlmostEqual(mat["pbrMetallicRoughness"]["metallicFactor"], 0)
        for key in ("occlusionTexture", "emissiveTexture", "normalTexture"):
            self.assertNotIn(key, mat)

    def test_usage_errors(self):
        p = lt.run([lt.tool("pack"), "-i", self.uv["colors"], "-o", os.path.join(self.dir, "x.glb"), "--normal-maps", "sometimes"],
                   check=False)
        self.assertEqual(p.returncode, 1)
        self.assertIn("--normal-maps", p.stderr)


if __name__ == "__main__":
    lt.main([PackMaterials])
