"""simplify on make-samples' drum.glb (issue 24): a large open textured backdrop on a floor around
21 small detailed parts, seven of them stuck on non-manifold spines. The coarse levels must spend
their budget where it shows:
- at 2% the silhouette IoU is >= 0.9 and the Hausdorff distance <= 5% of the diagonal (the drum
  stays, the small parts are pruned or reduced), and the level reaches its target;
- at 10% the level stays excellent (IoU >= 0.98, Hausdorff <= 1%);
- with --no-visual-weight (parts pruned by size, in a pass closed ones only) the 2% level loses
  the drum, which is what the flag is there to show.
Needs only the project's own samples."""
import json
import os
import unittest

import lodbake_test as lt

COMPARE = ["--json", "--views", "8", "--resolution", "256", "--samples", "100000"]


class SimplifyDrum(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        lt.require_tools("make-samples", "simplify", "compare")
        cls.dir = lt.work_dir("drum")
        cls.src = os.path.join(lt.make_samples(os.path.join(cls.dir, "in")), "drum.glb")

    def simplify(self, out, *extra):
        rep = out[:-4] + ".json"
        lt.run([lt.tool("simplify"), "-i", self.src, "-o", out, "--ratio", "0.1,0.02", "--report", rep,
                "--quiet"] + list(extra))
        with open(rep) as f:
            return json.load(f)

    def measure(self, out, lod):
        r = json.loads(lt.run([lt.tool("compare"), self.src, out, "--lod", str(lod)] + COMPARE).stdout)
        return r["geometry"]["relHausdorff"], min(r["images"][m]["iou"] for m in ("baseColor", "shaded"))

    def test_coarse_levels_keep_the_drum(self):
        out = os.path.join(self.dir, "drum.mr.glb")
        rep = self.simplify(out)
        self.assertEqual([lv["stopReason"] for lv in rep["levels"]], ["target", "target"], rep["levels"])
        hausdorff, iou = self.measure(out, 1)
        self.assertLessEqual(hausdorff, 0.01)
        self.assertGreaterEqual(iou, 0.98)
        hausdorff, iou = self.measure(out, 2)
        self.assertLessEqual(hausdorff, 0.05)
        self.assertGreaterEqual(iou, 0.9)

    def test_without_visual_weight_the_drum_dies(self):
        out = os.path.join(self.dir, "drum.size.mr.glb")
        self.simplify(out, "--no-visual-weight")
        hausdorff, iou = self.measure(out, 2)
        self.assertGreater(hausdorff, 0.1)
        self.assertLess(iou, 0.5)


if __name__ == "__main__":
    lt.main([SimplifyDrum])
