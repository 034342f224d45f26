"""CLI tests of `compare` on files written by `make-samples` (and variants of them made here):
a model against itself, against a copy shifted by 1% of its diagonal, against a copy whose
textures are replaced by flat grey; the pbr mode; exit codes; --threads determinism; contact sheet."""
import json
import os
import shutil
import struct
import subprocess
import sys
import unittest

BIN = os.environ.get("LODBAKE_BIN", "")
WORK = os.environ.get("LODBAKE_WORK", "/tmp/lodbake-test-compare")


def tool(name):
    return os.path.join(BIN, name)


def read_glb(path):
    data = open(path, "rb").read()
    n = struct.unpack_from("<I", data, 12)[0]
    return json.loads(data[20:20 + n]), data[20 + n:]


def write_glb(path, doc, rest):
    js = json.dumps(doc).encode()
    js += b" " * ((4 - len(js) % 4) % 4)
    body = struct.pack("<II", len(js), 0x4E4F534A) + js + rest
    with open(path, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)


def run(*args):
    return subprocess.run([tool("compare")] + [str(a) for a in args], capture_output=True, text=True)


def report(*args):
    p = run(*args, "--json")
    return p.returncode, (json.loads(p.stdout) if p.stdout.strip().startswith("{") else None), p


class CompareCli(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        shutil.rmtree(WORK, ignore_errors=True)
        os.makedirs(WORK)
        subprocess.run([tool("make-samples"), WORK], check=True)
        cls.a = os.path.join(WORK, "hemisphere9.glb")
        doc, rest = read_glb(cls.a)
        # Shifted copy: the hemisphere spans x in [-1, 1], y in [0, 1], z in [-1, 1] -> diagonal 3.
        cls.diag = 3.0
        shifted = json.loads(json.dumps(doc))
        shifted["nodes"][0]["translation"] = [0.01 * cls.diag, 0, 0]
        cls.shifted = os.path.join(WORK, "hemisphere9-shifted.glb")
        write_glb(cls.shifted, shifted, rest)
        grey = json.loads(json.dumps(doc))
        for m in grey["materials"]:
            pbr = m.setdefault("pbrMetallicRoughness", {})
            pbr.pop("baseColorTexture", None)
            pbr["baseColorFactor"] = [0.5, 0.5, 0.5, 1]
        cls.grey = os.path.join(WORK, "hemisphere9-grey.glb")
        write_glb(cls.grey, grey, rest)

    def test_model_against_itself(self):
        rc, j, p = report(self.a, self.a, "--samples", 50000, "--views", 8, "--resolution", 128)
        self.assertEqual(rc, 0, p.stderr)
        self.assertLess(j["geometry"]["relHausdorff"], 1e-12)
        for mode in ("baseColor", "shaded", "pbr"):
            self.assertEqual(j["images"][mode]["psnr"], 100.0)  # capped maximum
            self.assertEqual(j["images"][mode]["iou"], 1.0)
            self.assertAlmostEqual(j["images"][mode]["ssim"], 1.0, places=12)
        self.assertEqual(j["counts"]["a"], j["counts"]["b"])
        self.assertEqual(j["counts"]["a"]["materials"], 9)
        self.assertEqual(j["counts"]["a"]["drawCalls"], 9)
        self.assertEqual(j["counts"]["a"]["texels"], 9 * 128 * 128)
        self.assertTrue(j["pass"])

    def test_shifted_by_one_percent(self):
        rc, j, p = report(self.a, self.shifted, "--samples", 50000, "--views", 8, "--resolution", 128)
        self.assertEqual(rc, 0, p.stderr)
        self.assertAlmostEqual(j["geometry"]["relHausdorff"], 0.01, delta=0.0005)
        self.assertLess(j["geometry"]["relRms"], 0.01)
        self.assertLess(j["images"]["shaded"]["iou"], 1.0)
        # Tolerances: exceeded -> 1, held -> 0.
        self.assertEqual(run(self.a, self.shifted, "--views", 0, "--max-hausdorff", 0.005).returncode, 1)
        self.assertEqual(run(self.a, self.shifted, "--views", 0, "--max-hausdorff", 0.02).returncode, 0)

    def test_grey_texture_lowers_base_colour_psnr_only(self):
        rc, j, p = report(self.a, self.grey, "--samples", 1000, "--views", 8, "--resolution", 128)
        self.assertEqual(rc, 0, p.stderr)
        self.assertLess(j["images"]["baseColor"]["psnr"], 20)
        self.assertEqual(j["images"]["shaded"]["psnr"], 100.0)
        self.assertEqual(j["images"]["baseColor"]["iou"], 1.0)
        self.assertEqual(run(self.a, self.grey, "--views", 4, "--min-psnr", 30).returncode, 1)
        self.assertEqual(run(self.a, self.grey, "--views", 4, "--min-shaded-psnr", 60).returncode, 0)

    def test_pbr_mode(self):
        rc, j, p = report(self.a, self.grey, "--samples", 1000, "--views", 4, "--resolution", 96, "-v")
        self.assertEqual(rc, 0, p.stderr)
        self.assertIn("pbr", j["images"])
        self.assertEqual(len(j["images"]["perView"]), 4)
        self.assertIn("pbr", j["images"]["perView"][0])
        self.assertLess(j["images"]["pbr"]["psnr"], 30)  # the base colour shows through the lighting
        self.assertEqual(j["images"]["pbr"]["iou"], 1.0)
        self.assertEqual(run(self.a, self.grey, "--views", 4, "--min-pbr-psnr", 30).returncode, 1)
        self.assertEqual(run(self.a, self.a, "--views", 4, "--min-pbr-psnr", 99).returncode, 0)
        table = run(self.a, self.grey, "--views", 2, "--resolution", 64, "--samples", 1000)
        self.assertRegex(table.stdout, r"base colour +shaded +pbr")

    def test_threads_do_not_change_the_output(self):
        args = [self.a, self.shifted, "--samples", 30000, "--views", 6, "--resolution", 96]
        one = run(*args, "--threads", 1, "--json")
        two = run(*args, "--threads", 2, "--json")
        self.assertEqual(one.returncode, 0, one.stderr)
        self.assertEqual(one.stdout, two.stdout)

    def test_report_and_sheet(self):
        rep = os.path.join(WORK, "r.json")
        sheet = os.path.join(WORK, "sheet.png")
        p = run(self.a, self.grey, "--views", 3, "--resolution", 64, "--samples", 1000, "--report", rep, "--sheet", sheet)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("psnr", p.stdout)  # the table
        self.assertEqual(json.load(open(rep))["tool"], "compare")
        with open(sheet, "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")

    def test_exit_codes(self):
        self.assertEqual(run(self.a, os.path.join(WORK, "missing.glb")).returncode, 2)
        bad = os.path.join(WORK, "bad.glb")
        open(bad, "wb").write(b"not a glb at all")
        self.assertEqual(run(self.a, bad).returncode, 2)
        self.assertEqual(run(self.a).returncode, 1)
        self.assertEqual(run(self.a, self.a, "--no-such-flag").returncode, 1)
        self.assertEqual(run(self.a, self.a, "--lod", 1, "--views", 0).returncode, 3)  # no levels
        h = run("--help")
        self.assertEqual(h.returncode, 0)
        self.assertIn("tolerance is exceeded", h.stdout)


if __name__ == "__main__":
    if not BIN or not os.path.exists(tool("compare")) or not os.path.exists(tool("make-samples")):
        print("skipped: compare/make-samples not built in LODBAKE_BIN")
        sys.exit(77)
    unittest.main()
