"""pipelines/Makefile: builds the samples through simplify -> parameterize -> texture-refine -> pack
from scratch; a second run does nothing (`make -q` is 0, "Nothing to be done", output mtimes
unchanged); runs with THREADS=1 and THREADS=2 into different OUT folders give byte-identical
outputs at every stage; changing RATIOS rebuilds."""
import os
import shutil
import subprocess
import sys
import unittest

BIN = os.environ.get("LODBAKE_BIN", "")
SOURCE = os.environ.get("LODBAKE_SOURCE", "")
WORK = os.environ.get("LODBAKE_WORK", "/tmp/lodbake-test-pipeline")
NAMES = ["hemisphere9", "wall5", "colors", "seamball"]
STAGES = ["mr", "uv", "tex", "lod"]


def make(out, *extra, check=True):
    cmd = ["make", "-C", os.path.join(SOURCE, "pipelines"), "BIN=" + BIN, "OUT=" + out] + list(extra)
    return subprocess.run(cmd, capture_output=True, text=True, check=check)


def outputs(out):
    return sorted(os.path.join(out, "%s.%s.glb" % (n, stage)) for n in NAMES for stage in STAGES)


class Pipeline(unittest.TestCase):
    def test_build_rebuild_and_determinism(self):
        shutil.rmtree(WORK, ignore_errors=True)
        o1, o2 = os.path.join(WORK, "t1"), os.path.join(WORK, "t2")
        p = make(o1, "THREADS=1", "-j2", check=False)
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        for f in outputs(o1):
            self.assertTrue(os.path.getsize(f) > 0, f)
            self.assertTrue(os.path.exists(f[:-4] + ".json"), f)
        mtimes = [os.stat(f).st_mtime_ns for f in outputs(o1)]

        # Nothing to do the second time (THREADS is not part of the flag stamp).
        self.assertEqual(make(o1, "THREADS=2", "-q", check=False).returncode, 0)
        again = make(o1, "THREADS=1")
        self.assertIn("Nothing to be done", again.stdout)
        self.assertEqual(mtimes, [os.stat(f).st_mtime_ns for f in outputs(o1)])

        # Same bytes whatever the thread count.
        p = make(o2, "THREADS=2", "-j2", check=False)
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        for a, b in zip(outputs(o1), outputs(o2)):
            with open(a, "rb") as fa, open(b, "rb") as fb:
                self.assertEqual(fa.read(), fb.read(), "%s differs from %s" % (a, b))

        # A flag change rebuilds; going back rebuilds again, then nothing.
        self.assertNotEqual(make(o1, "RATIOS=0.5,0.1", "-q", check=False).returncode, 0)
        make(o1, "RATIOS=0.5,0.1")
        self.assertEqual(make(o1, "RATIOS=0.5,0.1", "-q", check=False).returncode, 0)

        # Golden files: update, then the check passes.
        golden = os.path.join(WORK, "golden")
        make(o2, "GOLDEN=" + golden, "golden-update")
        p = make(o2, "GOLDEN=" + golden, "golden-check", check=False)
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)


if __name__ == "__main__":
    tools = ("make-samples", "simplify", "parameterize", "texture-refine", "pack", "compare")
    missing = [t for t in tools if not os.path.exists(os.path.join(BIN, t))]
    if not BIN or not SOURCE or missing or shutil.which("make") is None:
        print("skipped: needs LODBAKE_BIN with %s, LODBAKE_SOURCE and make" % (missing or "the tools"))
        sys.exit(77)
    unittest.main()
