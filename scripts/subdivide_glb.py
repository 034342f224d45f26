#!/usr/bin/env python3
"""Writes a GLB whose single mesh is the input's first triangle mesh with its positions
subdivided N times (each triangle -> 4 by edge midpoints). Used by the benchmarks to make
>= 1M-triangle inputs from ../shared/assets/StanfordBunny (69,451 triangles -> 1.1M at N=2).
Usage: subdivide_glb.py IN.glb OUT.glb [N]"""
import array
import json
import struct
import sys

sys.path.insert(0, __import__("os").path.join(__import__("os").path.dirname(__file__), "../tests/cli"))
from lodbake_test import Gltf  # noqa: E402


def read_mesh(path):
    g = Gltf(path)
    prim = g.json["meshes"][0]["primitives"][0]
    pos = g.accessor(prim["attributes"]["POSITION"])
    idx = g.accessor(prim["indices"]) if "indices" in prim else list(range(len(pos) // 3))
    return pos, idx


def subdivide(pos, idx):
    pos = list(pos)
    mid = {}

    def midpoint(a, b):
        key = (a, b) if a < b else (b, a)
        m = mid.get(key)
        if m is None:
            m = len(pos) // 3
            pos.extend((pos[3 * a + k] + pos[3 * b + k]) * 0.5 for k in range(3))
            mid[key] = m
        return m

    out = []
    for t in range(0, len(idx), 3):
        a, b, c = idx[t], idx[t + 1], idx[t + 2]
        ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
        out += [a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca]
    return pos, out


def write_glb(path, pos, idx):
    p = array.array("f", pos).tobytes()
    i = array.array("I", idx).tobytes()
    n = len(pos) // 3
    mins = [min(pos[k::3]) for k in range(3)]
    maxs = [max(pos[k::3]) for k in range(3)]
    doc = {
        "asset": {"version": "2.0", "generator": "lodbake scripts/subdivide_glb.py"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3", "min": mins, "max": maxs},
            {"bufferView": 1, "componentType": 5125, "count": len(idx), "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(p), "target": 34962},
                        {"buffer": 0, "byteOffset": len(p), "byteLength": len(i), "target": 34963}],
        "buffers": [{"byteLength": len(p) + len(i)}],
    }
    js = json.dumps(doc).encode()
    js += b" " * ((4 - len(js) % 4) % 4)
    bin_ = p + i
    total = 12 + 8 + len(js) + 8 + len(bin_)
    with open(path, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, total))
        f.write(struct.pack("<II", len(js), 0x4E4F534A) + js)
        f.write(struct.pack("<II", len(bin_), 0x004E4942) + bin_)


if __name__ == "__main__":
    pos, idx = read_mesh(sys.argv[1])
    for _ in range(int(sys.argv[3]) if len(sys.argv) > 3 else 2):
        pos, idx = subdivide(pos, idx)
    write_glb(sys.argv[2], pos, idx)
    print("%s: %d triangles, %d vertices" % (sys.argv[2], len(idx) // 3, len(pos) // 3))
