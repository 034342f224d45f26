"""The HTML reports of `lodbake --html` and `compare --html`, opened from their files (no server) in
Debian's headless Chromium by playwright-core (tests/browser/html_report.js; never a downloaded
browser). A 4-level chain (LOD0 + the default three levels) of a generated sample: the page shows a
section per level with one decoded image per view (4) and its atlas pages, no script and no request
beyond the file itself; every figure on it equals the JSON report's value at its pointer, and shows
it rounded to 4 significant digits; the table has every figure of every level; the report (with its
compare section) matches its schema, and the compare figures of a level are those `compare IN OUT
--lod K` gives. compare --html the same for one pair.
Bad --html paths: a one-line error, the documented exit code, no file written. The full-page
screenshots stay in the test's work folder as artefacts. Skips (77) without chromium or node."""
import json
import os
import shutil
import subprocess
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
from lodbake_test import CHROMIUM, NODE_MODULES, SOURCE, make_samples, run, skip, tool, work_dir  # noqa: E402

SAMPLE = "seamball"
SMALL = ["--size", "128", "--refine-size", "128", "--sizes", "64,128", "--max-size", "128", "--samples", "2000", "-q"]
VIEWS = 4  # view images per level (ReviewImageOptions::maxViews)
PACK_FIGURES = ["triangles", "drawCalls", "texels", "bytes", "deviation/hausdorff", "deviation/relHausdorff",
                "switchDistance"]
IMAGE_FIGURES = ["images/%s/%s" % (mode, m) for m in ("psnr", "ssim") for mode in ("baseColor", "shaded", "pbr")] + \
    ["images/pbr/iou"]


def resolve(doc, pointer):
    for key in pointer.split("/")[1:]:
        key = key.replace("~1", "/").replace("~0", "~")
        doc = doc[int(key)] if isinstance(doc, list) else doc[key]
    return doc


def shown(value):
    """The text the page shows for a JSON value (metrics/html_report.cpp)."""
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, int):
        return "{:,}".format(value)
    if isinstance(value, float):
        return "%.4g" % value
    return value


class HtmlReport(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        for t in ("lodbake", "compare", "make-samples"):
            if not os.path.exists(tool(t)):
                skip(t + " is not built")
        if not os.path.exists(CHROMIUM):
            skip("chromium is missing (apt-get install chromium; scripts/setup-debian.sh)")
        if shutil.which("node") is None:
            skip("node is missing")
        if not os.path.isdir(os.path.join(NODE_MODULES, "playwright-core")):
            skip("scripts/node/node_modules/playwright-core is missing (cd scripts/node && npm ci)")
        cls.dir = work_dir("html")
        cls.src = os.path.join(make_samples(os.path.join(cls.dir, "samples")), SAMPLE + ".glb")
        cls.chain = os.path.join(cls.dir, SAMPLE + ".lod.glb")
        cls.report = os.path.join(cls.dir, SAMPLE + ".json")
        cls.html = os.path.join(cls.dir, SAMPLE + ".html")
        p = run([tool("lodbake"), "-i", cls.src, "-o", cls.chain, "--report", cls.report, "--html", cls.html] + SMALL)
        cls.stderr = p.stderr

    def open_page(self, html):
        shot = html + ".png"
        p = subprocess.run(["node", os.path.join(SOURCE, "tests/browser/html_report.js"), html, shot],
                           capture_output=True, text=True, timeout=120,
                           env=dict(os.environ, NODE_PATH=NODE_MODULES, CHROMIUM=CHROMIUM))
        self.assertEqual(p.returncode, 0, p.stderr[-3000:])
        page = json.loads(p.stdout.strip().splitlines()[-1])
        with open(shot, "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")
        self.assertEqual(page["pageErrors"], [])
        self.assertEqual(page["scripts"], 0)
        self.assertEqual(page["requests"], ["file://" + os.path.abspath(html)])  # self-contained
        return page

    def assert_figures_equal_report(self, page, report):
        """Every figure's value is the report's at its pointer, and its text that value rounded."""
        self.assertGreater(len(page["figures"]), 0)
        for f in page["figures"]:
            with self.subTest(pointer=f["pointer"]):
                expected = resolve(report, f["pointer"])
                self.assertEqual(f["value"], expected)
                self.assertEqual(f["text"], shown(expected))

    def test_lodbake_html(self):
        self.assertEqual(self.stderr, "")
        report = json.load(open(self.report))
        page = self.open_page(self.html)
        levels = report["stages"][-1]["levels"]
        self.assertEqual(len(levels), 4)  # LOD0 + the three default levels
        self.assertEqual(len(report["compare"]), 4)
        self.assertEqual([lv["title"] for lv in page["levels"]], ["LOD %d" % k for k in range(4)])
        for k, lv in enumerate(page["levels"]):
            with self.subTest(level=k):
                self.assertEqual(len(lv["views"]), VIEWS)
                self.assertGreaterEqual(len(lv["pages"]), 1)  # at least the base colour page
                for img in lv["views"]:
                    self.assertTrue(img["complete"])
                    self.assertEqual((img["width"], img["height"]), (3 * 256, 256))  # original | level | difference
                for img in lv["pages"]:
                    self.assertTrue(img["complete"] and img["width"] > 0 and img["height"] > 0)
        self.assertEqual(page["images"], sum(len(lv["views"]) + len(lv["pages"]) for lv in page["levels"]))
        self.assert_figures_equal_report(page, report)
        # The table holds every figure of every level, none missing.
        pointers = {f["pointer"] for f in page["figures"] if f["value"] is not None}
        pack = "/stages/%d/levels/" % (len(report["stages"]) - 1)
        for k in range(4):
            for name in PACK_FIGURES:
                self.assertIn(pack + "%d/%s" % (k, name), pointers)
            for name in IMAGE_FIGURES:
                self.assertIn("/compare/%d/%s" % (k, name), pointers)
        self.assertEqual(page["warnings"], report["warnings"])
        try:
            import jsonschema  # noqa: F401
        except ImportError:
            jsonschema = None
        if jsonschema is not None:  # the report with its "compare" section matches docs/schemas/lodbake.schema.json
            from test_report_schemas import errors, load_schemas
            self.assertEqual(errors(load_schemas(), "lodbake", report), [])

    def test_compare_html(self):
        html, rep = os.path.join(self.dir, "compare.html"), os.path.join(self.dir, "compare.json")
        p = run([tool("compare"), self.src, self.chain, "--lod", "3", "--html", html, "--report", rep])
        self.assertEqual(p.stderr, "")
        page = self.open_page(html)
        report = json.load(open(rep))
        self.assertEqual(len(page["levels"]), 1)
        self.assertEqual(len(page["levels"][0]["views"]), VIEWS)
        self.assertGreaterEqual(len(page["levels"][0]["pages"]), 1)
        self.assert_figures_equal_report(page, report)
        # lodbake's figures of a level are those compare itself reports for it.
        chain = json.load(open(self.report))
        for key in ("counts", "geometry", "images"):
            self.assertEqual(chain["compare"][3][key], report[key])
        pointers = {f["pointer"] for f in page["figures"]}
        for name in ["counts/b/triangles", "counts/b/texels", "geometry/relHausdorff"] + IMAGE_FIGURES:
            self.assertIn("/" + name, pointers)
        # Fewer views than four: all of them.
        few = os.path.join(self.dir, "few.html")
        run([tool("compare"), self.src, self.chain, "--lod", "1", "--views", "2", "--no-geometry", "--html", few])
        with open(few) as f:
            self.assertEqual(f.read().count('<img class="view"'), 2)

    def test_bad_html_paths(self):
        d = os.path.join(self.dir, "bad")
        os.makedirs(d, exist_ok=True)
        out = os.path.join(d, "x.lod.glb")
        missing = os.path.join(d, "no-such-folder", "x.html")
        cases = [
            (["--html", missing], 2),
            (["--html", d], 2),                                       # a folder
            (["--html", out], 1),                                     # the chain itself
            (["--html", os.path.join(d, "x.html"), "--split"], 1),    # the levels in several files
        ]
        for extra, code in cases:
            with self.subTest(args=extra):
                p = run([tool("lodbake"), "-i", self.src, "-o", out] + SMALL + extra, check=False)
                self.assertEqual(p.returncode, code, p.stderr)
                self.assertEqual(len(p.stderr.splitlines()), 1, p.stderr)
                self.assertTrue(p.stderr.startswith("lodbake error: "), p.stderr)
                self.assertEqual(os.listdir(d), [])
        # Batch mode: one page per run.
        p = run([tool("lodbake"), os.path.dirname(self.src), "-o", d + "/", "--html", os.path.join(d, "x.html")],
                check=False)
        self.assertEqual((p.returncode, len(p.stderr.splitlines())), (1, 1), p.stderr)
        self.assertEqual(os.listdir(d), [])
        p = run([tool("compare"), self.src, self.chain, "--html", missing], check=False)
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertEqual(p.stderr.splitlines(), ["compare error: %s: folder '%s' does not exist"
                                                 % (missing, os.path.dirname(missing))])
        self.assertFalse(os.path.exists(os.path.dirname(missing)))


if __name__ == "__main__":
    unittest.main()
