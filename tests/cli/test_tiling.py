"""A repeating material keeps its tiling (pack, lib/src/lod/tiled_levels.h).

`lodbake --ratio 0.5,0.1,0.02` on the make-samples tiles sheet (one woven material whose 64 x 64
base colour and normal map repeat 8 x 8 through KHR_texture_transform). Every level's textures
are one period of the material (64 x 64), sampled with REPEAT and shared by the levels; its UVs
are the original's texture coordinates (spanning 8 tiles); the report says each level is tiled.
LOD0 renders as the original: compare's base colour and PBR images (its normal map decoded in
the frames viewers derive from the transformed UVs) and three.js (lit, every channel) at >= 35 dB. glTF-Validator finds no error, also with --draco and --meshopt --quantize."""
import json
import os
import subprocess
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import lodbake_test as lt  # noqa: E402

RENDER = os.path.join(lt.SOURCE, "scripts/render_three.py")
RATIOS = "0.5,0.1,0.02"
LOD0_FLOOR_DB = 35
REPEAT = 10497
TILE = 64


class Tiling(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        lt.require_tools("lodbake", "make-samples", "compare", "pack")
        cls.dir = lt.work_dir("tiling")
        cls.src = os.path.join(lt.make_samples(os.path.join(cls.dir, "samples")), "tiles.glb")
        cls.out, rep = os.path.join(cls.dir, "tiles.lod.glb"), os.path.join(cls.dir, "tiles.json")
        inter = os.path.join(cls.dir, "inter")
        os.makedirs(inter, exist_ok=True)
        lt.run([lt.tool("lodbake"), "-i", cls.src, "-o", cls.out, "--ratio", RATIOS, "--report", rep, "-q",
                "--keep-intermediates", inter])
        with open(rep) as f:
            cls.report = json.load(f)["stages"][3]  # pack's
        cls.tex = os.path.join(inter, "tiles.tex.glb")
        cls.g = lt.Gltf(cls.out)

    def level_meshes(self):
        nodes = self.g.json["nodes"]
        ids = [0] + nodes[0].get("extensions", {}).get("MSFT_lod", {}).get("ids", [])
        return [nodes[i]["mesh"] for i in ids]

    def test_report_says_tiled(self):
        self.assertEqual(len(self.report["levels"]), 4)
        for level in self.report["levels"]:
            with self.subTest(lod=level["lod"]):
                self.assertTrue(level["tiling"]["tiled"], level["tiling"])
                self.assertEqual((level["width"], level["height"]), (TILE, TILE))
                self.assertAlmostEqual(level["tiling"]["span"], 8)

    def test_pages_repeat_and_are_tile_sized(self):
        doc = self.g.json
        used = set()
        for mesh in self.level_meshes():
            for prim in doc["meshes"][mesh]["primitives"]:
                mat = doc["materials"][prim["material"]]
                refs = [mat["pbrMetallicRoughness"]["baseColorTexture"], mat["normalTexture"]]
                for ref in refs:
                    tex = doc["textures"][ref["index"]]
                    sampler = doc["samplers"][tex["sampler"]]
                    self.assertEqual((sampler["wrapS"], sampler["wrapT"]), (REPEAT, REPEAT))
                    used.add(tex["source"])
                uv = self.g.accessor(prim["attributes"]["TEXCOORD_0"])
                self.assertGreater(max(abs(x) for x in uv), 4, "UVs span the tiles")
        self.assertEqual(len(used), 2, "every level shares the tile's two images")
        for i in used:
            img = doc["images"][i]
            view = doc["bufferViews"][img["bufferView"]]
            png = self.g.bin[view.get("byteOffset", 0): view.get("byteOffset", 0) + view["byteLength"]]
            self.assertEqual(png[:8], b"\x89PNG\r\n\x1a\n")
            self.assertEqual((int.from_bytes(png[16:20], "big"), int.from_bytes(png[20:24], "big")), (TILE, TILE))

    def test_lod0_compare_as_the_original(self):
        p = lt.run([lt.tool("compare"), self.src, self.out, "--lod", "0", "--samples", "0", "--json"], check=False)
        self.assertIn(p.returncode, (0, 1), p.stderr)
        for image in ("baseColor", "pbr"):
            psnr = json.loads(p.stdout)["images"][image]["psnr"]
            self.assertGreaterEqual(psnr, LOD0_FLOOR_DB, "compare's %s image of LOD0: %.2f dB" % (image, psnr))

    def test_lod0_three_js(self):
        lt.require_browser_chain(("three", "playwright-core"))
        out_json = os.path.join(self.dir, "three.json")
        p = subprocess.run([sys.executable, RENDER, "--reference", self.src, self.out + "#node=0", "--views", "8", "--size", "256",
                            "--out", os.path.join(self.dir, "renders"), "--json", out_json],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=600,
                           env=dict(os.environ, CHROMIUM=lt.CHROMIUM))
        if p.returncode != 0 and not os.path.exists(out_json):
            raise AssertionError("render_three.py failed (%d): %s" % (p.returncode, p.stderr[-3000:]))
        with open(out_json) as f:
            psnr = json.load(f)["candidates"][0]["psnr"]
        print("three.js LOD0 against the original: %.2f dB" % psnr)
        self.assertGreaterEqual(psnr, LOD0_FLOOR_DB, "three.js LOD0: %.2f dB" % psnr)

    def test_validator_and_compressed(self):
        files = [self.out]
        for name, flags in (("draco", ["--draco"]), ("meshopt", ["--meshopt", "--quantize"])):
            path = os.path.join(self.dir, "tiles.%s.glb" % name)
            lt.run([lt.tool("pack"), "-i", self.tex, "-o", path, "-q"] + flags)
            files.append(path)
        lt.assert_no_validator_errors(self, files)


if __name__ == "__main__":
    lt.main([Tiling])
