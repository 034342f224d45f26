"""Skins, rigid node animation and their animations kept on every level of the chain.

On simple_skin (assimp-testmodels), the make-samples walker and CesiumMilkTruck (../shared/assets,
skipped when absent): simplify -> parameterize -> texture-refine -> pack exits 0, glTF-Validator
reports no error, every level node uses the one skin with JOINTS_0/WEIGHTS_0 and the animations are
written once; reading an intermediate back keeps the rig (parameterize's output carries the same
skin and keys as simplify's); compare posed at the start, middle and end of the animation gives
LOD0 a silhouette IoU >= 0.99 and every coarser level a posed Hausdorff distance within the
deviation pack measured (the largest over the bind pose and the poses simplify samples), up to the
sampling's precision. simplify reports how many poses it sampled, none with --pose-samples 0.
pack --draco compresses skinned levels with JOINTS_0/WEIGHTS_0 as Draco attributes and they still
pose like the original.

AnimatedMorphCube (morph targets and a weights animation): every level of the intermediates and
the chain carries the two targets, the default weights and a weights channel per level node (one
shared sampler); posed at three times LOD0 has IoU >= 0.99 and coarser levels stay within the
deviation pack measured; the posed original changes shape over the animation. With --meshopt
--quantize and with --draco (morphed levels then stay uncompressed, with a warning) the chain is
valid and LOD0 still morphs like the original.
"""
import json
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
from lodbake_test import (ASSETS, Gltf, assert_no_validator_errors, main, make_samples, run, tool,  # noqa: E402
                          work_dir)

GLTF2 = "/usr/share/assimp/models/glTF2"
SIMPLE_SKIN = os.path.join(GLTF2, "simple_skin/simple_skin.gltf")
MORPH_CUBE = os.path.join(GLTF2, "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf")
TRUCK = os.path.join(ASSETS, "CesiumMilkTruck/CesiumMilkTruck.glb")


def chain(src, out, name):
    """Runs the whole chain; returns the paths of the intermediates and the chain, and the reports."""
    p = os.path.join(out, name)
    steps = [("simplify", ["-i", src, "-o", p + ".mr.glb", "--ratio", "0.5,0.1"]),
             ("parameterize", ["-i", p + ".mr.glb", "-o", p + ".uv.glb"]),
             ("texture-refine", ["-i", p + ".uv.glb", "-o", p + ".tex.glb"]),
             ("pack", ["-i", p + ".tex.glb", "-o", p + ".lod.glb"])]
    reports = {}
    for t, args in steps:
        rep = "%s.%s.json" % (p, t)
        run([tool(t), "-q", "--threads", "1", "--report", rep] + args)
        with open(rep) as f:
            reports[t] = json.load(f)
    return p, reports


def posed(original, lod_file, lod, time):
    r = run([tool("compare"), original, lod_file, "--lod", str(lod), "--animation", "0", "--time", time,
             "--views", "6", "--json", "--threads", "1"])
    return json.loads(r.stdout)


class AnimationChain(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.out = work_dir("animation")
        make_samples(os.path.join(cls.out, "samples"))
        cls.walker = os.path.join(cls.out, "samples", "walker.glb")

    def check_skinned_chain(self, src, name):
        p, reports = chain(src, self.out, name)
        assert_no_validator_errors(self, [p + ".mr.glb", p + ".lod.glb"])
        g = Gltf(p + ".lod.glb")
        j = g.json
        self.assertEqual(len(j["skins"]), 1)
        self.assertGreaterEqual(len(j["animations"]), 1)
        levels = [0] + j["nodes"][0]["extensions"]["MSFT_lod"]["ids"]
        self.assertEqual(len(levels), 3)
        for n in levels:
            node = j["nodes"][n]
            self.assertEqual(node.get("skin"), 0, node)
            attrs = j["meshes"][node["mesh"]]["primitives"][0]["attributes"]
            self.assertIn("JOINTS_0", attrs)
            weights = g.accessor(attrs["WEIGHTS_0"])
            for v in range(0, len(weights), 4):
                self.assertAlmostEqual(sum(weights[v:v + 4]), 1.0, places=5)
        # Every joint and the animation targets are in the scene, below one of its roots.
        scene = set(j["scenes"][0]["nodes"])
        reach = set()
        stack = list(scene)
        while stack:
            n = stack.pop()
            reach.add(n)
            stack.extend(j["nodes"][n].get("children", []))
        self.assertTrue(set(j["skins"][0]["joints"]) <= reach)
        # Reading an intermediate back keeps the rig: parameterize's output has simplify's skin and keys.
        a, b = Gltf(p + ".mr.glb"), Gltf(p + ".uv.glb")
        self.assertEqual(a.accessor(a.json["skins"][0]["inverseBindMatrices"]),
                         b.accessor(b.json["skins"][0]["inverseBindMatrices"]))
        for sa, sb in zip(a.json["animations"][0]["samplers"], b.json["animations"][0]["samplers"]):
            self.assertEqual(a.accessor(sa["input"]), b.accessor(sb["input"]))
            self.assertEqual(a.accessor(sa["output"]), b.accessor(sb["output"]))
        # Posed at three times: LOD0 matches the original; coarser levels stay within their measured
        # deviation. Both figures are sampled Hausdorff distances (compare 200,000 points per side,
        # pack 100,000, on differently ordered triangles), which differ by the sample spacing: a
        # slack of 0.1% of the diagonal covers it (CesiumMilkTruck's 10% level: 0.04% in the bind pose).
        self.assertGreater(reports["simplify"]["posedSamples"], 1)
        for time in ("start", "middle", "end"):
            with self.subTest(time=time):
                r0 = posed(src, p + ".lod.glb", 0, time)
                self.assertGreaterEqual(r0["images"]["baseColor"]["iou"], 0.99)
                for k in (1, 2):
                    rk = posed(src, p + ".lod.glb", k, time)
                    measured = reports["pack"]["levels"][k]["deviation"]["hausdorff"]
                    slack = 0.001 * rk["geometry"]["diagonal"]
                    self.assertLessEqual(rk["geometry"]["hausdorff"], measured + slack, (k, measured, rk["geometry"]))
        return reports

    def test_simple_skin(self):
        if not os.path.isfile(SIMPLE_SKIN):
            self.skipTest("assimp-testmodels is not installed")
        self.check_skinned_chain(SIMPLE_SKIN, "simple_skin")

    def test_walker(self):
        self.check_skinned_chain(self.walker, "walker")

    def test_milk_truck(self):
        if not os.path.isfile(TRUCK):
            self.skipTest("../shared/assets is absent")
        self.check_skinned_chain(TRUCK, "truck")

    def check_morph_chain(self, path, targets):
        g = Gltf(path)
        j = g.json
        ids = j["nodes"][0].get("extensions", {}).get("MSFT_lod", {}).get("ids", [])
        levels = [0] + ids
        channels = [c for a in j["animations"] for c in a["channels"] if c["target"]["path"] == "weights"]
        self.assertEqual(sorted(c["target"]["node"] for c in channels), sorted(levels))
        self.assertEqual(len({c["sampler"] for c in channels}), 1, channels)
        for n in levels:
            mesh = j["meshes"][j["nodes"][n]["mesh"]]
            self.assertEqual(len(mesh["weights"]), targets)
            prim = mesh["primitives"][0]
            self.assertEqual(len(prim["targets"]), targets)
            for t in prim["targets"]:
                self.assertEqual(j["accessors"][t["POSITION"]]["count"], j["accessors"][prim["attributes"]["POSITION"]]["count"])

    def test_animated_morph_cube(self):
        if not os.path.isfile(MORPH_CUBE):
            self.skipTest("assimp-testmodels is not installed")
        p, reports = chain(MORPH_CUBE, self.out, "morphcube")
        for t in ("simplify", "parameterize", "texture-refine", "pack"):
            self.assertFalse(any("morph" in w for w in reports[t]["warnings"]), reports[t]["warnings"])
        assert_no_validator_errors(self, [p + ".mr.glb", p + ".uv.glb", p + ".tex.glb", p + ".lod.glb"])
        mr = Gltf(p + ".mr.glb").json
        self.assertEqual([len(m["primitives"][0]["targets"]) for m in mr["meshes"]], [2] * len(mr["meshes"]))
        self.check_morph_chain(p + ".lod.glb", 2)
        diagonals = []
        for time in ("start", "middle", "end"):
            with self.subTest(time=time):
                r0 = posed(MORPH_CUBE, p + ".lod.glb", 0, time)
                self.assertGreaterEqual(r0["images"]["baseColor"]["iou"], 0.99)
                diagonals.append(r0["geometry"]["diagonal"])
                for k in (1, 2):
                    rk = posed(MORPH_CUBE, p + ".lod.glb", k, time)
                    # Absolute distances: compare's relative figures are relative to the posed
                    # diagonal, pack's to the rest pose's, and the cube's shrinks while it morphs.
                    measured = reports["pack"]["levels"][k]["deviation"]["hausdorff"]
                    slack = 0.005 * rk["geometry"]["diagonal"]
                    self.assertLessEqual(rk["geometry"]["hausdorff"], measured + slack, (k, measured, rk["geometry"]))
        # The animation changes the cube's shape: the posed bounds differ between start and middle.
        self.assertGreater(abs(diagonals[0] - diagonals[1]), 0.1 * diagonals[0], diagonals)
        # Compressed variants: meshopt + quantization keep the targets (FLOAT positions); Draco
        # leaves morphed levels uncompressed with a warning.
        for name, flags in (("meshopt", ["--meshopt", "--quantize"]), ("draco", ["--draco"])):
            with self.subTest(variant=name):
                out = "%s.%s.lod.glb" % (p, name)
                rep = "%s.%s.json" % (p, name)
                run([tool("pack"), "-q", "--threads", "1", "-i", p + ".tex.glb", "-o", out, "--report", rep] + flags)
                with open(rep) as f:
                    warnings = json.load(f)["warnings"]
                self.assertTrue(any("morphed levels" in w for w in warnings), warnings)
                assert_no_validator_errors(self, [out])
                self.check_morph_chain(out, 2)
                self.assertNotIn("KHR_draco_mesh_compression", Gltf(out).json.get("extensionsUsed", []))
                self.assertGreaterEqual(posed(MORPH_CUBE, out, 0, "middle")["images"]["baseColor"]["iou"], 0.99)

    def test_draco_skinned_levels(self):
        if not os.path.isfile(SIMPLE_SKIN):
            self.skipTest("assimp-testmodels is not installed")
        p, reports = chain(SIMPLE_SKIN, self.out, "skin_draco")
        out = p + ".draco.lod.glb"
        run([tool("pack"), "-q", "--threads", "1", "-i", p + ".tex.glb", "-o", out, "--draco"])
        assert_no_validator_errors(self, [out])
        j = Gltf(out).json
        self.assertIn("KHR_draco_mesh_compression", j["extensionsRequired"])
        for m in j["meshes"]:
            ext = m["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]
            self.assertIn("JOINTS_0", ext["attributes"])
            self.assertIn("WEIGHTS_0", ext["attributes"])
        for time in ("start", "middle", "end"):
            with self.subTest(time=time):
                self.assertGreaterEqual(posed(SIMPLE_SKIN, out, 0, time)["images"]["baseColor"]["iou"], 0.99)

    def test_pose_samples_flag(self):
        """--pose-samples 0 measures in the bind pose only; a negative count is a usage error."""
        rep = os.path.join(self.out, "walker.bind.json")
        run([tool("simplify"), "-q", "-i", self.walker, "-o", os.path.join(self.out, "walker.bind.mr.glb"),
             "--ratio", "0.1", "--pose-samples", "0", "--report", rep])
        with open(rep) as f:
            self.assertEqual(json.load(f)["posedSamples"], 0)
        r = run([tool("simplify"), "-i", self.walker, "-o", os.path.join(self.out, "x.mr.glb"), "--ratio", "0.1",
                 "--pose-samples", "-1"], check=False)
        self.assertEqual(r.returncode, 1, r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.out, "x.mr.glb")))

    def test_compare_without_animation_is_impossible(self):
        r = run([tool("compare"), self.walker, self.walker, "--animation", "3", "--views", "0"], check=False)
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)


if __name__ == "__main__":
    main([AnimationChain])
