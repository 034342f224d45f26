"""Textures in formats lodbake does not decode (EXT_texture_webp, KHR_texture_basisu,
EXT_texture_avif): optional with a PNG fallback, the chain uses the fallback with a warning;
required, every tool exits 2 with one line naming the extension and the file."""
import json
import os
import shutil
import unittest

import lodbake_test as lt

BOX = "/usr/share/assimp/models/glTF2/BoxTextured-glTF"


class ImageExtensions(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if not os.path.isdir(BOX):
            lt.skip(BOX + " is absent (apt-get install assimp-testmodels)")
        if shutil.which("oiiotool") is None:
            lt.skip("oiiotool is missing (apt-get install openimageio-tools)")
        cls.dir = lt.work_dir("image_extensions")
        for f in os.listdir(BOX):
            shutil.copy(os.path.join(BOX, f), cls.dir)
        lt.run(["oiiotool", os.path.join(cls.dir, "CesiumLogoFlat.png"), "-o", os.path.join(cls.dir, "logo.webp")])
        with open(os.path.join(cls.dir, "BoxTextured.gltf")) as f:
            doc = json.load(f)
        doc["images"].append({"uri": "logo.webp", "mimeType": "image/webp"})
        doc["textures"][0]["extensions"] = {"EXT_texture_webp": {"source": len(doc["images"]) - 1}}
        doc["extensionsUsed"] = doc.get("extensionsUsed", []) + ["EXT_texture_webp"]
        cls.optional = os.path.join(cls.dir, "optional.gltf")
        with open(cls.optional, "w") as f:
            json.dump(doc, f)
        doc["extensionsRequired"] = ["EXT_texture_webp"]
        del doc["textures"][0]["source"]
        cls.required = os.path.join(cls.dir, "required.gltf")
        with open(cls.required, "w") as f:
            json.dump(doc, f)

    def test_optional_uses_fallback(self):
        mr = os.path.join(self.dir, "optional.mr.glb")
        uv = os.path.join(self.dir, "optional.uv.glb")
        p = lt.run([lt.tool("simplify"), "-i", self.optional, "-o", mr, "--ratio", "0.5", "--quiet"])
        self.assertIn("EXT_texture_webp is not decoded; its fallback image 0 is used", p.stderr)
        # parameterize decodes every image of its input: the fallback PNG is what it bakes from.
        lt.run([lt.tool("parameterize"), "-i", mr, "-o", uv, "--size", "128", "--quiet"])

    def test_required_is_exit_2(self):
        for tool, extra in (("simplify", ["--ratio", "0.5"]), ("parameterize", []), ("pack", [])):
            with self.subTest(tool=tool):
                dst = os.path.join(self.dir, "required.%s.glb" % tool)
                p = lt.run([lt.tool(tool), "-i", self.required, "-o", dst] + extra, check=False)
                self.assertEqual(p.returncode, 2, p.stderr)
                self.assertEqual(len(p.stderr.strip().splitlines()), 1, p.stderr)
                self.assertIn("EXT_texture_webp", p.stderr)
                self.assertIn(self.required, p.stderr)
                self.assertFalse(os.path.exists(dst))


if __name__ == "__main__":
    lt.main([ImageExtensions])
