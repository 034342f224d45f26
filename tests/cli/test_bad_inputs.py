"""Every tool rejects bad input with a one-line error naming the file, a documented non-zero exit
code, no crash, no hang and no output file. Also the usage-error table of the CLI kit."""
import array
import base64
import json
import os
import struct
import unittest

import lodbake_test as lt

# Every tool that reads a glTF, with the flags it needs besides -i / -o.
TOOLS_WITH_IO = {"simplify": ["--ratio", "0.5"], "agsphere-build": ["--ratio", "0.5"], "parameterize": [],
                 "texture-refine": [], "pack": []}


def minimal_gltf(positions, indices, extra=None):
    """A one-triangle-list glTF with an embedded data-URI buffer."""
    p = array.array("f", positions).tobytes()
    i = array.array("I", indices).tobytes()
    doc = {
        "asset": {"version": "2.0"},
        "scenes": [{"nodes": [0]}], "scene": 0, "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(positions) // 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 1]},
            {"bufferView": 1, "componentType": 5125, "count": len(indices), "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteLength": len(p)}, {"buffer": 0, "byteOffset": len(p), "byteLength": len(i)}],
        "buffers": [{"byteLength": len(p) + len(i),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(p + i).decode()}],
    }
    if extra:
        doc.update(extra)
    return json.dumps(doc)


class BadInputs(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = lt.work_dir("bad")
        cls.cases = {}  # name -> path
        quad = [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0]

        def put(name, data, mode="w"):
            path = os.path.join(cls.dir, name)
            with open(path, mode) as f:
                f.write(data)
            cls.cases[name] = path

        put("empty.glb", b"", "wb")
        put("empty.gltf", "")
        put("not-json.gltf", "this is not json {")
        put("nan.gltf", minimal_gltf([0, 0, 0, float("nan"), 0, 0, 1, 1, 0], [0, 1, 2]))
        put("inf.gltf", minimal_gltf([0, 0, 0, float("inf"), 0, 0, 1, 1, 0], [0, 1, 2]))
        put("index-out-of-range.gltf", minimal_gltf(quad, [0, 1, 2, 0, 2, 7]))
        put("required-extension.gltf", minimal_gltf(quad, [0, 1, 2, 0, 2, 3],
                                                    {"extensionsUsed": ["EXT_lodbake_nonexistent"],
                                                     "extensionsRequired": ["EXT_lodbake_nonexistent"]}))
        put("no-triangles.gltf", json.dumps({"asset": {"version": "2.0"}, "scenes": [{"nodes": []}], "scene": 0}))
        # Found by fuzzing: an image whose bufferView runs past its buffer (tinygltf hands the
        # bytes over unchecked), a primitive mode outside 0..6, and a GLB whose buffer claims 0
        # bytes (tinygltf throws std::out_of_range).
        image_doc = json.loads(minimal_gltf(quad, [0, 1, 2, 0, 2, 3]))
        image_doc["bufferViews"].append({"buffer": 0, "byteOffset": 8, "byteLength": 10 ** 9})
        image_doc["images"] = [{"bufferView": 2, "mimeType": "image/png"}]
        put("image-view-past-buffer.gltf", json.dumps(image_doc))
        # Found by fuzzing under AddressSanitizer: a buffer URI naming a directory (tinygltf sized
        # its read from tellg's -1).
        dir_doc = json.loads(minimal_gltf(quad, [0, 1, 2, 0, 2, 3]))
        dir_doc["buffers"][0]["uri"] = "."
        put("buffer-uri-directory.gltf", json.dumps(dir_doc))
        mode_doc = json.loads(minimal_gltf(quad, [0, 1, 2, 0, 2, 3]))
        mode_doc["meshes"][0]["primitives"][0]["mode"] = 4000
        put("invalid-mode.gltf", json.dumps(mode_doc))
        # EXT_mesh_gpu_instancing whose attributes disagree on the instance count, and a node
        # naming a light that does not exist.
        inst_doc = json.loads(minimal_gltf(quad, [0, 1, 2, 0, 2, 3]))
        trs = array.array("f", [0, 0, 0, 2, 0, 0, 1, 1, 1]).tobytes()
        inst_doc["buffers"].append({"byteLength": len(trs), "uri": "data:application/octet-stream;base64," +
                                    base64.b64encode(trs).decode()})
        inst_doc["bufferViews"].append({"buffer": 1, "byteLength": len(trs)})
        inst_doc["accessors"] += [{"bufferView": 2, "componentType": 5126, "count": 2, "type": "VEC3"},
                                  {"bufferView": 2, "byteOffset": 24, "componentType": 5126, "count": 1, "type": "VEC3"}]
        inst_doc["nodes"][0]["extensions"] = {"EXT_mesh_gpu_instancing": {"attributes": {"TRANSLATION": 2, "SCALE": 3}}}
        inst_doc["extensionsUsed"] = ["EXT_mesh_gpu_instancing"]
        put("instancing-counts.gltf", json.dumps(inst_doc))
        light_doc = json.loads(minimal_gltf(quad, [0, 1, 2, 0, 2, 3]))
        light_doc["nodes"].append({"extensions": {"KHR_lights_punctual": {"light": 3}}})
        light_doc["scenes"][0]["nodes"].append(1)
        light_doc["extensions"] = {"KHR_lights_punctual": {"lights": [{"type": "point"}]}}
        light_doc["extensionsUsed"] = ["KHR_lights_punctual"]
        put("light-out-of-range.gltf", json.dumps(light_doc))
        # A valid GLB of our own, then truncated at several places.
        good = os.path.join(cls.dir, "good.gltf")
        with open(good, "w") as f:
            f.write(minimal_gltf(quad, [0, 1, 2, 0, 2, 3]))
        glb = os.path.join(cls.dir, "good.glb")
        lt.run([lt.tool("simplify"), "-i", good, "-o", glb, "--ratio", "0.5", "--quiet"])
        with open(glb, "rb") as f:
            data = f.read()
        for frac in (0.1, 0.5, 0.9):
            put("truncated-%d.glb" % int(frac * 100), data[: int(len(data) * frac)], "wb")
        put("bad-magic-length.glb", struct.pack("<III", 0x46546C67, 2, 10 ** 9) + data[12:], "wb")
        put("zero-length-buffer.glb", lt.glb_with_json(data, lambda doc: doc["buffers"][0].update(byteLength=0)), "wb")
        if os.path.isdir(lt.BAD_INPUTS):
            for name in sorted(os.listdir(lt.BAD_INPUTS)):
                if name.endswith((".gltf", ".glb")):
                    cls.cases["shared/" + name] = os.path.join(lt.BAD_INPUTS, name)
        else:
            print("note: ../shared/bad-inputs absent; testing only the files this test makes")

    def check_rejected(self, tool, name, path):
        out = os.path.join(self.dir, "out-%s-%s.glb" % (tool, name.replace("/", "_")))
        p = lt.run([lt.tool(tool), "-i", path, "-o", out] + TOOLS_WITH_IO[tool], check=False, timeout=120)
        self.assertIn(p.returncode, (2, 3), "%s %s: exit %d, stderr %r" % (tool, name, p.returncode, p.stderr))
        lines = p.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, "%s %s: expected one line, got %r" % (tool, name, p.stderr))
        self.assertIn(os.path.basename(path), lines[0], "error must name the file: %r" % lines[0])
        self.assertTrue(lines[0].startswith(tool + " error: "), lines[0])
        self.assertFalse(os.path.exists(out), "no output file on failure")
        leftovers = [f for f in os.listdir(self.dir) if ".tmp" in f]
        self.assertEqual(leftovers, [], "no temporary files left behind")

    def test_every_bad_input_is_rejected(self):
        for tool in TOOLS_WITH_IO:
            for name, path in sorted(self.cases.items()):
                with self.subTest(tool=tool, case=name):
                    self.check_rejected(tool, name, path)

    def test_specific_messages(self):
        cases = {
            "required-extension.gltf": "EXT_lodbake_nonexistent",
            "nan.gltf": "NaN",
            "index-out-of-range.gltf": "out of range",
            "image-view-past-buffer.gltf": "exceeds its buffer",
            "invalid-mode.gltf": "invalid mode 4000",
            "zero-length-buffer.glb": "malformed glTF",
            "buffer-uri-directory.gltf": "not a regular file",
            "instancing-counts.gltf": "different counts",
            "light-out-of-range.gltf": "light 3 does not exist",
        }
        for name, needle in cases.items():
            p = lt.run([lt.tool("simplify"), "-i", self.cases[name], "-o", os.path.join(self.dir, "x.glb"),
                        "--ratio", "0.5"], check=False)
            self.assertIn(needle.lower(), p.stderr.lower(), p.stderr)

    def test_multires_counts(self):
        # Found by fuzzing: a negative vertexCount in LODBAKE_multires sized a 2^64-element array
        # (exit 4); it is invalid input.
        with open(os.path.join(self.dir, "good.glb"), "rb") as f:
            data = f.read()
        path = os.path.join(self.dir, "negative-vertex-count.glb")
        with open(path, "wb") as f:
            f.write(lt.glb_with_json(data, lambda doc: doc["extensions"]["LODBAKE_multires"]["original"].update(vertexCount=-8)))
        out = os.path.join(self.dir, "negative-vertex-count.uv.glb")
        p = lt.run([lt.tool("parameterize"), "-i", path, "-o", out, "--quiet"], check=False, timeout=120)
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertIn("vertexCount", p.stderr)
        self.assertFalse(os.path.exists(out))


class Images(unittest.TestCase):
    """Images stay encoded in the reader: simplify copies them through without loading OpenImageIO;
    the tools that use them decode every image on load and reject one that cannot be decoded."""

    def test_simplify_does_not_link_openimageio(self):
        for name in ("simplify", "agsphere-build"):
            p = lt.run(["readelf", "-d", lt.tool(name)])
            self.assertNotIn("OpenImageIO", p.stdout, "%s must not load OpenImageIO" % name)
        self.assertIn("OpenImageIO", lt.run(["readelf", "-d", lt.tool("parameterize")]).stdout)

    def test_corrupt_image(self):
        d = lt.work_dir("bad-image")
        quad = [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0]
        uv = array.array("f", [0, 1, 1, 1, 1, 0, 0, 0]).tobytes()
        png = b"\x89PNG\r\n\x1a\n" + b"\0\0\0\rIHDR" + b"\x07" * 9  # a PNG cut in its header
        doc = json.loads(minimal_gltf(quad, [0, 1, 2, 0, 2, 3]))
        doc["buffers"].append({"byteLength": len(uv), "uri": "data:application/octet-stream;base64," +
                               base64.b64encode(uv).decode()})
        doc["bufferViews"].append({"buffer": 1, "byteLength": len(uv)})
        doc["accessors"].append({"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"})
        doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 2
        doc["meshes"][0]["primitives"][0]["material"] = 0
        doc["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]
        doc["textures"] = [{"source": 0}]
        doc["images"] = [{"name": "cut", "uri": "data:image/png;base64," + base64.b64encode(png).decode()}]
        src = os.path.join(d, "cut-image.gltf")
        with open(src, "w") as f:
            json.dump(doc, f)
        mr = os.path.join(d, "cut-image.mr.glb")
        lt.run([lt.tool("simplify"), "-i", src, "-o", mr, "--ratio", "0.5", "--quiet"])
        out = os.path.join(d, "cut-image.uv.glb")
        p = lt.run([lt.tool("parameterize"), "-i", mr, "-o", out, "--quiet"], check=False, timeout=120)
        self.assertEqual(p.returncode, 2, p.stderr)
        lines = p.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, p.stderr)
        self.assertTrue(lines[0].startswith("parameterize error: " + mr + ": image 0 'cut': cannot decode"), lines[0])
        self.assertFalse(os.path.exists(out))
        # The chain in one process: parameterize decodes the images it is handed in memory too
        # (the later stages check only headers of images it decoded).
        lod = os.path.join(d, "cut-image.lod.glb")
        p = lt.run([lt.tool("lodbake"), "-i", src, "-o", lod, "--ratio", "0.5", "--quiet"], check=False, timeout=120)
        self.assertEqual(p.returncode, 2, p.stderr)
        # simplify's warning comes first (half the quad is over the gross-error bound), then the one error line
        lines = [l for l in p.stderr.strip().splitlines() if not l.startswith("lodbake warning: ")]
        self.assertEqual(len(lines), 1, p.stderr)
        self.assertTrue(lines[0].startswith("lodbake error: "), lines[0])
        self.assertIn(": image 0 'cut': cannot decode", lines[0])
        self.assertFalse(os.path.exists(lod))


class Usage(unittest.TestCase):
    """Table-driven CLI contract: args -> exit code and the start of the message."""

    def test_table(self):
        d = lt.work_dir("usage")
        good = os.path.join(d, "good.gltf")
        with open(good, "w") as f:
            f.write(minimal_gltf([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0], [0, 1, 2, 0, 2, 3]))
        out = os.path.join(d, "o.glb")
        table = [
            (["--help"], 0, ""),
            (["--version"], 0, ""),
            (["--bogus"], 1, "simplify error: unrecognized option '--bogus'"),
            (["-i", good, "-o", out, "--ratio", ""], 1, "simplify error: --ratio"),
            (["-i", good, "-o", out, "--ratio", "abc"], 1, "simplify error: --ratio: 'abc' is not a number"),
            (["-i", good, "-o", out, "--ratio", "1.5"], 1, "simplify error: --ratio values must be in (0, 1]"),
            (["-i", good, "-o", os.path.join(d, "o.obj"), "--ratio", "0.5"], 1, "simplify error: output"),
            (["-o", out, "--ratio", "0.5"], 1, "simplify error: missing input"),
            (["-i", os.path.join(d, "missing.glb"), "-o", out, "--ratio", "0.5"], 2, "simplify error: "),
            (["-i", good, "-o", os.path.join(d, "no-such-dir", "o.glb"), "--ratio", "0.5"], 2, "simplify error: "),
            (["-i", good, "-o", out, "--ratio", "0.5", "--threads", "-2"], 1, "simplify error: --threads"),
        ]
        for args, code, start in table:
            with self.subTest(args=args):
                p = lt.run([lt.tool("simplify")] + args, check=False)
                self.assertEqual(p.returncode, code, p.stderr)
                if start:
                    self.assertTrue(p.stderr.startswith(start), p.stderr)
                    self.assertEqual(len(p.stderr.strip().splitlines()), 1)
                    if code == 1:
                        self.assertIn("See 'simplify --help'", p.stderr)
        self.assertIn("Exit codes", lt.run([lt.tool("simplify"), "--help"]).stdout)
        self.assertFalse(os.path.exists(out))


if __name__ == "__main__":
    lt.main([BadInputs, Images, Usage])
