"""CLI tests for parameterize: simplify -> parameterize on generated samples."""
import json
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import lodbake_test as lt  # noqa: E402


class ParameterizeCli(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if not os.path.exists(lt.tool("parameterize")) or not os.path.exists(lt.tool("make-samples")):
            lt.skip("parameterize or make-samples is not built")
        cls.dir = lt.work_dir("parameterize")
        lt.make_samples(cls.dir)

    def chain(self, name):
        src = os.path.join(self.dir, name + ".glb")
        mr = os.path.join(self.dir, name + ".mr.glb")
        uv = os.path.join(self.dir, name + ".uv.glb")
        rep = os.path.join(self.dir, name + ".param.json")
        lt.run([lt.tool("simplify"), "-i", src, "-o", mr, "--ratio", "0.5,0.1,0.02"])
        lt.run([lt.tool("parameterize"), "-i", mr, "-o", uv, "--size", "256", "--report", rep])
        with open(rep) as f:
            return uv, json.load(f)

    def check(self, name):
        uv, r = self.chain(name)
        t = r["total"]
        self.assertEqual(t["flips"], 0)
        self.assertEqual(t["overlaps"], 0)
        self.assertGreaterEqual(t["charts"], 1)
        self.assertLessEqual(t["final"]["E"], t["tutte"]["E"] + 1e-9)
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
        return uv

    def test_hemisphere(self):
        self.check("hemisphere9")

    def test_seamball_closed(self):
        uv = self.check("seamball")
        # The output is itself a valid parameterize input (levels survive the round trip).
        lt.run([lt.tool("parameterize"), "-i", uv, "-o", os.path.join(self.dir, "again.glb"), "--size", "128",
                "--iterations", "0"])

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
