"""A flat-shaded asset keeps its facets on every level (issue 34, must-show), beside gltfpack.

`lodbake --ratio 0.5,0.1,0.02` on the make-samples facets gem (720 triangles, every corner
carrying its face's normal: hard edges everywhere, as in a flat-shaded low-poly export such as
ChrKnight). A coarse level has fewer, larger faces than the original, so the original's facets
can only reach it through the baked normal map. gltfpack `-sp` keeps the split normals of the
faces it keeps, along with the original texture. Each level k >= 1 is set beside npm gltfpack
`-sp -se 1` at the same triangle count: the `-si` ratio is searched until the counts match, or,
when no ratio gives that count, gltfpack's smallest output above it (lodbake_test.gltfpack_at with at_least). All of
them are rendered by three.js (scripts/render_three.py, 8 views, 256 px) and checked:

- LOD0 (the original's triangles and split normals on the original's texels) renders at
  LOD0_FLOOR_DB or more against the original (issue 34's bar);
- every level k >= 1 is at most THREE_MARGIN_DB below gltfpack's PSNR (issue 34's bar);
- on LOD1 and LOD2 the baked normal map is worth at least NORMAL_MAP_GAIN_DB: the same level
  rendered with its normalTexture removed scores that much lower. gltfpack's bar alone would not
  notice lost facets here, because stripping the normal map leaves LOD1 at 25.52 dB against
  gltfpack's 26.37 dB, which is inside the 2 dB margin. The 2% level (14 triangles, a 16x20 page)
  is too coarse for this check.

Default flags, as a user runs lodbake and as issue 34 states its bars. This test does not use
--lod0-density, unlike the quality benchmark, which uses it so that close-up renders compare
every level at LOD0's density. On this asset that flag changes nothing, because LOD0 keeps the
original's texels (an 88x72 page, from the 64x64 source texture) and no coarser page may hold
more texels than the level before it. With the flag the levels score 27.00 / 20.45 / 13.72 dB,
and with default flags 27.23 / 20.45 / 13.33 dB.

Measured at the time of writing: three.js dB, ours / gltfpack:
    LOD1 360 tris: 27.23 / 26.37; LOD2 72 tris: 20.45 / 14.80; LOD3 14 tris: 13.33 / 8.24 (38 tris).
    LOD0: 63.46. Normal-map gain: +1.71 dB on LOD1, +0.81 dB on LOD2.
About 60 s. Skips (77) without chromium, node, the node modules or npm gltfpack.
"""
import json
import os
import struct
import subprocess
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import lodbake_test as lt  # noqa: E402

RENDER = os.path.join(lt.SOURCE, "scripts/render_three.py")
RATIOS = "0.5,0.1,0.02"
THREE_MARGIN_DB = 2.0  # issue 34: "within 2 dB of gltfpack -sp at the same count or above it"
LOD0_FLOOR_DB = 35.0
NORMAL_MAP_GAIN_DB = 0.4  # the smallest measured gain is +0.81 dB (LOD2), so this leaves half of it as slack
NORMAL_MAP_LEVELS = (1, 2)


def without_normal_maps(path, out):
    """Writes `path` (a GLB) to `out` with every material's normalTexture removed."""
    g = lt.Gltf(path)
    for m in g.json.get("materials", []):
        m.pop("normalTexture", None)
    js = json.dumps(g.json).encode()
    js += b" " * ((4 - len(js) % 4) % 4)
    body = struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack("<II", len(g.bin), 0x004E4942) + g.bin
    with open(out, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)


class FlatShaded(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        lt.require_browser_chain(("three", "playwright-core"))
        if not os.path.exists(lt.tool("lodbake")):
            lt.skip("lodbake is not built")
        if not os.path.exists(lt.NPM_GLTFPACK):
            lt.skip("npm gltfpack is missing (cd scripts/node && npm ci)")
        cls.dir = lt.work_dir("flat_shaded")
        src = os.path.join(lt.make_samples(os.path.join(cls.dir, "samples")), "facets.glb")
        out, rep = os.path.join(cls.dir, "facets.lod.glb"), os.path.join(cls.dir, "facets.json")
        lt.run([lt.tool("lodbake"), "-i", src, "-o", out, "--ratio", RATIOS, "--report", rep, "-q"])
        with open(rep) as f:
            report = json.load(f)
        flat = os.path.join(cls.dir, "facets.no-normal-maps.lod.glb")
        without_normal_maps(out, flat)
        ids = [0] + lt.Gltf(out).json["nodes"][0].get("extensions", {}).get("MSFT_lod", {}).get("ids", [])
        cls.levels = []
        for k, level in enumerate(report["stages"][3]["levels"]):  # pack's
            e = {"lod": k, "triangles": level["triangles"], "ours": "%s#node=%d" % (out, ids[k])}
            if k > 0:
                e["gltfpack"], e["gltfpack_triangles"] = lt.gltfpack_at(src, level["triangles"], cls.dir, "facets", at_least=True)
            if k in NORMAL_MAP_LEVELS:
                e["flat"] = "%s#node=%d" % (flat, ids[k])
            cls.levels.append(e)
        candidates = [c for e in cls.levels for c in (e["ours"], e.get("gltfpack"), e.get("flat")) if c]
        batch, out_json = os.path.join(cls.dir, "batch.json"), os.path.join(cls.dir, "results.json")
        with open(batch, "w") as f:
            json.dump([{"reference": src, "candidates": candidates, "out": os.path.join(cls.dir, "renders")}], f, indent=1)
        p = subprocess.run([sys.executable, RENDER, "--batch", batch, "--views", "8", "--size", "256", "--json", out_json],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=600,
                           env=dict(os.environ, CHROMIUM=lt.CHROMIUM))
        if p.returncode != 0 and not os.path.exists(out_json):
            raise AssertionError("render_three.py failed (%d): %s" % (p.returncode, p.stderr[-3000:]))
        with open(out_json) as f:
            cls.psnr = {c["candidate"]: c["psnr"] for c in json.load(f)[0]["candidates"]}
        print("three.js, PSNR dB against the original: ours / gltfpack -sp -se 1 (its triangles) / ours without the normal map")
        for e in cls.levels:
            def db(key):
                return "%6.2f" % cls.psnr[e[key]] if key in e else "     -"
            print("  facets LOD%d %4d tris  %s / %s (%4s) / %s" % (e["lod"], e["triangles"], db("ours"), db("gltfpack"),
                                                                 e.get("gltfpack_triangles", "-"), db("flat")))
        sys.stdout.flush()

    def test_lod0(self):
        ours = self.psnr[self.levels[0]["ours"]]
        self.assertGreaterEqual(ours, LOD0_FLOOR_DB, "LOD0 renders at %.2f dB against the original" % ours)

    def test_levels_beside_gltfpack(self):
        self.assertEqual(len(self.levels), 4, "the chain has LOD0 and one level per ratio")
        for e in self.levels[1:]:
            with self.subTest(level=e["lod"]):
                self.assertGreaterEqual(e["gltfpack_triangles"], e["triangles"], "gltfpack's output has fewer triangles")
                ours, theirs = self.psnr[e["ours"]], self.psnr[e["gltfpack"]]
                self.assertGreaterEqual(ours, theirs - THREE_MARGIN_DB, "LOD%d: three.js %.2f dB, gltfpack %.2f dB at %d "
                                        "triangles (ours %d)" % (e["lod"], ours, theirs, e["gltfpack_triangles"], e["triangles"]))

    def test_normal_map_carries_the_facets(self):
        for e in self.levels:
            if "flat" not in e:
                continue
            with self.subTest(level=e["lod"]):
                ours, flat = self.psnr[e["ours"]], self.psnr[e["flat"]]
                self.assertGreaterEqual(ours - flat, NORMAL_MAP_GAIN_DB, "LOD%d: %.2f dB with its normal map, %.2f dB "
                                        "without" % (e["lod"], ours, flat))


if __name__ == "__main__":
    lt.main([FlatShaded])
