"""Appearance test: every level of a pack output, lit and physically based, in three.js.

simplify -> parameterize -> pack on the seamball and hemisphere9 samples (and Duck, Avocado when
../shared/assets exists), then scripts/render_three.py renders the original and each level
(FILE#node=K: node 0 and the MSFT_lod ids) in Debian's headless Chromium from the same 8 cameras
(three.js from scripts/node/node_modules, served on 127.0.0.1, no CDN). Checks: every level loads
without error and renders non-empty; LOD0's PSNR against the original stays above a floor
measured on this toolchain (pack bakes the base colour only, so PBR assets sit low); coarser
levels' PSNR and SSIM are finite and no level renders more than LEVEL_ORDER_SLACK closer to the
original than the level before it; the original rendered twice compares as identical (100 dB).
Seams: on pbrscene (a normal-mapped dome cut into charts) every level's seam band (the pixels
within 2 of a texture seam it shows, psnr_seam) stays within SEAM_BAND_MARGIN of the whole
foreground's PSNR, seams looking no worse than the rest of the surface; at least one level shows
seams.
A pack --draco output checks three.js's DRACOLoader path.
The PNGs and results.json stay in the test's work dir. Skips (77) when chromium, node or the node
modules are missing.
"""
import json
import math
import os
import subprocess
import sys
import time
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import lodbake_test as lt  # noqa: E402

RENDER = os.path.join(lt.SOURCE, "scripts/render_three.py")
CHROMIUM = lt.CHROMIUM

# LOD0 PSNR floors (dB, RGB, mean over 8 views against the original): the value measured with
# three 0.187 in Debian 12's chromium minus LOD0_PSNR_MARGIN, for small renderer differences.
LOD0_PSNR_MARGIN = 3.0
LOD0_PSNR_MEASURED = {
    "seamball": 33.60,
    "seamball.draco": 33.47,
    "hemisphere9": 30.13,
    "Duck": 45.03,
    "Avocado": 39.02,
    "pbrscene": 31.18,
}
LEVEL_ORDER_SLACK = 0.3  # dB: a coarser level may render this much closer than the finer one (bake noise)
SEAM_BAND_MARGIN = 2.0  # dB: a level's seam band PSNR may sit this far below its foreground PSNR
MIN_COVERAGE = 0.01  # fraction of non-background pixels a rendered level must reach


class ThreeChain(unittest.TestCase):
    """Builds every chain, then renders all of them in one browser session (the first render of
    each material kind compiles shaders in SwiftShader, the slow part); each test checks one asset."""

    @classmethod
    def setUpClass(cls):
        lt.require_browser_chain(("three", "playwright-core"))
        cls.dir = lt.work_dir("threejs")
        samples = lt.make_samples(os.path.join(cls.dir, "samples"))
        sources = {name: os.path.join(samples, name + ".glb") for name in ("seamball", "hemisphere9", "pbrscene")}
        cls.absent = {}
        for name in ("Duck", "Avocado"):
            path = os.path.join(lt.ASSETS, lt.ASSET_FILES[name])
            if os.path.exists(path):
                sources[name] = path
            else:
                cls.absent[name] = path + " is absent (../shared/assets)"
                print("SKIPPING %s: %s" % (name, cls.absent[name]))
        start = time.time()
        cls.chains, cls.failures, groups, cls.labels = {}, {}, [], {}
        for name, src in sources.items():
            try:
                cls.chains[name] = cls.chain(src, name, draco=(name == "seamball"))
            except AssertionError as e:
                cls.failures[name] = str(e)
                continue
            # seamball's original again: the renders are deterministic and the comparison says so.
            candidates, labels = ([src], ["original"]) if name == "seamball" else ([], [])
            for tag, path in cls.chains[name]:
                for k, node in enumerate(cls.levels(path)):
                    candidates.append("%s#node=%d" % (path, node))
                    labels.append(tag + "LOD%d" % k)
            groups.append({"reference": src, "candidates": candidates, "out": os.path.join(cls.dir, name + ".png")})
            cls.labels[name] = labels
        cls.results = {}
        if not groups:
            return
        print("chains built in %.1f s" % (time.time() - start))
        start = time.time()
        batch, out_json = os.path.join(cls.dir, "batch.json"), os.path.join(cls.dir, "results.json")
        with open(batch, "w") as f:
            json.dump(groups, f, indent=1)
        p = subprocess.run([sys.executable, RENDER, "--batch", batch, "--views", "8", "--size", "256", "--json", out_json],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=1800,
                           env=dict(os.environ, CHROMIUM=CHROMIUM))
        print(p.stdout)
        if p.returncode != 0 and not os.path.exists(out_json):
            raise AssertionError("render_three.py failed (%d): %s" % (p.returncode, p.stderr[-3000:]))
        with open(out_json) as f:
            for name, result in zip(cls.labels, json.load(f)):
                for c, label in zip(result["candidates"], cls.labels[name]):
                    c["level"] = label
                cls.results[name] = result
        print("rendered and compared in %.1f s" % (time.time() - start))
        print("three.js %s, against the original: PSNR dB (RGB / foreground only), SSIM grey, coverage"
              % next(iter(cls.results.values()))["three"])
        for name, r in cls.results.items():
            for c in r["candidates"]:
                seam = "" if c.get("psnr_seam") is None else "  seam band %6.2f" % c["psnr_seam"]
                print("  %-12s %-11s %s" % (name, c["level"], "FAILED" if c["psnr"] is None else
                                            "%6.2f / %6.2f  %.4f  %.3f%s" % (c["psnr"], c["psnr_fg"], c["ssim"],
                                                                             c["coverage"], seam)))
        sys.stdout.flush()

    @classmethod
    def chain(cls, src, name, draco=False):
        """simplify -> parameterize -> pack; returns [(tag, pack output)], plus its --draco twin."""
        mr = os.path.join(cls.dir, name + ".mr.glb")
        uv = os.path.join(cls.dir, name + ".uv.glb")
        out = os.path.join(cls.dir, name + ".lod.glb")
        lt.run([lt.tool("simplify"), "-i", src, "-o", mr, "--ratio", "0.5,0.1,0.02", "--quiet"])
        lt.run([lt.tool("parameterize"), "-i", mr, "-o", uv, "--size", "512", "--quiet"])
        pack = [lt.tool("pack"), "-i", uv, "--max-size", "512", "--samples", "5000", "--quiet"]
        lt.run(pack + ["-o", out])
        files = [("", out)]
        if draco:
            files.append(("draco.", os.path.join(cls.dir, name + ".draco.lod.glb")))
            lt.run(pack + ["-o", files[-1][1], "--draco"])
        return files

    @staticmethod
    def levels(path):
        nodes = lt.Gltf(path).json["nodes"]
        return [0] + list(nodes[0].get("extensions", {}).get("MSFT_lod", {}).get("ids", []))

    def check(self, name, level_count=None):
        if name in self.absent:
            self.skipTest(self.absent[name])
        self.assertNotIn(name, self.failures, self.failures.get(name))
        self.assertIn(name, self.results, "no render result for " + name)
        result = self.results[name]
        self.assertTrue(result["reference"]["loaded"], result["reference"]["errors"])
        self.assertGreater(result["reference"]["coverage"], MIN_COVERAGE, "the original renders (nearly) empty")
        for c in result["candidates"]:
            self.assertTrue(c["loaded"], "%s: %s" % (c["candidate"], c["errors"]))
            self.assertGreater(c["coverage"], MIN_COVERAGE, "%s renders (nearly) empty" % c["candidate"])
            self.assertTrue(math.isfinite(c["psnr"]) and math.isfinite(c["ssim"]), c)
        levels = {c["level"]: c for c in result["candidates"]}
        if level_count is not None:
            self.assertEqual(len([k for k in levels if k.startswith("LOD")]), level_count)
        if "original" in levels:
            self.assertEqual(levels["original"]["psnr"], 100.0, levels["original"])
            self.assertEqual(levels["original"]["ssim"], 1.0, levels["original"])
        for tag in sorted({k[:-len("LOD0")] for k in levels if k.endswith("LOD0")}):
            key, psnr = name + ("." + tag[:-1] if tag else ""), levels[tag + "LOD0"]["psnr"]
            floor = LOD0_PSNR_MEASURED[key] - LOD0_PSNR_MARGIN
            self.assertGreaterEqual(psnr, floor, "%s LOD0 PSNR %.2f dB is below its floor %.2f dB" % (key, psnr, floor))
            chain = [levels[tag + "LOD%d" % k]["psnr"] for k in range(len(levels)) if tag + "LOD%d" % k in levels]
            for k in range(1, len(chain)):
                self.assertLessEqual(chain[k], chain[k - 1] + LEVEL_ORDER_SLACK,
                                     "%s LOD%d renders %.2f dB, closer than LOD%d (%.2f dB)" % (key, k, chain[k], k - 1, chain[k - 1]))

    def test_seamball_and_draco(self):
        self.check("seamball", level_count=4)
        self.assertIn("draco.LOD0", {c["level"] for c in self.results["seamball"]["candidates"]})

    def test_hemisphere9(self):
        self.check("hemisphere9")

    def test_pbrscene_seams(self):
        self.check("pbrscene")
        seamed = [c for c in self.results["pbrscene"]["candidates"] if c["psnr_seam"] is not None]
        self.assertTrue(seamed, "no level shows a texture seam: the seam band is not measured")
        for c in seamed:
            self.assertGreater(c["seam_pixels"], 100, c["level"])
            self.assertGreaterEqual(c["psnr_seam"], c["psnr_fg"] - SEAM_BAND_MARGIN,
                                    "%s's seam band renders %.2f dB, the whole foreground %.2f dB"
                                    % (c["level"], c["psnr_seam"], c["psnr_fg"]))

    def test_duck(self):
        self.check("Duck")

    def test_avocado(self):
        self.check("Avocado")


if __name__ == "__main__":
    lt.main([ThreeChain])
