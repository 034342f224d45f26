"""`compare` against Debian's gltfpack simplification (-si R) of the shared Duck and Avocado:
triangles fall and the geometric error (Hausdorff, RMS) grows as the ratio drops. gltfpack stops
near the same count at small ratios (UV seams); when two outputs have nearly the same triangle
count their errors may differ by a little either way, so that case only needs to stay close."""
import json
import os
import shutil
import subprocess
import sys
import unittest

BIN = os.environ.get("LODBAKE_BIN", "")
SHARED = os.environ.get("LODBAKE_SHARED", "")
WORK = os.environ.get("LODBAKE_WORK", "/tmp/lodbake-test-compare-gltfpack")
GLTFPACK = "/usr/bin/gltfpack"
RATIOS = [0.5, 0.2, 0.05]
ASSETS = ["Duck/Duck.glb", "Avocado/Avocado.gltf"]


class CompareWithGltfpack(unittest.TestCase):
    def figures(self, original, ratio):
        out = os.path.join(WORK, "%s_%s.glb" % (os.path.basename(original).split(".")[0], ratio))
        subprocess.run([GLTFPACK, "-i", original, "-o", out, "-si", str(ratio)], check=True, capture_output=True)
        p = subprocess.run([os.path.join(BIN, "compare"), original, out, "--json", "--views", "8", "--resolution", "128"],
                           capture_output=True, text=True)
        self.assertEqual(p.returncode, 0, p.stderr)
        return json.loads(p.stdout)

    def test_error_grows_as_ratio_drops(self):
        for rel in ASSETS:
            original = os.path.join(SHARED, "assets", rel)
            rows = [self.figures(original, r) for r in RATIOS]
            for j in rows:
                self.assertEqual(j["counts"]["b"]["drawCalls"], j["counts"]["a"]["drawCalls"])
                self.assertGreater(j["images"]["shaded"]["iou"], 0.9)
                print(rel, j["counts"]["b"]["triangles"], j["geometry"]["relHausdorff"], j["geometry"]["relRms"],
                      j["images"]["baseColor"]["psnr"], j["images"]["shaded"]["psnr"])
            for coarse, fine in zip(rows[1:], rows[:-1]):
                tc, tf = coarse["counts"]["b"]["triangles"], fine["counts"]["b"]["triangles"]
                self.assertLessEqual(tc, 1.05 * tf, rel)  # gltfpack may land a few triangles apart
                for key in ("relHausdorff", "relRms"):
                    gc, gf = coarse["geometry"][key], fine["geometry"][key]
                    if tc < 0.9 * tf:
                        self.assertGreater(gc, gf, "%s %s: %d tris %g vs %d tris %g" % (rel, key, tc, gc, tf, gf))
                    else:
                        self.assertGreater(gc, 0.9 * gf, "%s %s" % (rel, key))


if __name__ == "__main__":
    missing = [p for p in [os.path.join(SHARED, "assets", a) for a in ASSETS] + [GLTFPACK] if not os.path.exists(p)]
    if not BIN or not os.path.exists(os.path.join(BIN, "compare")):
        missing.append("compare in LODBAKE_BIN")
    if not SHARED:
        missing.append("LODBAKE_SHARED")
    if missing:
        print("skipped: missing " + ", ".join(missing))
        sys.exit(77)
    shutil.rmtree(WORK, ignore_errors=True)
    os.makedirs(WORK)
    unittest.main()
