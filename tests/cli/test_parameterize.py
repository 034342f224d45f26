"""CLI tests for parameterize: simplify -> parameterize on generated samples."""
import json
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import lodbake_test as lt  # noqa: E402
from lodbake_test import count_flips, count_overlaps, level_uv_triangles  # noqa: E402,F401




class ParameterizeCli(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if not os.path.exists(lt.tool("parameterize")) or not os.path.exists(lt.tool("make-samples")):
            lt.skip("parameterize or make-samples is not built")
        cls.dir = lt.work_dir("parameterize")
        lt.make_samples(cls.dir)
        cls.samples = sorted(f[:-4] for f in os.listdir(cls.dir) if f.endswith(".glb"))

    def chain(self, name, extra=()):
        src = os.path.join(self.dir, name + ".glb")
        mr = os.path.join(self.dir, name + ".mr.glb")
        uv = os.path.join(self.dir, name + ".uv.glb")
        rep = os.path.join(self.dir, name + ".param.json")
        lt.run([lt.tool("simplify"), "-i", src, "-o", mr, "--ratio", "0.5,0.1,0.02"])
        lt.run([lt.tool("parameterize"), "-i", mr, "-o", uv, "--size", "256", "--report", rep] + list(extra))
        with open(rep) as f:
            return uv, json.load(f)

    def check(self, name):
        uv, r = self.chain(name)
        t = r["total"]
        self.assertEqual(t["flips"], 0)
        self.assertEqual(t["overlaps"], 0)
        self.assertGreaterEqual(t["charts"], 1)
        self.assertLessEqual(t["final"]["E"], t["initial"]["E"] + 1e-9)
        self.assertEqual(sum(t["areaRatioHistogram"]), sum(c["faces"] for c in r["charts"]))
        g = lt.Gltf(uv)
        mats = g.json["materials"]
        atlas = len(mats) - 1
        self.assertIn("baseColorTexture", mats[atlas]["pbrMetallicRoughness"])
        # Every level mesh (nodes 1..n) uses only the atlas material.
        for node in g.json["nodes"][1:]:
            for prim in g.json["meshes"][node["mesh"]]["primitives"]:
                self.assertEqual(prim.get("material"), atlas)
                self.assertIn("TEXCOORD_0", prim["attributes"])
        if lt.validator_available():
            self.assertEqual(lt.validate(uv)["errors"], 0)
        # The report checked every level with its final UVs.
        self.assertEqual(len(r["levels"]), 4)
        for lv in r["levels"]:
            self.assertEqual((lv["flips"], lv["overlaps"]), (0, 0), lv)
        # The written file: every level mesh's TEXCOORD_0 has no flipped or overlapping triangle.
        for k, node in enumerate(g.json["nodes"][1:], 1):
            tris = level_uv_triangles(g, node["mesh"])
            self.assertEqual(count_flips(tris), 0, "level %d" % k)
            self.assertEqual(count_overlaps(tris), 0, "level %d" % k)
        # The chart layout travels in the file.
        ext = g.multires()
        ch = ext["charts"]
        faces = ext["original"]["faceCount"]
        self.assertEqual(ch["count"], t["charts"])
        self.assertEqual(ch["material"], atlas)
        self.assertEqual(len(g.accessor(ch["faceChart"])), faces)
        self.assertEqual(len(g.accessor(ch["cornerUV"])), 6 * faces)
        self.assertLess(max(g.accessor(ch["faceChart"])), ch["count"])
        return uv

    def test_surviving_folds_are_warnings(self):
        # Without the island fallback a level of seamball keeps a folded triangle: the chain is still
        # written (exit 0), with one warning line naming the folds, and the report counts them.
        # --allow-level-folds is accepted (deprecated, no effect) and changes no byte.
        src = os.path.join(self.dir, "seamball.glb")
        mr = os.path.join(self.dir, "seamball.folds.mr.glb")
        lt.run([lt.tool("simplify"), "-i", src, "-o", mr, "--ratio", "0.5,0.1,0.02", "--quiet"])
        outs = []
        for extra in ([], ["--allow-level-folds"]):
            uv = os.path.join(self.dir, "seamball.folds%d.uv.glb" % len(outs))
            rep = uv + ".json"
            p = lt.run([lt.tool("parameterize"), "-i", mr, "-o", uv, "--size", "256", "--no-level-islands",
                        "--report", rep] + extra, check=False)
            self.assertEqual(p.returncode, 0, p.stderr)
            with open(rep) as f:
                r = json.load(f)
            folds = r["total"]["levelFlips"] + r["total"]["levelOverlaps"]
            self.assertGreater(folds, 0, "seamball no longer folds without islands: pick another case")
            warnings = [w for w in p.stderr.splitlines() if w.startswith("parameterize warning: the levels keep")]
            self.assertEqual(len(warnings), 1, p.stderr)
            self.assertTrue(any(w.startswith("the levels keep") for w in r["warnings"]), r["warnings"])
            with open(uv, "rb") as f:
                outs.append(f.read())
        self.assertEqual(outs[0], outs[1])

    def test_hemisphere(self):
        self.check("hemisphere9")

    def test_seamball_closed(self):
        # seamball's base region is split (normal cone > 150 deg), so level triangles cross the
        # split; each gets its own island (crossing islands) instead of projected UVs.
        uv = self.check("seamball")
        # The output is itself a valid parameterize input (levels survive the round trip).
        lt.run([lt.tool("parameterize"), "-i", uv, "-o", os.path.join(self.dir, "again.glb"), "--size", "128",
                "--iterations", "0"])

    def fold_free(self, name, src, size="1024"):
        """simplify 0.5,0.1,0.02 -> parameterize WITHOUT --allow-level-folds: exit 0, every level
        0 flipped / 0 overlapping (the tool's own check of the written UVs), validator clean."""
        mr = os.path.join(self.dir, name + ".ff.mr.glb")
        uv = os.path.join(self.dir, name + ".ff.uv.glb")
        rep = os.path.join(self.dir, name + ".ff.json")
        lt.run([lt.tool("simplify"), "-i", src, "-o", mr, "--ratio", "0.5,0.1,0.02", "--quiet"])
        p = lt.run([lt.tool("parameterize"), "-i", mr, "-o", uv, "--size", size, "--quiet", "--report", rep],
                   check=False)
        self.assertEqual(p.returncode, 0, "%s: %s" % (name, p.stderr))
        with open(rep) as f:
            r = json.load(f)
        self.assertEqual(len(r["levels"]), 4, name)
        for lv in r["levels"]:
            self.assertEqual((lv["flips"], lv["overlaps"]), (0, 0), "%s level %d" % (name, lv["level"]))
        self.assertEqual(r["total"]["islandTriangles"], sum(lv["islandTriangles"] for lv in r["levels"]))
        print("%s: islands %d (level triangles %s), parameterize %.2f s" % (
            name, r["total"]["islands"], [lv["islandTriangles"] for lv in r["levels"][1:]], r["time"]["parameterize"]))
        if lt.validator_available():
            self.assertEqual(lt.validate(uv)["errors"], 0, name)
        return uv, r

    def test_every_sample_fold_free(self):
        # Every generated sample is fold-free at every level; the written level UVs are re-checked here.
        self.assertGreaterEqual(len(self.samples), 4)
        for name in self.samples:
            with self.subTest(sample=name):
                uv, _ = self.fold_free(name, os.path.join(self.dir, name + ".glb"), size="256")
                g = lt.Gltf(uv)
                # Level nodes carry a mesh; a skinned sample's rig adds joint nodes without one.
                level_nodes = [n for n in g.json["nodes"] if "mesh" in n]
                for k, node in enumerate(level_nodes[1:], 1):
                    tris = level_uv_triangles(g, node["mesh"])
                    self.assertEqual(count_flips(tris), 0, "%s level %d" % (name, k))
                    self.assertEqual(count_overlaps(tris), 0, "%s level %d" % (name, k))

    def test_every_asset_fold_free(self):
        # Every asset of ../shared/assets is fold-free at every level. StanfordBunny (69k triangles) is
        # the slow one; LODBAKE_SKIP_SLOW=1 leaves it out.
        if not os.path.isdir(lt.ASSETS):
            self.skipTest("../shared/assets is absent")
        for name, src in sorted(lt.require_assets().items()):
            if name == "StanfordBunny" and os.environ.get("LODBAKE_SKIP_SLOW"):
                continue
            with self.subTest(asset=name):
                self.fold_free(name, src)

    def test_texture_deviation_beta(self):
        # The thesis's claim: beta < 1 (E_poly on) lowers the coarsest level's texture deviation.
        _, default = self.chain("hemisphere9")
        _, pixel_only = self.chain("hemisphere9", ["--beta", "1"])
        d, p = default["textureDeviation"], pixel_only["textureDeviation"]
        self.assertGreater(d["samples"], 0)
        self.assertLess(d["meanRelative"], p["meanRelative"])
        self.assertLess(d["maxRelative"], p["maxRelative"])

    def test_texture_deviation_beta_avocado(self):
        # The same claim on a real scanned asset, at its 2% level (13 triangles).
        if not os.path.isdir(lt.ASSETS):
            self.skipTest("../shared/assets is absent")
        src = lt.require_assets()["Avocado"]
        mr = os.path.join(self.dir, "Avocado.mr.glb")
        lt.run([lt.tool("simplify"), "-i", src, "-o", mr, "--ratio", "0.5,0.1,0.02", "--quiet"])
        dev = {}
        for beta in ("0.7", "1"):
            rep = os.path.join(self.dir, "Avocado.beta%s.json" % beta)
            lt.run([lt.tool("parameterize"), "-i", mr, "-o", os.path.join(self.dir, "Avocado.uv.glb"),
                    "--beta", beta, "--quiet", "--report", rep])
            with open(rep) as f:
                dev[beta] = json.load(f)["textureDeviation"]
            print("Avocado 2%%, beta %s: texture deviation mean %.5f / max %.5f of the diagonal, rms %.6f" % (
                beta, dev[beta]["meanRelative"], dev[beta]["maxRelative"], dev[beta]["rms"]))
        self.assertEqual(dev["0.7"]["level"], 3)
        self.assertLess(dev["0.7"]["meanRelative"], dev["1"]["meanRelative"])
        self.assertLess(dev["0.7"]["rms"], dev["1"]["rms"])

    def test_baked_beats_original_uvs_at_2_percent(self):
        # wall5's 2% level rendered with the baked atlas vs with the original UVs and textures.
        src = os.path.join(self.dir, "wall5.glb")
        mr = os.path.join(self.dir, "wall5.mr.glb")
        uv, _ = self.chain("wall5", ["--size", "1024"])
        psnr = {}
        for name, path in (("baked", uv), ("original", mr)):
            p = lt.run([lt.tool("compare"), src, path, "--lod", "3", "--no-geometry", "--json"])
            psnr[name] = json.loads(p.stdout)["images"]["baseColor"]["psnr"]
        self.assertGreater(psnr["baked"], psnr["original"], psnr)

    def test_baked_beats_original_uvs_duck(self):
        # Duck's 2% level with the baked atlas vs with the original UVs and texture.
        if not os.path.isdir(lt.ASSETS):
            self.skipTest("../shared/assets is absent")
        src = lt.require_assets()["Duck"]
        mr = os.path.join(self.dir, "Duck.mr.glb")
        uv = os.path.join(self.dir, "Duck.uv.glb")
        lt.run([lt.tool("simplify"), "-i", src, "-o", mr, "--ratio", "0.5,0.1,0.02", "--quiet"])
        lt.run([lt.tool("parameterize"), "-i", mr, "-o", uv, "--quiet"])
        psnr = {}
        for name, path in (("baked", uv), ("original", mr)):
            p = lt.run([lt.tool("compare"), src, path, "--lod", "3", "--no-geometry", "--json"])
            psnr[name] = json.loads(p.stdout)["images"]["baseColor"]["psnr"]
        print("Duck 2%%: base-colour PSNR baked %.2f dB, original UVs %.2f dB" % (psnr["baked"], psnr["original"]))
        self.assertGreater(psnr["baked"], psnr["original"], psnr)

    def test_usage_errors(self):
        p = lt.run([lt.tool("parameterize"), "-i", "x.glb", "-o", "y.glb", "--beta", "2"], check=False)
        self.assertEqual(p.returncode, 1)
        p = lt.run([lt.tool("parameterize"), "-i", "x.glb", "-o", "y.glb", "--bogus"], check=False)
        self.assertEqual(p.returncode, 1)

    def test_input_without_multires(self):
        src = os.path.join(self.dir, "colors.glb")
        p = lt.run([lt.tool("parameterize"), "-i", src, "-o", os.path.join(self.dir, "c.uv.glb")], check=False)
        self.assertEqual(p.returncode, 3, p.stderr)


if __name__ == "__main__":
    lt.main([ParameterizeCli])
