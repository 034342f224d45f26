#!/usr/bin/python3
"""Writes a GLB whose single mesh is the input's first mesh primitive subdivided N times (each
triangle -> 4 by edge midpoints) WITH its attributes: every float attribute (TEXCOORD_n,
NORMAL, TANGENT, COLOR_0) is interpolated at the midpoints (normals and tangents' xyz
renormalised, the tangent's handedness kept), and the primitive's material, textures, samplers
and images are copied (images embedded in the GLB). The mesh node's world transform is kept.
The benchmarks use it to make textured >= 1M-triangle inputs from small shared assets
(../shared/assets/Duck: 4,212 triangles -> 1.08M at N=4, 4.3M at N=5).
Needs numpy (Debian python3-numpy), hence /usr/bin/python3.
Usage: subdivide_textured.py IN.glb|IN.gltf OUT.glb N"""
import json
import os
import struct
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../tests/cli"))
from lodbake_test import Gltf  # noqa: E402

COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}
DTYPES = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}


class Source:
    """A glTF or GLB: JSON, buffers, accessors as numpy arrays, image bytes."""

    def __init__(self, path):
        self.dir = os.path.dirname(path)
        g = Gltf(path)  # JSON and buffer 0 (GLB chunk or external .bin)
        self.json = g.json
        if len(self.json.get("buffers", [])) > 1:
            sys.exit("subdivide_textured.py: %s: more than one buffer is not supported" % path)
        self.buffers = [g.bin]

    def view_bytes(self, index):
        v = self.json["bufferViews"][index]
        start = v.get("byteOffset", 0)
        return self.buffers[v["buffer"]][start: start + v["byteLength"]], v.get("byteStride")

    def accessor(self, index):
        acc = self.json["accessors"][index]
        if "sparse" in acc or "bufferView" not in acc:
            sys.exit("subdivide_textured.py: sparse or view-less accessors are not supported")
        comps = COMPONENTS[acc["type"]]
        dtype = np.dtype(DTYPES[acc["componentType"]])
        data, stride = self.view_bytes(acc["bufferView"])
        start = acc.get("byteOffset", 0)
        elem = comps * dtype.itemsize
        stride = stride or elem
        n = acc["count"]
        raw = np.frombuffer(data, dtype=np.uint8, count=(n - 1) * stride + elem if n else 0, offset=start)
        rows = np.lib.stride_tricks.as_strided(raw, shape=(n, elem), strides=(stride, 1)) if n else raw.reshape(0, elem)
        out = np.ascontiguousarray(rows).view(dtype).reshape(n, comps)
        if acc.get("normalized") and dtype.kind in "ui":
            out = out.astype(np.float64) / np.iinfo(dtype).max
        return out

    def image_bytes(self, image):
        if "bufferView" in image:
            return self.view_bytes(image["bufferView"])[0], image.get("mimeType", "image/png")
        uri = image["uri"]
        if uri.startswith("data:"):
            sys.exit("subdivide_textured.py: data URI images are not supported")
        mime = "image/jpeg" if uri.lower().endswith((".jpg", ".jpeg")) else "image/png"
        with open(os.path.join(self.dir, uri), "rb") as f:
            return f.read(), mime


def node_matrix(node):
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T
    t = np.array(node.get("translation", [0, 0, 0]), dtype=np.float64)
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    s = np.array(node.get("scale", [1, 1, 1]), dtype=np.float64)
    r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                  [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                  [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    m = np.eye(4)
    m[:3, :3] = r * s
    m[:3, 3] = t
    return m


def mesh_world_matrix(doc, mesh_index):
    """World matrix of the first node (depth first from the scene roots) that draws the mesh."""
    nodes = doc.get("nodes", [])
    scene = doc.get("scenes", [{}])[doc.get("scene", 0)] if doc.get("scenes") else {"nodes": list(range(len(nodes)))}
    stack = [(n, np.eye(4)) for n in reversed(scene.get("nodes", []))]
    while stack:
        n, parent = stack.pop()
        m = parent @ node_matrix(nodes[n])
        if nodes[n].get("mesh") == mesh_index:
            return m
        stack.extend((c, m) for c in reversed(nodes[n].get("children", [])))
    return np.eye(4)


def subdivide(attrs, idx):
    """One 1 -> 4 split: attrs maps name -> (n, k) float64 arrays; idx is (t, 3)."""
    n = len(next(iter(attrs.values())))
    a, b, c = idx[:, 0], idx[:, 1], idx[:, 2]
    edges = np.concatenate([np.stack([a, b], 1), np.stack([b, c], 1), np.stack([c, a], 1)])
    edges.sort(axis=1)
    key = edges[:, 0].astype(np.int64) * n + edges[:, 1]
    unique, inverse = np.unique(key, return_inverse=True)
    e0, e1 = unique // n, unique % n
    out = {name: np.concatenate([v, 0.5 * (v[e0] + v[e1])]) for name, v in attrs.items()}
    for name in ("NORMAL", "TANGENT"):
        if name in out:
            xyz = out[name][:, :3]
            length = np.linalg.norm(xyz, axis=1, keepdims=True)
            out[name][:, :3] = xyz / np.where(length > 0, length, 1)
    if "TANGENT" in out:
        out["TANGENT"][n:, 3] = np.where(attrs["TANGENT"][e0, 3] < 0, -1.0, 1.0)
    t = len(idx)
    mid = (inverse.reshape(3, t) + n).astype(np.uint32)
    ab, bc, ca = mid[0], mid[1], mid[2]
    new = np.stack([a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca], 1).reshape(-1, 3)
    return out, new.astype(np.uint32)


def write_glb(path, src, prim, attrs, idx, world):
    doc_src = src.json
    chunks, views, accessors = [], [], []

    def add_view(data, target=None):
        offset = sum(len(c) for c in chunks)
        chunks.append(data + b"\0" * ((4 - len(data) % 4) % 4))
        v = {"buffer": 0, "byteOffset": offset, "byteLength": len(data)}
        if target:
            v["target"] = target
        views.append(v)
        return len(views) - 1

    attributes = {}
    for name, v in attrs.items():
        arr = v.astype(np.float32)
        acc = {"bufferView": add_view(arr.tobytes(), 34962), "componentType": 5126, "count": len(arr),
               "type": {1: "SCALAR", 2: "VEC2", 3: "VEC3", 4: "VEC4"}[arr.shape[1]]}
        if name == "POSITION":
            acc["min"] = arr.min(axis=0).tolist()
            acc["max"] = arr.max(axis=0).tolist()
        accessors.append(acc)
        attributes[name] = len(accessors) - 1
    accessors.append({"bufferView": add_view(idx.astype(np.uint32).tobytes(), 34963), "componentType": 5125,
                      "count": int(idx.size), "type": "SCALAR"})
    primitive = {"attributes": attributes, "indices": len(accessors) - 1, "mode": 4}
    doc = {"asset": {"version": "2.0", "generator": "lodbake scripts/subdivide_textured.py"},
           "scene": 0, "scenes": [{"nodes": [0]}],
           "nodes": [{"mesh": 0, "matrix": world.T.reshape(-1).tolist()}],
           "meshes": [{"primitives": [primitive]}]}
    if "material" in prim:
        doc["materials"] = [doc_src["materials"][prim["material"]]]
        primitive["material"] = 0
        for key in ("textures", "samplers"):
            if key in doc_src:
                doc[key] = doc_src[key]
        images = []
        for image in doc_src.get("images", []):
            data, mime = src.image_bytes(image)
            images.append({"bufferView": add_view(data), "mimeType": mime})
        if images:
            doc["images"] = images
        used = doc_src.get("extensionsUsed", [])
        if used:
            doc["extensionsUsed"] = used
    doc["accessors"] = accessors
    doc["bufferViews"] = views
    body = b"".join(chunks)
    doc["buffers"] = [{"byteLength": len(body)}]
    js = json.dumps(doc).encode()
    js += b" " * ((4 - len(js) % 4) % 4)
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(js) + 8 + len(body)))
        f.write(struct.pack("<II", len(js), 0x4E4F534A) + js)
        f.write(struct.pack("<II", len(body), 0x004E4942) + body)
    os.replace(tmp, path)


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    src = Source(sys.argv[1])
    prim = src.json["meshes"][0]["primitives"][0]
    if prim.get("mode", 4) != 4:
        sys.exit("subdivide_textured.py: %s: the first primitive is not a triangle list" % sys.argv[1])
    attrs = {}
    for name, a in prim["attributes"].items():
        if name.startswith(("JOINTS_", "WEIGHTS_")):
            continue
        attrs[name] = src.accessor(a).astype(np.float64)
    n = len(attrs["POSITION"])
    idx = src.accessor(prim["indices"]).reshape(-1, 3).astype(np.uint32) if "indices" in prim \
        else np.arange(n, dtype=np.uint32).reshape(-1, 3)
    for _ in range(int(sys.argv[3])):
        attrs, idx = subdivide(attrs, idx)
    write_glb(sys.argv[2], src, prim, attrs, idx, mesh_world_matrix(src.json, 0))
    print("%s: %d triangles, %d vertices" % (sys.argv[2], len(idx), len(attrs["POSITION"])))


if __name__ == "__main__":
    main()
