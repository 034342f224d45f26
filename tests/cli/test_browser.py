"""Browser test: a pack output (MSFT_lod chain) opens in a real viewer.

simplify -> parameterize -> pack on a generated sample (and Duck when ../shared/assets exists),
then Babylon.js (scripts/node/node_modules, served from 127.0.0.1 on a free port, no CDN) loads
the chain in Debian's headless Chromium driven by playwright-core. Checks: every LOD was loaded
by Babylon's MSFT_lod extension (node and material LOD observables), no loader error, and the
rendered frame is not empty; also a --meshopt --quantize chain (Babylon's meshopt decoder
served locally). The skinned walker's chain plays its animation: its silhouette at
the start, middle and end changes as the original's does. The screenshot stays in the test's work dir as an artefact.
Skips (77) when chromium or the node modules are missing.
"""
import functools
import http.server
import json
import os
import shutil
import sys
import threading
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import lodbake_test as lt  # noqa: E402

NODE_MODULES = lt.NODE_MODULES
BROWSER_DIR = os.path.join(lt.SOURCE, "tests/browser")


class QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


class BrowserChain(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        lt.require_browser_chain(("babylonjs", "babylonjs-loaders", "playwright-core", "draco3dgltf", "meshoptimizer"))
        cls.dir = lt.work_dir("browser")
        site = os.path.join(cls.dir, "site")
        os.makedirs(site)
        shutil.copy(os.path.join(BROWSER_DIR, "index.html"), site)
        shutil.copy(os.path.join(NODE_MODULES, "babylonjs/babylon.js"), site)
        shutil.copy(os.path.join(NODE_MODULES, "babylonjs-loaders/babylonjs.loaders.min.js"), site)
        shutil.copy(os.path.join(NODE_MODULES, "draco3dgltf/draco_decoder_gltf.wasm"), site)
        shutil.copy(os.path.join(NODE_MODULES, "draco3dgltf/draco_decoder_gltf_nodejs.js"),
                    os.path.join(site, "draco_wasm_wrapper_gltf.js"))
        # The script build of the decoder: it defines the global MeshoptDecoder Babylon looks for.
        shutil.copy(os.path.join(NODE_MODULES, "meshoptimizer/meshopt_decoder.cjs"), os.path.join(site, "meshopt_decoder.js"))
        cls.site = site
        handler = functools.partial(QuietHandler, directory=site)
        cls.server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
        cls.port = cls.server.server_address[1]
        cls.thread = threading.Thread(target=cls.server.serve_forever, daemon=True)
        cls.thread.start()

    @classmethod
    def tearDownClass(cls):
        if hasattr(cls, "server"):
            cls.server.shutdown()
            cls.server.server_close()

    def chain(self, src, name, extra=()):
        mr = os.path.join(self.dir, name + ".mr.glb")
        uv = os.path.join(self.dir, name + ".uv.glb")
        out = os.path.join(self.site, name + ".lod.glb")
        lt.run([lt.tool("simplify"), "-i", src, "-o", mr, "--ratio", "0.5,0.1,0.02", "--quiet"])
        lt.run([lt.tool("parameterize"), "-i", mr, "-o", uv, "--size", "512", "--quiet"])
        lt.run([lt.tool("pack"), "-i", uv, "-o", out, "--max-size", "512", "--samples", "20000", "--quiet"] + list(extra))
        return out, lt.lod_levels(lt.Gltf(out))

    def view(self, model, levels, animate=False):
        shot = os.path.join(self.dir, os.path.basename(model) + ".png")
        r = lt.babylon_view(self, self.port, model, shot, animate)
        print("%s: %s" % (os.path.basename(model), json.dumps({k: r[k] for k in ("nodeLODs", "materialLODs", "meshes", "nonEmptyPixels", "pixels")})))
        print("screenshot: " + shot)
        if levels == 1:
            return r
        self.assertTrue(r.get("msftLod"), "Babylon did not activate MSFT_lod")
        # Babylon's MSFT_lod loads coarse to fine and reports each node LOD index once loaded.
        self.assertEqual(sorted(set(r["nodeLODs"])), list(range(levels)), r)
        # Our materials carry no material-level MSFT_lod; each node LOD brings its own material.
        self.assertGreater(r["nonEmptyPixels"], 0.01 * r["pixels"], "rendered frame is (nearly) empty")
        self.assertTrue(os.path.getsize(shot) > 0)
        return r

    def test_sample_chain(self):
        src = os.path.join(lt.make_samples(os.path.join(self.dir, "samples")), "seamball.glb")
        model, levels = self.chain(src, "seamball")
        self.assertEqual(levels, 4)
        self.view(model, levels)

    def test_sample_chain_meshopt_quantize(self):
        src = os.path.join(lt.make_samples(os.path.join(self.dir, "samples")), "seamball.glb")
        model, levels = self.chain(src, "seamball.mq", ["--meshopt", "--quantize"])
        self.assertIn("EXT_meshopt_compression", lt.Gltf(model).json["extensionsRequired"])
        self.view(model, levels)
    def test_walker_chain_moves(self):
        """The chain plays its walk in Babylon: the silhouette changes over time as the original's does."""
        samples = lt.make_samples(os.path.join(self.dir, "walker-samples"))
        src = os.path.join(samples, "walker.glb")
        shutil.copy(src, os.path.join(self.site, "walker.glb"))
        model, _ = self.chain(src, "walker")
        levels = 1 + len(lt.Gltf(model).json["nodes"][0]["extensions"]["MSFT_lod"]["ids"])  # the rig adds nodes
        original = self.view(os.path.join(self.site, "walker.glb"), 1, animate=True)
        chain = self.view(model, levels, animate=True)
        print("walker silhouettes: original %s changed %s; chain %s changed %s" %
              (original["silhouettes"], original["changed"], chain["silhouettes"], chain["changed"]))
        for r in (original, chain):
            # The legs swing from one side to the other between the start and the middle.
            self.assertGreater(r["changed"][0], 0.002 * r["pixels"], r)
        for a, b in zip(original["silhouettes"], chain["silhouettes"]):
            self.assertLess(abs(a - b), 0.05 * a)
        for a, b in zip(original["changed"], chain["changed"]):
            self.assertLess(abs(a - b), 0.25 * a + 0.001 * original["pixels"])

    def test_duck_chain_draco(self):
        if not os.path.isdir(lt.ASSETS):
            self.skipTest("../shared/assets is absent")
        model, levels = self.chain(os.path.join(lt.ASSETS, lt.ASSET_FILES["Duck"]), "Duck", ["--draco"])
        self.view(model, levels)


if __name__ == "__main__":
    lt.main([BrowserChain])
