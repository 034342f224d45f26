"""CLI tests for pack: simplify -> parameterize -> pack on every generated sample.

Checks the MSFT_lod chain structure (LOD0 node with ids, only LOD0 in the scene, MSFT_lod used
but never required, one more coverage value than ids, decreasing), one mesh / one primitive /
one material per level with NORMAL and TEXCOORD_0, gltf-validator (0 errors, 0 warnings: the
MSFT_lod notice is an info), the report, --draco (decodes back to the same triangle count within
the quantisation error, compare --lod K on MSFT_lod files), --split, --image-format jpeg, --pot,
usage and input errors.
"""
import json
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import lodbake_test as lt  # noqa: E402

SAMPLES = ["hemisphere9", "wall5", "colors", "seamball"]
FAST = ["--max-size", "512", "--samples", "20000", "--quiet"]


def check_fold_free(tc, path, what, report=None):
    """Every level of a written chain has 0 flipped and 0 overlapping UV triangles in its atlas,
    except a LOD0 on the original's texels (its report's sourceTexels) and a tiled level (its
    report's tiling): they keep the original's UVs, mirrored and shared ones included."""
    g = lt.Gltf(path)
    skip = set()
    if report:
        with open(report) as f:
            levels = json.load(f)["levels"]
        if levels[0].get("sourceTexels", {}).get("used"):
            skip.add(0)
        skip |= {k for k, lv in enumerate(levels) if lv.get("tiling", {}).get("tiled")}
    for m in range(len(g.json["meshes"])):
        if m in skip:
            continue
        tris = lt.level_uv_triangles(g, m)
        with tc.subTest(chain=what, mesh=m):
            tc.assertEqual((lt.count_flips(tris), lt.count_overlaps(tris)), (0, 0), "flipped / overlapping UVs")


def check_chain(tc, path, report=None):
    """Structure checks shared with test_pack_assets.py; returns the Gltf."""
    g = lt.Gltf(path)
    j = g.json
    lod = j["nodes"][0]["extensions"]["MSFT_lod"]
    ids = lod["ids"]
    # The level nodes come first; a skinned or animated input's rig (joint nodes, in the scene
    # beside node 0) follows them, and every level node uses its one skin.
    skinned = "skins" in j
    levels = 1 + len(ids)
    tc.assertEqual(ids, list(range(1, levels)))
    scene = j["scenes"][j.get("scene", 0)]["nodes"]
    tc.assertEqual(scene[0], 0)
    # After the levels (and the rig) come the nodes that place the input's lights and cameras,
    # each a root of the scene holding nothing else.
    placed = [k for k, n in enumerate(j["nodes"]) if "camera" in n or "KHR_lights_punctual" in n.get("extensions", {})]
    for k in placed:
        tc.assertIn(k, scene)
        tc.assertNotIn("mesh", j["nodes"][k])
    if not skinned:
        tc.assertEqual(scene, [0] + placed)
        tc.assertEqual(len(j["nodes"]), levels + len(placed))
    nodes = j["nodes"][:levels]
    for n in nodes:
        tc.assertEqual(n.get("skin"), 0 if skinned else None)
    tc.assertIn("MSFT_lod", j["extensionsUsed"])
    tc.assertNotIn("MSFT_lod", j.get("extensionsRequired", []))
    cov = nodes[0]["extras"]["MSFT_screencoverage"]
    tc.assertEqual(len(cov), len(ids) + 1)
    for a, b in zip(cov, cov[1:]):
        tc.assertGreaterEqual(a, b)
    tc.assertGreater(cov[-1], 0)
    tc.assertEqual(len(j["meshes"]), len(nodes))
    tc.assertEqual(len(j["materials"]), len(nodes))
    for i, n in enumerate(nodes):
        prims = j["meshes"][n["mesh"]]["primitives"]
        tc.assertEqual(len(prims), 1, "LOD%d: one draw call" % i)
        tc.assertEqual(prims[0]["material"], i)
        for a in ("POSITION", "NORMAL", "TEXCOORD_0"):
            tc.assertIn(a, prims[0]["attributes"])
        mat = j["materials"][i]
        pbr = mat["pbrMetallicRoughness"]
        # A base colour that varies is baked; one constant over the asset is a factor.
        tc.assertTrue("baseColorTexture" in pbr or "baseColorFactor" in pbr, mat)
        if "normalTexture" in mat:
            tc.assertIn("TANGENT", prims[0]["attributes"])
    if lt.validator_available():
        v = lt.validate(path)
        tc.assertEqual(v["errors"], 0, v)
        tc.assertEqual(v["warnings"], 0, v)
        for m in v["messages"]:
            if m["code"] == "UNSUPPORTED_EXTENSION":  # an info; the validator decodes none of these
                tc.assertTrue(any(e in m["message"] for e in ("MSFT_lod", "KHR_draco_mesh_compression", "EXT_meshopt_compression")), m)
    if report:
        with open(report) as f:
            r = json.load(f)
        tc.assertEqual(len(r["levels"]), len(nodes))
        tris = [lv["triangles"] for lv in r["levels"]]
        tc.assertEqual(tris, [g.mesh_triangle_count(n["mesh"]) for n in nodes])
        for k, lv in enumerate(r["levels"]):
            for key in ("texels", "bytes", "utilisation", "boxUtilisation", "screenCoverage"):
                tc.assertIn(key, lv)
            # A tiled level's page is one period of its material, not charts (tiled_levels.h).
            if not lv.get("tiling", {}).get("tiled"):
                tc.assertGreater(lv["utilisation"], 0)
            # (A LOD0 on the original's texels counts texels that several faces share more than once.)
            if not lv.get("sourceTexels", {}).get("used"):
                tc.assertLessEqual(lv["utilisation"], lv["boxUtilisation"] + 1e-9)
            tc.assertEqual(lv["screenCoverage"], cov[k])
            if k > 0:
                # A level the gross-error stop kept whole (a cube) is the original's surface.
                if lv["triangles"] < r["levels"][0]["triangles"]:
                    tc.assertGreater(lv["deviation"]["hausdorff"], 0)
                # A coarse level never carries more texels than it can show.
                tc.assertLessEqual(lv["texelsPerUnit"], lv["texelLimit"] * 1.0001)
                tc.assertLessEqual(lv["texels"], r["levels"][k - 1]["texels"])
    return g


class PackCli(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        for t in ("simplify", "parameterize", "pack", "make-samples"):
            if not os.path.exists(lt.tool(t)):
                lt.skip(t + " is not built")
        cls.dir = lt.work_dir("pack")
        cls.uv = lt.parameterized_samples(cls.dir, SAMPLES)

    def pack(self, name, out, *extra):
        return lt.pack(self.uv[name], os.path.join(self.dir, out), FAST + list(extra))

    def test_every_sample(self):
        for n in SAMPLES:
            with self.subTest(sample=n):
                out, rep = self.pack(n, n + ".lod.glb")
                check_chain(self, out, rep)

    def test_draco_round_trip(self):
        plain, _ = self.pack("seamball", "ball.lod.glb")
        draco, _ = self.pack("seamball", "ball.draco.glb", "--draco", "--qp", "16")
        g = check_chain(self, draco)
        self.assertIn("KHR_draco_mesh_compression", g.json["extensionsUsed"])
        self.assertIn("KHR_draco_mesh_compression", g.json["extensionsRequired"])
        self.assertLess(os.path.getsize(draco), os.path.getsize(plain))
        for k in range(len(g.json["nodes"])):
            p = lt.run([lt.tool("compare"), plain, draco, "--lod-a", str(k), "--lod", str(k), "--json",
                        "--views", "2", "--resolution", "64", "--samples", "20000", "--max-hausdorff", "0.0005"],
                       check=False)
            self.assertEqual(p.returncode, 0, p.stdout[-2000:] + p.stderr)
            c = json.loads(p.stdout)
            self.assertEqual(c["counts"]["a"]["triangles"], c["counts"]["b"]["triangles"])

    def test_split_manifest(self):
        out, _ = self.pack("hemisphere9", "hemi.glb", "--split")
        with open(os.path.join(self.dir, "hemi.lods.json")) as f:
            m = json.load(f)
        self.assertEqual(len(m["levels"]), 4)
        for lv in m["levels"]:
            f = os.path.join(self.dir, lv["file"])
            g = lt.Gltf(f)
            self.assertEqual(len(g.json["nodes"]), 1)
            self.assertNotIn("extensionsUsed", g.json)
            self.assertEqual(g.mesh_triangle_count(0), lv["triangles"])
            if lt.validator_available():
                v = lt.validate(f)
                self.assertEqual((v["errors"], v["warnings"]), (0, 0), v)
        self.assertFalse(os.path.exists(out))

    def test_jpeg_gltf_external_pot(self):
        out, rep = self.pack("colors", "colors.lod.gltf", "--image-format", "jpeg", "--jpeg-quality", "80",
                             "--external-images", "--pot")
        g = check_chain(self, out, rep)
        for img in g.json["images"]:
            # Normal maps stay lossless PNG; every other page is JPEG.
            self.assertTrue(img["uri"].endswith(".png" if img["name"].endswith("_normal") else ".jpg"), img)
            self.assertTrue(os.path.exists(os.path.join(self.dir, img["uri"])))
        with open(rep) as f:
            r = json.load(f)
        for lv in r["levels"]:
            for side in (lv["width"], lv["height"]):
                self.assertEqual(side & (side - 1), 0, "power of two")

    def test_lod0_density(self):
        # --lod0-density: every level is textured at LOD0's texel limit (for close-up comparisons
        # such as scripts/bench.py quality), so coarse pages are larger than by default, never larger
        # than the finer level's, and the chain stays valid.
        # Both on resampled LOD0 pages: a LOD0 on the original's texels (a smaller page here)
        # holds the coarser pages' texels down in both runs alike.
        _, rep_default = self.pack("seamball", "ball.default.glb", "--no-source-texels")
        out, rep = self.pack("seamball", "ball.dense.glb", "--lod0-density", "--no-source-texels")
        check_chain(self, out, rep)
        with open(rep_default) as f:
            default = json.load(f)["levels"]
        with open(rep) as f:
            r = json.load(f)
        dense = r["levels"]
        self.assertTrue(r["options"]["lod0Density"])
        self.assertEqual(len(dense), len(default))
        for k in range(1, len(dense)):
            self.assertAlmostEqual(dense[k]["texelLimit"], dense[0]["texelLimit"], delta=1e-9 * dense[0]["texelLimit"])
            self.assertLess(default[k]["texelLimit"], dense[k]["texelLimit"])
            self.assertGreaterEqual(dense[k]["texels"], default[k]["texels"])
            self.assertLessEqual(dense[k]["texels"], dense[k - 1]["texels"])

    def test_identical_for_any_threads(self):
        one, _ = self.pack("seamball", "ball.t1.glb", "--threads", "1")
        two, _ = self.pack("seamball", "ball.t2.glb", "--threads", "2")
        with open(one, "rb") as a, open(two, "rb") as b:
            self.assertEqual(a.read(), b.read())

    def test_errors(self):
        p = lt.run([lt.tool("pack"), "-i", "x.glb", "-o", "y.glb", "--bogus"], check=False)
        self.assertEqual(p.returncode, 1)
        p = lt.run([lt.tool("pack"), "-i", "x.glb", "-o", "y.glb", "--pixel-error", "0"], check=False)
        self.assertEqual(p.returncode, 1)
        p = lt.run([lt.tool("pack"), "-i", os.path.join(self.dir, "missing.glb"), "-o", "y.glb"], check=False)
        self.assertEqual(p.returncode, 2)
        # Valid glTF without LODBAKE_multires / without charts: impossible (3).
        p = lt.run([lt.tool("pack"), "-i", os.path.join(self.dir, "colors.glb"), "-o", os.path.join(self.dir, "c.glb")], check=False)
        self.assertEqual(p.returncode, 3, p.stderr)
        p = lt.run([lt.tool("pack"), "-i", os.path.join(self.dir, "colors.mr.glb"), "-o", os.path.join(self.dir, "c.glb")], check=False)
        self.assertEqual(p.returncode, 3, p.stderr)


if __name__ == "__main__":
    lt.main([PackCli])
