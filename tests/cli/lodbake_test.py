"""Shared helpers for lodbake's CLI tests (python3 stdlib only).

Environment (set by tests/CMakeLists.txt): LODBAKE_BIN (built executables), LODBAKE_SOURCE,
LODBAKE_SHARED (../shared, may be absent), LODBAKE_WORK (scratch folder for this test).
A test that cannot run here exits 77, which ctest reports as skipped.
"""
import array
import json
import os
import shutil
import struct
import subprocess
import sys

BIN = os.environ.get("LODBAKE_BIN", os.path.join(os.path.dirname(__file__), "../../build/bin"))
SOURCE = os.environ.get("LODBAKE_SOURCE", os.path.join(os.path.dirname(__file__), "../.."))
SHARED = os.environ.get("LODBAKE_SHARED", os.path.join(SOURCE, "../shared"))
WORK = os.environ.get("LODBAKE_WORK", "/tmp/lodbake-test")
ASSETS = os.path.join(SHARED, "assets")
BAD_INPUTS = os.path.join(SHARED, "bad-inputs")
SKIP = 77

# The real assets of ../shared/assets, by name.
ASSET_FILES = {
    "Duck": "Duck/Duck.glb",
    "Avocado": "Avocado/Avocado.gltf",
    "BoxTextured": "BoxTextured/BoxTextured.glb",
    "CesiumMilkTruck": "CesiumMilkTruck/CesiumMilkTruck.glb",
    "2CylinderEngine": "2CylinderEngine/2CylinderEngine.glb",
    "StanfordBunny": "StanfordBunny/StanfordBunny.glb",
}


def skip(reason):
    print("SKIPPED: " + reason)
    sys.exit(SKIP)


def require_assets():
    if not os.path.isdir(ASSETS):
        skip("../shared/assets is absent (a user's clone has no ../shared); nothing to test here")
    return {name: os.path.join(ASSETS, rel) for name, rel in ASSET_FILES.items()}


def require_tools(*names):
    """Skips (exit 77) unless every named tool is built."""
    for t in names:
        if not os.path.exists(tool(t)):
            skip(t + " is not built")


def work_dir(name=""):
    d = os.path.join(WORK, name)
    if os.path.isdir(d):
        shutil.rmtree(d)
    os.makedirs(d, exist_ok=True)
    return d


def tool(name):
    return os.path.join(BIN, name)


def run(args, check=True, timeout=1200):
    """Runs a command; returns CompletedProcess with text stdout/stderr."""
    p = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=timeout)
    if check and p.returncode != 0:
        raise AssertionError("command failed (%d): %s\nstdout: %s\nstderr: %s"
                             % (p.returncode, " ".join(args), p.stdout[-2000:], p.stderr[-2000:]))
    return p


def pack(uv, out, flags):
    """pack `uv` into `out` with `flags` and a report beside it (out + ".json"); returns (out, report)."""
    rep = out + ".json"
    run([tool("pack"), "-i", uv, "-o", out, "--report", rep] + list(flags))
    return out, rep


def parameterized_samples(out_dir, names, size="512"):
    """make-samples into out_dir, then simplify (50/10/2%) and parameterize (--size `size`) each
    named sample; returns {name: path of its .uv.glb}."""
    make_samples(out_dir)
    uv = {}
    for n in names:
        src = os.path.join(out_dir, n + ".glb")
        mr = os.path.join(out_dir, n + ".mr.glb")
        uv[n] = os.path.join(out_dir, n + ".uv.glb")
        run([tool("simplify"), "-i", src, "-o", mr, "--ratio", "0.5,0.1,0.02", "--quiet"])
        run([tool("parameterize"), "-i", mr, "-o", uv[n], "--size", size, "--quiet"])
    return uv


def make_samples(out_dir):
    run([tool("make-samples"), out_dir])
    return out_dir


NODE_MODULES = os.path.join(SOURCE, "scripts/node/node_modules")
CHROMIUM = os.environ.get("CHROMIUM", "/usr/bin/chromium")


def require_browser_chain(node_modules):
    """Skips unless the chain tools, Debian's chromium, node and these scripts/node modules exist."""
    for t in ("simplify", "parameterize", "pack", "make-samples"):
        if not os.path.exists(tool(t)):
            skip(t + " is not built")
    if not os.path.exists(CHROMIUM):
        skip("chromium is missing (apt-get install chromium; scripts/setup-debian.sh)")
    if shutil.which("node") is None:
        skip("node is missing")
    for m in node_modules:
        if not os.path.isdir(os.path.join(NODE_MODULES, m)):
            skip("scripts/node/node_modules/%s is missing (cd scripts/node && npm ci)" % m)


BROWSER_PAGE_DIR = os.path.join(SOURCE, "tests/browser")


def babylon_view(test, port, model, shot, animate=False):
    """Babylon.js's view of MODEL (served on PORT beside tests/browser/index.html): the page's result
    dict. Headless SwiftShader now and then stalls before the loader completes (about one run in
    fifty here, at no fixed step); the page names the step, and a stalled run is tried once more."""
    url = "http://127.0.0.1:%d/index.html?model=%s%s" % (port, os.path.basename(model), "&animate=1" if animate else "")
    env = dict(os.environ, NODE_PATH=NODE_MODULES, CHROMIUM=CHROMIUM)
    for attempt in (1, 2):
        p = subprocess.run(["node", os.path.join(BROWSER_PAGE_DIR, "run.js"), url, shot], stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True, timeout=600, env=env)
        r = json.loads(p.stdout.strip().splitlines()[-1]) if p.returncode == 0 else None
        stalled = r is None or (not r["ok"] and "did not finish" in " ".join(r["errors"]))
        if not stalled or attempt == 2:
            break
        print("Babylon stalled on %s (%s); trying once more" % (os.path.basename(model), p.stderr.strip()[-300:] if r is None else r["errors"]))
    test.assertEqual(p.returncode, 0, p.stderr[-3000:])
    test.assertTrue(r["ok"], r)
    test.assertEqual(r["errors"], [], r)
    return r


VALIDATOR = os.path.join(SOURCE, "scripts/node/validate.js")


def validator_available():
    return shutil.which("node") is not None and os.path.isdir(os.path.join(SOURCE, "scripts/node/node_modules/gltf-validator"))


def validate(path):
    """Khronos glTF-Validator report summary for one file: dict with errors, warnings, messages."""
    p = run(["node", VALIDATOR, path], check=False)
    if p.returncode not in (0, 1):
        raise AssertionError("validator could not read %s: %s" % (path, p.stderr))
    return json.loads(p.stdout.strip().splitlines()[-1])


def assert_no_validator_errors(tc, files):
    """For a unittest.TestCase: glTF-Validator reports 0 errors on every file (one subTest each);
    skips the test when the validator is not installed."""
    if not validator_available():
        tc.skipTest("glTF-Validator not installed (scripts/setup-debian.sh installs it)")
    for path in files:
        with tc.subTest(file=os.path.basename(path)):
            r = validate(path)
            tc.assertEqual(r["errors"], 0, r["messages"])


class Gltf:
    """A glTF or GLB file's JSON and binary buffer 0, with accessor reading."""

    def __init__(self, path):
        self.path = path
        with open(path, "rb") as f:
            data = f.read()
        self.bin = b""
        if data[:4] == b"glTF":
            length = struct.unpack_from("<I", data, 8)[0]
            off = 12
            while off < length:
                clen, ctype = struct.unpack_from("<II", data, off)
                chunk = data[off + 8: off + 8 + clen]
                if ctype == 0x4E4F534A:
                    self.json = json.loads(chunk.decode("utf-8"))
                elif ctype == 0x004E4942:
                    self.bin = chunk
                off += 8 + clen
        else:
            self.json = json.loads(data.decode("utf-8"))
            buffers = self.json.get("buffers", [])
            if buffers and "uri" in buffers[0] and not buffers[0]["uri"].startswith("data:"):
                with open(os.path.join(os.path.dirname(path), buffers[0]["uri"]), "rb") as f:
                    self.bin = f.read()

    def accessor(self, index):
        """Accessor values as a flat list (uint32/uint16/uint8/float, non-sparse, buffer 0)."""
        acc = self.json["accessors"][index]
        view = self.json["bufferViews"][acc["bufferView"]]
        comps = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}[acc["type"]]
        code = {5121: "B", 5123: "H", 5125: "I", 5126: "f", 5120: "b", 5122: "h"}[acc["componentType"]]
        size = array.array(code).itemsize
        start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
        stride = view.get("byteStride", size * comps)
        n = acc["count"]
        if stride == size * comps:
            a = array.array(code)
            a.frombytes(self.bin[start: start + n * comps * size])
            return list(a)
        out = []
        for i in range(n):
            a = array.array(code)
            a.frombytes(self.bin[start + i * stride: start + i * stride + comps * size])
            out.extend(a)
        return out

    def multires(self):
        return self.json.get("extensions", {}).get("LODBAKE_multires")

    def mesh_triangle_count(self, mesh_index):
        n = 0
        for prim in self.json["meshes"][mesh_index]["primitives"]:
            if "indices" in prim:
                n += self.json["accessors"][prim["indices"]]["count"] // 3
            else:
                n += self.json["accessors"][prim["attributes"]["POSITION"]]["count"] // 3
        return n


# UV fold checks on written glTF UVs (independent of the tools' own counts).

def glb_with_json(glb, edit):
    """The GLB `glb` with its JSON chunk changed by edit(doc); the binary chunk is kept."""
    length = struct.unpack_from("<I", glb, 12)[0]
    doc = json.loads(glb[20:20 + length])
    edit(doc)
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    rest = glb[20 + length:]
    return struct.pack("<IIIII", 0x46546C67, 2, 20 + len(text) + len(rest), len(text), 0x4E4F534A) + text + rest


def lod_levels(g):
    """Levels of an MSFT_lod chain (a Gltf): node 0 and the nodes its MSFT_lod lists. Other nodes
    (a rig's joints, lights, cameras) are not levels."""
    node0 = g.json["nodes"][0]
    return 1 + len(node0.get("extensions", {}).get("MSFT_lod", {}).get("ids", []))


def level_uv_triangles(g, mesh_index):
    """UV triangles (glTF convention) of every primitive of a mesh."""
    out = []
    for prim in g.json["meshes"][mesh_index]["primitives"]:
        uv = g.accessor(prim["attributes"]["TEXCOORD_0"])
        idx = g.accessor(prim["indices"])
        for i in range(0, len(idx), 3):
            out.append([(uv[2 * idx[i + k]], uv[2 * idx[i + k] + 1]) for k in range(3)])
    return out


def signed_area(t):
    # glTF v points down: a front-facing triangle has positive area with v flipped.
    (ax, ay), (bx, by), (cx, cy) = t
    return 0.5 * ((bx - ax) * (ay - cy) - (ay - by) * (cx - ax))


def count_flips(tris):
    return sum(1 for t in tris if not signed_area(t) > 0)


# Overlap tolerance in atlas units: UVs are stored as float32 (an ulp is 6e-8 near 1), and a seam
# corner reached by two computations (a chart's vertex, a level island's projected corner) can
# differ by a few ulps; 5e-7 is a 500th of a texel on a 4096 page.
def _overlap(a, b, eps=5e-7):
    for t in (a, b):
        for k in range(3):
            ex, ey = t[(k + 1) % 3][0] - t[k][0], t[(k + 1) % 3][1] - t[k][1]
            n = (ex * ex + ey * ey) ** 0.5
            if n == 0:
                continue
            nx, ny = -ey / n, ex / n
            pa = [nx * p[0] + ny * p[1] for p in a]
            pb = [nx * p[0] + ny * p[1] for p in b]
            if max(pa) <= min(pb) + eps or max(pb) <= min(pa) + eps:
                return False
    return True


def count_overlaps(tris, grid=64):
    """Triangles whose UV interior intersects another's (uniform grid, separating axes)."""
    cells = {}
    for i, t in enumerate(tris):
        xs, ys = [p[0] for p in t], [p[1] for p in t]
        for y in range(int(min(ys) * grid), int(max(ys) * grid) + 1):
            for x in range(int(min(xs) * grid), int(max(xs) * grid) + 1):
                cells.setdefault((x, y), []).append(i)
    bad = set()
    for items in cells.values():
        for a in range(len(items)):
            for b in range(a + 1, len(items)):
                i, j = items[a], items[b]
                if (i in bad and j in bad) or signed_area(tris[i]) <= 0 or signed_area(tris[j]) <= 0:
                    continue
                if _overlap(tris[i], tris[j]):
                    bad.update((i, j))
    return len(bad)


def main(test_case_classes):
    """Runs unittest test cases and exits with a ctest-friendly status."""
    import unittest
    suite = unittest.TestSuite()
    for c in test_case_classes:
        suite.addTests(unittest.defaultTestLoader.loadTestsFromTestCase(c))
    result = unittest.TextTestRunner(verbosity=2).run(suite)
    sys.exit(0 if result.wasSuccessful() else 1)


NPM_GLTFPACK = os.path.join(NODE_MODULES, ".bin", "gltfpack")


def gltfpack_at(src, triangles, out_dir, name, at_least=False):
    """npm gltfpack -sp -se 1 at the -si ratio whose output has `triangles` triangles (bisection on
    the ratio). When no ratio gives that count: the closest count, or with `at_least` the smallest
    count above it (a harder bar for the level compared). Returns (path, triangles)."""
    tried = {}

    def run_at(ratio):
        if ratio not in tried:
            out = os.path.join(out_dir, "%s.gltfpack.%.6f.glb" % (name, ratio))
            p = run([NPM_GLTFPACK, "-i", src, "-o", out, "-sp", "-se", "1", "-si", "%.6f" % ratio, "-v"])
            line = next(l for l in p.stdout.splitlines() if l.startswith("output: ") and "triangles" in l)
            tried[ratio] = (out, int(line.split("(")[1].split()[0]))
        return tried[ratio]

    lo, hi = 0.0, 1.0
    best = run_at(1.0) if at_least else None
    for _ in range(20):
        mid = 0.5 * (lo + hi)
        out, count = run_at(mid)
        better = triangles <= count < best[1] if at_least else best is None or abs(count - triangles) < abs(best[1] - triangles)
        if better:
            best = (out, count)
        if count == triangles:
            break
        lo, hi = (mid, hi) if count < triangles else (lo, mid)
    return best
