"""Smoke test of the benchmark harness (scripts/bench.py), not a benchmark: `bench.py speed --quick`
on one tiny generated sample (make-samples --scale 0.3: seamball, 432 triangles), one rep, then
`bench.py report` on its results file. Checks the results file's shape (machine, builds, settings,
one row per tool with its figures, the chain's stage split) and that the report prints the
tables; and that `bench.py scale --chain-only` runs the whole chain alone (no stage rows). No
timing is asserted."""
import json
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import lodbake_test as lt  # noqa: E402

BENCH = os.path.join(lt.SOURCE, "scripts/bench.py")


class BenchSmoke(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        lt.require_tools("lodbake", "make-samples")
        cls.dir = lt.work_dir("bench")
        samples = os.path.join(cls.dir, "samples")
        lt.run([lt.tool("make-samples"), samples, "--scale", "0.3"])
        cls.results = os.path.join(cls.dir, "speed.json")
        cls.proc = lt.run([sys.executable, BENCH, "speed", "--quick", "--bin", lt.BIN, "--reps", "1",
                          "--assets", os.path.join(samples, "seamball.glb"), "--work", os.path.join(cls.dir, "work"),
                          "--out", cls.results], timeout=300)
        with open(cls.results) as f:
            cls.json = json.load(f)

    def test_run_record(self):
        j = self.json
        self.assertEqual(j["schema"], "lodbake-bench/1")
        self.assertEqual(j["suite"], "speed")
        self.assertIn("--quick", j["command"])
        for key in ("cores", "loadAverageStart", "loadAverageEnd", "os"):
            self.assertIn(key, j["machine"])
        self.assertEqual([b["label"] for b in j["builds"]], ["bin"])
        self.assertEqual(os.path.realpath(j["builds"][0]["bin"]), os.path.realpath(lt.BIN))
        self.assertEqual(j["settings"]["reps"], 1)
        self.assertGreater(j["seconds"], 0)

    def test_rows(self):
        self.assertEqual(len(self.json["assets"]), 1)
        a = self.json["assets"][0]
        self.assertEqual(a["name"], "seamball")
        self.assertGreater(a["triangles"], 0)
        ours = [r for r in a["rows"] if r["tool"] == "lodbake"]
        self.assertEqual(len(ours), 1)
        r = ours[0]
        self.assertNotIn("error", r)
        for key in ("wall", "cpu", "peakMB", "bytes"):
            self.assertGreater(r[key], 0, key)
        self.assertEqual(len(r["walls"]), 1)
        self.assertEqual(set(r["stages"]) - {"total"}, {"simplify", "parameterize", "texture-refine", "pack"})
        self.assertEqual(len(r["levels"]), 4)  # LOD0 and the three ratios
        self.assertEqual(len(r["sha256"]), 64)
        self.assertTrue(a["identicalAcrossThreads"]["bin"])
        tools = {r["tool"] for r in a["rows"]}
        self.assertEqual(tools - {"lodbake"}, set(self.json["settings"]["peers"]))
        for p in a["rows"]:
            self.assertTrue("error" in p or p["wall"] >= 0, p)

    def test_scale_chain_only(self):
        out = os.path.join(self.dir, "scale.json")
        lt.run([sys.executable, BENCH, "scale", "--bin", lt.BIN, "--assets", os.path.join(self.dir, "samples", "seamball.glb"),
                "--chain-only", "seamball", "--no-compare", "--work", os.path.join(self.dir, "work"), "--out", out], timeout=300)
        with open(out) as f:
            a = json.load(f)["assets"][0]
        ours = [r["tool"] for r in a["rows"] if r.get("build") == "bin"]
        self.assertEqual(ours, ["lodbake"])
        self.assertNotIn("error", a["rows"][0])
        self.assertEqual(set(a["rows"][0]["stages"]), {"simplify", "parameterize", "texture-refine", "pack"})
        p = lt.run([sys.executable, BENCH, "report", out])
        self.assertIn("- seamball: whole chain", p.stdout)

    def test_report(self):
        p = lt.run([sys.executable, BENCH, "report", self.results])
        self.assertIn("| seamball |", p.stdout)
        self.assertIn("| asset | triangles | build | threads | wall s |", p.stdout)


if __name__ == "__main__":
    lt.main([BenchSmoke])
