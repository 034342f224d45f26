"""CLI test: a texture-refine rank whose layout does not validate is dropped, and the run goes on
(issue 35: "A rank that does not validate must be dropped (T0 serves those levels), never fail the
run").

The input is real, not injected: `graded.glb`, written here at test time (deterministic, 6,192
triangles, 0 validator errors), is a saddle-shaped disk whose 65 rings shrink geometrically
toward its centre (radius 0.75^k, k = 0..64, so the innermost is 1e-8 of the rim), as a
tessellator refining toward a singular point leaves a mesh. An atlas has one texel density, so
the inner rings' triangles are far smaller than a float UV step in [0, 1]. parameterize checks the
atlas as written (float UVs): a face that comes out flipped and that nudgeRoundedSliverCorners
cannot turn within its eight steps leaves its chart for a chart of its own, and the atlas is
packed again, up to four times. Each packing moves every chart and the carved charts take area
(the density drops), so further rings fall to float precision and fold anew: the geometric grading
never runs out of them. parameterize (T0) warns about the faces it carved and the level triangles
it keeps folded; every rank-1 candidate (split charts, no merging) still has flipped triangles
after the last pass (19 to 42 here), so solveRankLayout throws SolverError and refineTextures
drops the rank: before that catch, `texture-refine error: rank 1: 42 flipped and 0 overlapping UV
triangles`, exit 4, as on the user's CAD assembly.

Checked for the four tools (simplify -> parameterize -> texture-refine -> pack) and for the
one-process `lodbake`: exit 0; the report's rejectedCandidates say "its layout does not validate";
stderr holds only the tool's own warning lines, one per dropped rank among them; the refined file
carries no dropped rank; every LOD of the packed chain uses T0 or a remaining rank valid for it;
gltf-validator 0 errors on the input and the chains.
"""
import json
import math
import os
import struct
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import lodbake_test as lt  # noqa: E402
from test_pack import check_chain  # noqa: E402

DOES_NOT_VALIDATE = "its layout does not validate ("
DROPPED = "dropped: rank "


def graded_disk(n=48, rings=64, q=0.75):
    """Positions and CCW triangles of the disk: a centre vertex, then rings k = 0..rings of n
    vertices at radius q^(rings - k) (every other ring turned half a step), on the saddle
    z = 0.4 r cos(2 theta) + 0.3 r^2."""
    pos = [(0.0, 0.0, 0.0)]
    for k in range(rings + 1):
        r = q ** (rings - k)
        for j in range(n):
            t = 2 * math.pi * (j + 0.5 * (k % 2)) / n
            pos.append((r * math.cos(t), r * math.sin(t), 0.4 * r * math.cos(2 * t) + 0.3 * r * r))

    def v(k, j):
        return 1 + k * n + j % n

    tris = [(0, v(0, j), v(0, j + 1)) for j in range(n)]
    for k in range(rings):
        for j in range(n):
            if k % 2 == 0:
                tris += [(v(k, j), v(k + 1, j), v(k, j + 1)), (v(k, j + 1), v(k + 1, j), v(k + 1, j + 1))]
            else:
                tris += [(v(k, j), v(k + 1, j), v(k + 1, j + 1)), (v(k, j), v(k + 1, j + 1), v(k, j + 1))]
    return pos, tris


def write_glb(path, pos, tris):
    """One primitive (POSITION, NORMAL from the faces around each vertex, uint32 indices) with a
    plain base-colour material."""
    nrm = [[0.0, 0.0, 0.0] for _ in pos]
    for tri in tris:
        a, b, c = (pos[i] for i in tri)
        e1 = [b[i] - a[i] for i in range(3)]
        e2 = [c[i] - a[i] for i in range(3)]
        cr = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0])
        ln = math.sqrt(sum(x * x for x in cr)) or 1.0
        for i in tri:
            for d in range(3):
                nrm[i][d] += cr[d] / ln
    nrm = [[x / (math.sqrt(sum(y * y for y in m)) or 1.0) for x in m] for m in nrm]
    chunks = [b"".join(struct.pack("<3f", *p) for p in pos), b"".join(struct.pack("<3f", *m) for m in nrm),
              b"".join(struct.pack("<3I", *t) for t in tris)]
    views, blob = [], b""
    for k, c in enumerate(chunks):
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(c), "target": 34963 if k == 2 else 34962})
        blob += c
    lo = [min(float(struct.unpack("<f", struct.pack("<f", p[d]))[0]) for p in pos) for d in range(3)]
    hi = [max(float(struct.unpack("<f", struct.pack("<f", p[d]))[0]) for p in pos) for d in range(3)]
    doc = {
        "asset": {"version": "2.0", "generator": "lodbake tests/cli/test_rank_fallback.py"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "name": "graded"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.5, 0.3, 1.0], "metallicFactor": 0.0}}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3", "min": lo, "max": hi},
                      {"bufferView": 1, "componentType": 5126, "count": len(pos), "type": "VEC3"},
                      {"bufferView": 2, "componentType": 5125, "count": 3 * len(tris), "type": "SCALAR"}],
        "bufferViews": views, "buffers": [{"byteLength": len(blob)}],
    }
    js = json.dumps(doc, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    blob += b"\0" * (-len(blob) % 4)
    with open(path, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 28 + len(js) + len(blob)))
        f.write(struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack("<II", len(blob), 0x004E4942) + blob)


class RankFallback(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        lt.require_tools("simplify", "parameterize", "texture-refine", "pack", "lodbake")
        cls.work = lt.work_dir("rank_fallback")
        cls.src = os.path.join(cls.work, "graded.glb")
        pos, tris = graded_disk()
        write_glb(cls.src, pos, tris)

    def check_dropped(self, refine, stderr, prefix):
        """The texture-refine report `refine` rejects at least one candidate because its layout does
        not validate, and says so in a warning; `stderr` holds only `prefix` warning lines, one
        per dropped rank among them. Returns the ranks kept."""
        bad = [x for x in refine["rejectedCandidates"] if x["reason"].startswith(DOES_NOT_VALIDATE)]
        self.assertGreaterEqual(len(bad), 1, refine["rejectedCandidates"])
        for x in bad:
            self.assertRegex(x["reason"],
                             r"^its layout does not validate \(rank \d+: \d+ flipped and \d+ overlapping UV triangles\)$")
        lines = stderr.splitlines()
        self.assertTrue(lines)
        for line in lines:
            self.assertTrue(line.startswith(prefix + " warning: "), "not the tool's own warning line: %r" % line)
        dropped = [w for w in refine["warnings"] if DROPPED in w]
        self.assertEqual(len(dropped), len(bad), refine["warnings"])
        for x, w in zip(bad, dropped):
            self.assertRegex(w, r"^rank \d+ from level %d dropped: rank \d+: \d+ flipped and \d+ overlapping UV triangles; "
                                r"the coarser ranks serve its levels$" % x["level"])
            self.assertIn(w, stderr)
        kept = refine["ranks"]
        self.assertEqual([k["rank"] for k in kept], list(range(len(kept))))
        return kept

    def check_levels(self, pack_report, kept):
        """Every LOD textured by T0 or a kept rank whose valid levels include it."""
        levels = pack_report["levels"]
        self.assertGreaterEqual(len(levels), 2)
        for k, lv in enumerate(levels):
            r = lv["textureRank"]
            self.assertLess(r, len(kept), "LOD%d uses a dropped rank" % k)
            lo, hi = kept[r]["validLevels"]
            self.assertTrue(lo <= k <= hi, "LOD%d: rank %d serves levels %d..%d" % (k, r, lo, hi))

    def test_input_is_valid(self):
        lt.assert_no_validator_errors(self, [self.src])

    def test_four_tools(self):
        base = os.path.join(self.work, "graded")
        mr, uv, tex, lod = base + ".mr.glb", base + ".uv.glb", base + ".tex.glb", base + ".lod.glb"
        lt.run([lt.tool("simplify"), "-i", self.src, "-o", mr, "--ratio", "0.5,0.1,0.02", "--quiet"])
        lt.run([lt.tool("parameterize"), "-i", mr, "-o", uv])
        p = lt.run([lt.tool("texture-refine"), "-i", uv, "-o", tex, "--report", tex + ".json"])
        with open(tex + ".json") as f:
            refine = json.load(f)
        kept = self.check_dropped(refine, p.stderr, "texture-refine")
        # The refined file carries the kept ranks only.
        h = lt.Gltf(tex).multires()["textureHierarchy"]
        self.assertEqual(len(h.get("ranks", [])), len(kept) - 1)
        p = lt.run([lt.tool("pack"), "-i", tex, "-o", lod, "--report", lod + ".json", "--max-size", "512"])
        self.assertEqual(p.stderr, "")
        with open(lod + ".json") as f:
            packed = json.load(f)
        check_chain(self, lod, lod + ".json")
        self.check_levels(packed, kept)
        lt.assert_no_validator_errors(self, [lod])

    def test_lodbake(self):
        out = os.path.join(self.work, "graded.one.lod.glb")
        p = lt.run([lt.tool("lodbake"), self.src, "-o", out, "--report", out + ".json", "--max-size", "512"])
        with open(out + ".json") as f:
            rep = json.load(f)
        stages = {s["tool"]: s for s in rep["stages"]}
        kept = self.check_dropped(stages["texture-refine"], p.stderr, "lodbake")
        for w in stages["texture-refine"]["warnings"]:
            self.assertIn("lodbake warning: texture-refine: " + w, p.stderr.splitlines())
        check_chain(self, out, None)
        self.check_levels(stages["pack"], kept)
        lt.assert_no_validator_errors(self, [out])


if __name__ == "__main__":
    lt.main([RankFallback])
