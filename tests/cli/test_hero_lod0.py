"""The hero LOD0 (`--lod0 original`, issue 34 item 4): LOD0 is the input asset itself.

`lodbake --ratio 0.5,0.1 --lod0 original` on the make-samples materials sample (five primitives,
five materials: a textured floor and four spheres on KHR_materials_* extensions), on the pbrscene
sample Draco-compressed by npm gltf-transform (decoded into plain accessors on the way; three
primitives, three materials, every channel), and on the skinned walker (its walk drives LOD0
through its own nodes and the baked levels through a skin on the same nodes); the materials chain
also in the default mode beside it, and pack on its intermediate. Checks:

- glTF-Validator reports 0 errors on every output;
- node 0 is a group over the original's scene roots (its own meshes, materials and images), its
  MSFT_lod ids are the baked levels, each one mesh (one primitive, or one per draw group: the
  materials sample's glass is its own), and byte for byte the default chain's LOD1 and LOD2
  (geometry and images);
- `pack --lod0 original --original ASSET` writes lodbake's bytes; its usage and input errors
  (no --original, a bad mode, another asset, an intermediate, a missing file) exit 1, 2, 3;
- the reports say so: pack's lod0.mode "original" with the original's draw calls and materials,
  LOD0's source "original asset", the Draco input's decoded compression;
- three.js (scripts/render_three.py, 4 views, 256 px): LOD0 (FILE#node=0) renders as the input
  does, PSNR >= 60 dB (identical: 100); the baked levels render non-empty;
- Babylon.js (tests/browser/index.html): MSFT_lod loads every level of the pbrscene and materials
  chains without an error, every pbrscene mesh ready to draw, and the walker's chain walks like the
  original (silhouettes at the start, middle and end). On the materials chain Babylon's
  transmission never gets ready under headless SwiftShader (its opaque-scene render target is
  never drawn), so only the glass primitive may stay undrawn there.

Skips (77) without chromium, node or the node modules.
"""
import functools
import http.server
import json
import re
import os
import shutil
import subprocess
import sys
import threading
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import lodbake_test as lt  # noqa: E402

RENDER = os.path.join(lt.SOURCE, "scripts/render_three.py")
BROWSER_DIR = os.path.join(lt.SOURCE, "tests/browser")
GLTF_TRANSFORM = os.path.join(lt.NODE_MODULES, ".bin/gltf-transform")
RATIOS = "0.5,0.1"
MIN_LOD0_PSNR = 60.0  # dB; an identical render is 100
MIN_COVERAGE = 0.01


class QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


def level_nodes(g):
    """Node 0 and the nodes its MSFT_lod lists."""
    return [0] + g.json["nodes"][0].get("extensions", {}).get("MSFT_lod", {}).get("ids", [])


def level_bytes(g, node):
    """The bytes a level node draws: every accessor's view of its mesh, then its images."""
    j = g.json
    out = []

    def view(i):
        v = j["bufferViews"][i]
        return g.bin[v.get("byteOffset", 0): v.get("byteOffset", 0) + v["byteLength"]]

    for prim in j["meshes"][j["nodes"][node]["mesh"]]["primitives"]:
        for name in sorted(prim["attributes"]):
            out.append((name, view(j["accessors"][prim["attributes"][name]]["bufferView"])))
        out.append(("indices", view(j["accessors"][prim["indices"]]["bufferView"])))
        material = json.dumps(j["materials"][prim["material"]], sort_keys=True)
        for t in sorted(set(int(i) for i in re.findall(r'"index": (\d+)', material))):
            out.append(("image", view(j["images"][j["textures"][t]["source"]]["bufferView"])))
    return out


class HeroLod0(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        lt.require_browser_chain(("three", "playwright-core", "babylonjs", "babylonjs-loaders", "@gltf-transform"))
        lt.require_tools("lodbake")
        cls.dir = lt.work_dir("hero_lod0")
        samples = lt.make_samples(os.path.join(cls.dir, "samples"))
        site = os.path.join(cls.dir, "site")
        os.makedirs(site)
        sources = {"materials": os.path.join(samples, "materials.glb"), "walker": os.path.join(samples, "walker.glb")}
        draco = os.path.join(site, "pbrscene.draco.glb")
        lt.run([GLTF_TRANSFORM, "draco", os.path.join(samples, "pbrscene.glb"), draco])
        sources["pbrscene.draco"] = draco
        cls.sources, cls.hero, cls.baked, cls.reports = sources, {}, {}, {}
        for name, src in sources.items():
            if not src.startswith(site):
                shutil.copy(src, site)
            hero, baked = os.path.join(site, name + ".hero.glb"), os.path.join(cls.dir, name + ".baked.glb")
            report = os.path.join(cls.dir, name + ".hero.json")
            keep = ["--keep-intermediates", cls.dir] if name == "materials" else []
            lt.run([lt.tool("lodbake"), "-i", src, "-o", hero, "--ratio", RATIOS, "--lod0", "original", "--report", report, "-q"] + keep)
            if name == "materials":  # the default chain beside it: the same LOD1 and LOD2
                lt.run([lt.tool("lodbake"), "-i", src, "-o", baked, "--ratio", RATIOS, "-q"])
                cls.baked[name] = baked
            cls.hero[name] = hero
            with open(report) as f:
                cls.reports[name] = json.load(f)

        # three.js: the original, LOD0 and every baked level, in one browser session.
        groups = []
        for name, src in sources.items():
            g = lt.Gltf(cls.hero[name])
            candidates = ["%s#node=%d" % (cls.hero[name], n) for n in level_nodes(g)]
            groups.append({"reference": src, "candidates": candidates, "out": os.path.join(cls.dir, name + ".png")})
        batch, results = os.path.join(cls.dir, "batch.json"), os.path.join(cls.dir, "results.json")
        with open(batch, "w") as f:
            json.dump(groups, f, indent=1)
        p = subprocess.run([sys.executable, RENDER, "--batch", batch, "--views", "4", "--size", "256", "--json", results],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=900,
                           env=dict(os.environ, CHROMIUM=lt.CHROMIUM))
        if p.returncode != 0 and not os.path.exists(results):
            raise AssertionError("render_three.py failed (%d): %s" % (p.returncode, p.stderr[-3000:]))
        with open(results) as f:
            cls.renders = dict(zip(sources, json.load(f)))
        for name, r in cls.renders.items():
            print("%s: %s" % (name, ", ".join("LOD%d %s dB" % (k, c["psnr"]) for k, c in enumerate(r["candidates"]))))

        # Babylon.js, served like test_browser.py.
        for rel, dst in (("babylonjs/babylon.js", "babylon.js"), ("babylonjs-loaders/babylonjs.loaders.min.js", "babylonjs.loaders.min.js")):
            shutil.copy(os.path.join(lt.NODE_MODULES, rel), os.path.join(site, dst))
        shutil.copy(os.path.join(BROWSER_DIR, "index.html"), site)
        cls.server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(QuietHandler, directory=site))
        threading.Thread(target=cls.server.serve_forever, daemon=True).start()
        sys.stdout.flush()

    @classmethod
    def tearDownClass(cls):
        if hasattr(cls, "server"):
            cls.server.shutdown()
            cls.server.server_close()

    def babylon(self, model, animate=False):
        shot = os.path.join(self.dir, os.path.basename(model) + ".babylon.png")
        return lt.babylon_view(self, self.server.server_address[1], model, shot, animate)

    def test_validator(self):
        lt.assert_no_validator_errors(self, list(self.hero.values()))

    def test_lod0_is_the_original(self):
        for name, src in self.sources.items():
            with self.subTest(asset=name):
                g, o = lt.Gltf(self.hero[name]), lt.Gltf(src)
                node0 = g.json["nodes"][0]
                self.assertNotIn("mesh", node0)
                roots = o.json["scenes"][o.json.get("scene", 0)]["nodes"]
                self.assertEqual(node0["children"], [r + 1 for r in roots])
                self.assertEqual(g.json["scenes"][0]["nodes"], [0])
                # The original's meshes and materials, at their own indices.
                for i, mesh in enumerate(o.json["meshes"]):
                    self.assertEqual([p.get("material") for p in g.json["meshes"][i]["primitives"]],
                                     [p.get("material") for p in mesh["primitives"]])
                for i, material in enumerate(o.json.get("materials", [])):
                    self.assertEqual(g.json["materials"][i], material)
                self.assertNotIn("KHR_draco_mesh_compression", g.json.get("extensionsUsed", []))
                pack = self.reports[name]["stages"][3]
                drawCalls = sum(len(m["primitives"]) for m in o.json["meshes"])
                self.assertEqual(pack["lod0"]["mode"], "original")
                self.assertEqual(pack["options"]["lod0"], "original")
                self.assertEqual(pack["lod0"]["drawCalls"], drawCalls)
                self.assertEqual(pack["levels"][0]["source"], "original asset")
                self.assertEqual(pack["levels"][0]["drawCalls"], drawCalls)
                self.assertEqual(pack["levels"][0]["materials"], len(o.json.get("materials", [])) or 1)
                # The baked levels: one primitive, two for the materials sample (its glass
                # transmits, the rest does not: draw_split.h).
                self.assertEqual([lv["drawCalls"] for lv in pack["levels"][1:]], [2, 2] if name == "materials" else [1, 1])
                ids = level_nodes(g)
                self.assertEqual([len(g.json["meshes"][g.json["nodes"][ids[k]]["mesh"]]["primitives"]) for k in (1, 2)],
                                 [lv["drawCalls"] for lv in pack["levels"][1:]])
        self.assertEqual(self.reports["materials"]["stages"][3]["lod0"]["drawCalls"], 5)
        self.assertEqual(self.reports["pbrscene.draco"]["stages"][3]["lod0"]["decoded"],
                         ["KHR_draco_mesh_compression (3 primitives)"])

    def test_levels_are_the_baked_ones(self):
        for name, baked in self.baked.items():
            with self.subTest(asset=name):
                g, b = lt.Gltf(self.hero[name]), lt.Gltf(baked)
                ids, baked_ids = level_nodes(g), level_nodes(b)
                self.assertEqual(len(ids), 3)
                self.assertEqual(len(ids), len(baked_ids))
                for k in (1, 2):
                    self.assertEqual(len(g.json["meshes"][g.json["nodes"][ids[k]]["mesh"]]["primitives"]),
                                     len(b.json["meshes"][b.json["nodes"][baked_ids[k]]["mesh"]]["primitives"]))
                    self.assertEqual(level_bytes(g, ids[k]), level_bytes(b, baked_ids[k]), "LOD%d differs from the baked chain's" % k)
                self.assertEqual(g.json["nodes"][0]["extras"]["MSFT_screencoverage"],
                                 b.json["nodes"][0]["extras"]["MSFT_screencoverage"])

    def test_pack_same_bytes_and_errors(self):
        """pack --lod0 original --original ASSET writes lodbake's bytes; the usage and input errors."""
        tex, src = os.path.join(self.dir, "materials.tex.glb"), self.sources["materials"]
        out = os.path.join(self.dir, "materials.pack.glb")
        lt.run([lt.tool("pack"), "-i", tex, "-o", out, "--lod0", "original", "--original", src, "-q"])
        with open(out, "rb") as a, open(self.hero["materials"], "rb") as b:
            self.assertEqual(a.read(), b.read())
        cases = [
            (["--lod0", "original"], 1, "--original"),
            (["--lod0", "hero"], 1, "--lod0 must be baked or original"),
            (["--lod0", "original", "--original", self.sources["walker"]], 2, "not the original"),
            (["--lod0", "original", "--original", tex], 3, "LODBAKE_multires"),
            (["--lod0", "original", "--original", os.path.join(self.dir, "missing.glb")], 2, "missing.glb"),
        ]
        for args, rc, message in cases:
            with self.subTest(args=args):
                p = lt.run([lt.tool("pack"), "-i", tex, "-o", os.path.join(self.dir, "bad.glb"), "-q"] + args, check=False)
                self.assertEqual(p.returncode, rc, p.stderr)
                self.assertIn(message, p.stderr)
                self.assertEqual(len(p.stderr.strip().splitlines()), 1, p.stderr)

    def test_walker_levels_share_the_original_joints(self):
        g = lt.Gltf(self.hero["walker"])
        skins = g.json["skins"]
        original_joints = skins[g.json["nodes"][1]["skin"]]["joints"]
        for node in level_nodes(g)[1:]:
            self.assertEqual(skins[g.json["nodes"][node]["skin"]]["joints"], original_joints)
        # One animation, driving the original's nodes only (no copy of the joints).
        self.assertEqual(len(g.json["animations"]), 1)
        targets = {c["target"]["node"] for c in g.json["animations"][0]["channels"]}
        self.assertTrue(targets <= set(original_joints), targets)

    def test_three_renders_lod0_as_the_original(self):
        for name, r in self.renders.items():
            with self.subTest(asset=name):
                self.assertTrue(r["reference"]["loaded"], r["reference"])
                lod0 = r["candidates"][0]
                self.assertTrue(lod0["loaded"], lod0)
                self.assertGreaterEqual(lod0["psnr"], MIN_LOD0_PSNR, lod0)
                for c in r["candidates"][1:]:
                    self.assertTrue(c["loaded"], c)
                    self.assertGreater(c["coverage"], MIN_COVERAGE, c)

    def test_babylon_switches_the_levels(self):
        for name, undrawn in (("pbrscene.draco", 0), ("materials", 1)):
            with self.subTest(asset=name):
                r = self.babylon(self.hero[name])
                self.assertTrue(r.get("msftLod"), "Babylon did not activate MSFT_lod")
                # Babylon's MSFT_lod loads coarse to fine, each level replacing the one before it.
                self.assertEqual(sorted(set(r["nodeLODs"])), [0, 1, 2], r)
                self.assertLessEqual(len(r["notReady"]), undrawn, r["notReady"])
                self.assertGreater(r["nonEmptyPixels"], 0.01 * r["pixels"])

    def test_babylon_walker_walks(self):
        original = self.babylon(os.path.join(self.dir, "site", "walker.glb"), animate=True)
        chain = self.babylon(self.hero["walker"], animate=True)
        self.assertEqual(chain["notReady"], [], chain)
        self.assertEqual(sorted(set(chain["nodeLODs"])), [0, 1, 2], chain)
        print("walker silhouettes: original %s changed %s; hero chain %s changed %s" %
              (original["silhouettes"], original["changed"], chain["silhouettes"], chain["changed"]))
        self.assertGreater(chain["changed"][0], 0.002 * chain["pixels"], chain)
        for a, b in zip(original["silhouettes"], chain["silhouettes"]):
            self.assertLess(abs(a - b), 0.02 * a)
        for a, b in zip(original["changed"], chain["changed"]):
            self.assertLess(abs(a - b), 0.1 * a + 0.001 * original["pixels"])


if __name__ == "__main__":
    lt.main([HeroLod0])
