#!/usr/bin/env python3
"""Render glTF files with three.js in headless Chromium and compare them with a reference.

    python3 scripts/render_three.py --reference ORIGINAL.glb[#variant=V] CANDIDATE[#node=K][&variant=V] ... --out DIR
        [--views 8] [--size 256] [--elevation 25] [--json FILE]
    python3 scripts/render_three.py --batch GROUPS.json [--json FILE] ...


Every file is rendered under one fixed, physically based setup (tests/browser/three_view.js:
RoomEnvironment PMREM, one directional light, Neutral tone mapping, sRGB output) from the same
cameras: `views` azimuths every 360/views degrees at `elevation` degrees, framing the bounding
sphere of the reference's scene. A candidate renders its default scene, or only node K (with its
children) when written FILE#node=K, e.g. one level of a pack output (node 0 carries MSFT_lod, its
ids are the coarser levels' nodes). FILE#variant=NAME (or FILE#node=K&variant=NAME; the reference
too) selects that KHR_materials_variants variant the way a viewer does (three.js's GLTFLoader reads
only the default materials: tests/browser/three_view.js applies the mappings). The images are composited over black and written as PNGs to
DIR. Per candidate it prints and writes (--json) whether it loaded without error, the fraction
of non-background pixels, and over the views the mean PSNR (RGB, dB; identical images = 100 dB),
mean SSIM (grey, 8x8 sliding uniform window, K1 = 0.01, K2 = 0.03) and mean silhouette IoU
against the reference, plus psnr_fg: the PSNR over the pixels covered in either image only, and
psnr_seam: the PSNR over the seam band, the pixels within --seam-band pixels of a texture seam the
candidate shows (an interior edge whose two triangles give it different UVs, e.g. an atlas chart
boundary; tests/browser/three_view.js), covered in either image (mean over the views that show a
seam; None when none does, or with --seam-band 0; skinned meshes are not masked).

Needs Debian's chromium, node and scripts/node/node_modules (three, playwright-core: `npm ci`).
Uses numpy when importable (re-running itself with /usr/bin/python3 when only Debian's python3
has it, python3-numpy), else pure python (slow).
--batch renders several groups [{"reference", "candidates", "out"}] in one browser session (the
first render of each material kind compiles its shaders in SwiftShader: the slow part).
Exit codes: 0 rendered (see each candidate's "loaded"), 2 usage error, browser or page failure,
or a reference that did not load.
"""
import argparse
import functools
import http.server
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import threading
import urllib.parse
import zlib

SOURCE = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
BROWSER_DIR = os.path.join(SOURCE, "tests/browser")
DEFAULT_NODE_MODULES = os.path.join(SOURCE, "scripts/node/node_modules")
SYSTEM_PYTHON = "/usr/bin/python3"

try:
    import numpy as np
except ImportError:
    np = None
    if (os.path.realpath(sys.executable) != os.path.realpath(SYSTEM_PYTHON) and os.path.exists(SYSTEM_PYTHON)
            and not os.environ.get("LODBAKE_RENDER_NO_REEXEC")
            and subprocess.run([SYSTEM_PYTHON, "-c", "import numpy"], stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL).returncode == 0):
        os.environ["LODBAKE_RENDER_NO_REEXEC"] = "1"
        os.execv(SYSTEM_PYTHON, [SYSTEM_PYTHON, os.path.abspath(__file__)] + sys.argv[1:])

PSNR_IDENTICAL = 100.0  # dB reported for identical images
SSIM_WINDOW = 8
SSIM_C1 = (0.01 * 255) ** 2
SSIM_C2 = (0.03 * 255) ** 2


# ---- images -------------------------------------------------------------------------------------

class Image:
    """One view: RGB composited over black (0..255) and coverage mask, both width x height."""

    def __init__(self, rgba, width, height):
        self.width, self.height = width, height
        if np is not None:
            a = np.frombuffer(rgba, dtype=np.uint8).reshape(height, width, 4)
            self.rgb = a[:, :, :3].copy()  # premultiplied by alpha: composited over black
            self.mask = a[:, :, 3] != 0
            self.covered = int(np.count_nonzero(self.mask))
        else:
            self.rgb = bytes(b for i, b in enumerate(rgba) if i % 4 != 3)
            self.mask = [rgba[i] != 0 for i in range(3, len(rgba), 4)]
            self.covered = sum(self.mask)

    def rgb_bytes(self):
        return self.rgb.tobytes() if np is not None else self.rgb


def write_png(path, image):
    w, h = image.width, image.height
    data = image.rgb_bytes()
    raw = b"".join(b"\x00" + data[y * w * 3:(y + 1) * w * 3] for y in range(h))

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xffffffff)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


# ---- metrics ------------------------------------------------------------------------------------

def psnr(a, b, foreground=False):
    """PSNR of two RGB images in dB, PSNR_IDENTICAL when equal. foreground: only over the pixels
    covered in either image (the background is the same black in both)."""
    if np is not None:
        d = a.rgb.astype(np.float64) - b.rgb.astype(np.float64)
        if foreground:
            d = d[a.mask | b.mask]
        mse = float(np.mean(d * d)) if d.size else 0.0
    else:
        keep = [m or n for m, n in zip(a.mask, b.mask) for _ in range(3)] if foreground else [True] * len(a.rgb)
        diffs = [(x - y) * (x - y) for x, y, k in zip(a.rgb, b.rgb, keep) if k]
        mse = sum(diffs) / len(diffs) if diffs else 0.0
    if mse == 0:
        return PSNR_IDENTICAL
    return min(PSNR_IDENTICAL, 10 * math.log10(255.0 * 255.0 / mse))


def _grey_np(image):
    rgb = image.rgb.astype(np.float64)
    return 0.299 * rgb[:, :, 0] + 0.587 * rgb[:, :, 1] + 0.114 * rgb[:, :, 2]


def _box_sums_np(x, k):
    s = np.zeros((x.shape[0] + 1, x.shape[1] + 1))
    s[1:, 1:] = x.cumsum(0).cumsum(1)
    return s[k:, k:] - s[:-k, k:] - s[k:, :-k] + s[:-k, :-k]


def _ssim_from_sums(sx, sy, sxx, syy, sxy, n):
    mx, my = sx / n, sy / n
    vx, vy, cxy = sxx / n - mx * mx, syy / n - my * my, sxy / n - mx * my
    return ((2 * mx * my + SSIM_C1) * (2 * cxy + SSIM_C2)) / ((mx * mx + my * my + SSIM_C1) * (vx + vy + SSIM_C2))


def ssim(a, b):
    """Mean SSIM of the grey levels (Rec. 601 luma) over every 8x8 window, 1 when equal."""
    k, n = SSIM_WINDOW, SSIM_WINDOW * SSIM_WINDOW
    if np is not None:
        x, y = _grey_np(a), _grey_np(b)
        m = _ssim_from_sums(_box_sums_np(x, k), _box_sums_np(y, k), _box_sums_np(x * x, k),
                            _box_sums_np(y * y, k), _box_sums_np(x * y, k), n)
        return float(m.mean())
    w, h = a.width, a.height

    def grey(img):
        p = img.rgb
        return [0.299 * p[i] + 0.587 * p[i + 1] + 0.114 * p[i + 2] for i in range(0, len(p), 3)]

    def integral(v):
        s = [0.0] * ((w + 1) * (h + 1))
        for yy in range(h):
            row = 0.0
            base, prev = (yy + 1) * (w + 1), yy * (w + 1)
            for xx in range(w):
                row += v[yy * w + xx]
                s[base + xx + 1] = s[prev + xx + 1] + row
        return s

    x, y = grey(a), grey(b)
    sums = [integral(v) for v in (x, y, [p * p for p in x], [q * q for q in y], [p * q for p, q in zip(x, y)])]
    total, count = 0.0, 0
    for yy in range(h - k + 1):
        for xx in range(w - k + 1):
            i00, i01 = yy * (w + 1) + xx, yy * (w + 1) + xx + k
            i10, i11 = (yy + k) * (w + 1) + xx, (yy + k) * (w + 1) + xx + k
            box = [s[i11] - s[i01] - s[i10] + s[i00] for s in sums]
            total += _ssim_from_sums(*box, n)
            count += 1
    return total / count


def seam_band(rgba, width, height, radius):
    """The seam mask (R channel set) grown by `radius` pixels (a square neighbourhood)."""
    if np is not None:
        m = np.frombuffer(rgba, dtype=np.uint8).reshape(height, width, 4)[:, :, 0] > 127
        grown = m.copy()
        for dy in range(-radius, radius + 1):
            for dx in range(-radius, radius + 1):
                shifted = np.zeros_like(m)
                shifted[max(dy, 0):height + min(dy, 0), max(dx, 0):width + min(dx, 0)] = \
                    m[max(-dy, 0):height + min(-dy, 0), max(-dx, 0):width + min(-dx, 0)]
                grown |= shifted
        return grown
    seam = [rgba[i] > 127 for i in range(0, len(rgba), 4)]
    grown = [False] * (width * height)
    for i, on in enumerate(seam):
        if not on:
            continue
        y, x = divmod(i, width)
        for yy in range(max(0, y - radius), min(height, y + radius + 1)):
            for xx in range(max(0, x - radius), min(width, x + radius + 1)):
                grown[yy * width + xx] = True
    return grown


def band_image(band, size):
    """The band as a white-on-black Image (for looking at it)."""
    if np is not None:
        rgba = np.zeros((size, size, 4), dtype=np.uint8)
        rgba[band] = 255
        return Image(rgba.tobytes(), size, size)
    return Image(bytes(255 if on else 0 for on in band for _ in range(4)), size, size)


def psnr_in(a, b, band):
    """PSNR of two RGB images over the pixels of `band` covered in either image; None when there
    are none."""
    if np is not None:
        keep = band & (a.mask | b.mask)
        if not keep.any():
            return None
        d = a.rgb.astype(np.float64)[keep] - b.rgb.astype(np.float64)[keep]
        mse = float(np.mean(d * d))
    else:
        keep = [k and (m or n) for k, m, n in zip(band, a.mask, b.mask)]
        idx = [i for i, k in enumerate(keep) if k]
        if not idx:
            return None
        mse = sum((a.rgb[3 * i + c] - b.rgb[3 * i + c]) ** 2 for i in idx for c in range(3)) / (3.0 * len(idx))
    if mse == 0:
        return PSNR_IDENTICAL
    return min(PSNR_IDENTICAL, 10 * math.log10(255.0 * 255.0 / mse))


def iou(a, b):
    """Silhouette IoU: covered pixels in both over covered pixels in either, 1 when both are empty."""
    if np is not None:
        union = int(np.count_nonzero(a.mask | b.mask))
        return int(np.count_nonzero(a.mask & b.mask)) / union if union else 1.0
    union = sum(1 for m, n in zip(a.mask, b.mask) if m or n)
    return sum(1 for m, n in zip(a.mask, b.mask) if m and n) / union if union else 1.0


# ---- serving and rendering ----------------------------------------------------------------------

class Handler(http.server.SimpleHTTPRequestHandler):
    """Serves /page/ (tests/browser), /three/ (node_modules/three) and /f/K/ (directory of file K)."""
    routes = {}
    extensions_map = dict(http.server.SimpleHTTPRequestHandler.extensions_map,
                          **{".js": "text/javascript", ".mjs": "text/javascript", ".wasm": "application/wasm",
                             ".glb": "model/gltf-binary", ".gltf": "model/gltf+json"})

    def translate_path(self, path):
        path = urllib.parse.unquote(urllib.parse.urlsplit(path).path)
        parts = [p for p in path.split("/") if p]
        if len(parts) >= 2 and parts[0] == "f" and parts[1] in self.routes:
            root, rest = self.routes[parts[1]], parts[2:]
        elif parts and parts[0] in self.routes:
            root, rest = self.routes[parts[0]], parts[1:]
        else:
            return "/nonexistent"
        if any(p in ("..", ".") for p in rest):
            return "/nonexistent"
        return os.path.join(root, *rest)

    def log_message(self, *args):
        pass


def parse_spec(text):
    """'FILE#node=K&variant=NAME' (either part optional) -> (FILE, K or -1, NAME or None)."""
    path, _, fragment = text.partition("#")
    node, variant = -1, None
    for part in fragment.split("&") if fragment else []:
        key, _, value = part.partition("=")
        if key == "node" and value.isdigit():
            node = int(value)
        elif key == "variant" and value:
            variant = urllib.parse.unquote(value)
        else:
            raise ValueError("candidate fragment must be #node=K, #variant=NAME or #node=K&variant=NAME: " + text)
    return path, node, variant


def parse_candidate(text):
    """'FILE#node=K' -> (FILE, K); 'FILE' -> (FILE, -1) (a variant is ignored: parse_spec)."""
    return parse_spec(text)[:2]


def spec_text(path, node, variant=None):
    parts = (["node=%d" % node] if node >= 0 else []) + (["variant=" + variant] if variant is not None else [])
    return path + ("#" + "&".join(parts) if parts else "")


def label_for(path, node, variant=None):
    base = os.path.basename(path)
    for ext in (".glb", ".gltf"):
        if base.endswith(ext):
            base = base[:-len(ext)]
    return (base + ("_node%d" % node if node >= 0 else "")
            + ("_" + "".join(c if c.isalnum() else "_" for c in variant) if variant is not None else ""))


def _serve(entries, node_modules):
    """Starts the local server; returns (server, url_of(path))."""
    routes = {"page": BROWSER_DIR, "three": os.path.join(node_modules, "three")}
    dirs = {}
    for path in entries:
        d = os.path.dirname(path)
        if d not in dirs:
            dirs[d] = str(len(dirs))
            routes[dirs[d]] = d
    handler = type("RouteHandler", (Handler,), {"routes": routes})
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(handler, directory=BROWSER_DIR))
    threading.Thread(target=server.serve_forever, daemon=True).start()

    def url_of(path):
        return "/f/%s/%s" % (dirs[os.path.dirname(path)], urllib.parse.quote(os.path.basename(path)))
    return server, url_of


def _compare(entries, reports, size, views, band=0):
    """Per entry of one group (reference first): PNGs and metrics against the reference."""
    results, ref_images = [], None
    for i, e in enumerate(entries):
        r = reports.get(e["index"], {"ok": False, "errors": ["no report from the renderer"], "console": []})
        errors = list(r.get("errors", [])) + [c for c in r.get("console", []) if c.startswith(("error", "pageerror"))]
        res = {"candidate": spec_text(e["path"], e["node"], e["variant"]), "file": e["path"],
               "node": e["node"], "variant": e["variant"], "label": e["label"], "loaded": bool(r.get("ok")) and not errors, "errors": errors,
               "warnings": [c for c in r.get("console", []) if c.startswith("warning")], "pngs": []}
        images = []
        if r.get("ok"):
            with open(e["rgba"], "rb") as f:
                data = f.read()
            step = size * size * 4
            for v in range(views):
                img = Image(data[v * step:(v + 1) * step], size, size)
                png = os.path.join(e["out"], "%s.v%d.png" % (e["label"], v))
                write_png(png, img)
                res["pngs"].append(png)
                images.append(img)
            res["coverage"] = sum(im.covered for im in images) / float(views * size * size)
        if i == 0:
            ref_images = images
        elif images and ref_images:
            res["psnr_views"] = [round(psnr(a, b), 4) for a, b in zip(ref_images, images)]
            res["ssim_views"] = [round(ssim(a, b), 6) for a, b in zip(ref_images, images)]
            res["psnr"] = round(sum(res["psnr_views"]) / views, 4)
            res["psnr_fg"] = round(sum(psnr(a, b, True) for a, b in zip(ref_images, images)) / views, 4)
            res["ssim"] = round(sum(res["ssim_views"]) / views, 6)
            res["iou"] = round(sum(iou(a, b) for a, b in zip(ref_images, images)) / views, 6)
            res["psnr_seam"] = res["seam_pixels"] = None
            if band > 0 and os.path.exists(e.get("seams") or ""):
                with open(e["seams"], "rb") as f:
                    masks = f.read()
                step, found, pixels = size * size * 4, [], 0
                for v, (a, b) in enumerate(zip(ref_images, images)):
                    grown = seam_band(masks[v * step:(v + 1) * step], size, size, band)
                    write_png(os.path.join(e["out"], "%s.v%d.seams.png" % (e["label"], v)), band_image(grown, size))
                    value = psnr_in(a, b, grown)
                    if value is not None:
                        found.append(value)
                        pixels += int(grown.sum()) if np is not None else sum(grown)
                if found:
                    res["psnr_seam"] = round(sum(found) / len(found), 4)
                    res["seam_pixels"] = pixels
        else:
            res["psnr"] = res["psnr_fg"] = res["ssim"] = res["iou"] = res["psnr_seam"] = None
        results.append(res)
    return results


def render_batch(groups, views=8, size=256, elevation=25.0, node_modules=DEFAULT_NODE_MODULES, chromium=None,
                 timeout=1800, seam_band=2):
    """Renders groups [{"reference": FILE, "candidates": [FILE or FILE#node=K], "out": DIR}] in one
    browser session, each group from cameras framing its reference; returns one result per group."""
    chromium = chromium or os.environ.get("CHROMIUM", "/usr/bin/chromium")
    if not os.path.exists(chromium):
        raise RuntimeError("chromium is missing: " + chromium)
    for m in ("three", "playwright-core"):
        if not os.path.isdir(os.path.join(node_modules, m)):
            raise RuntimeError("%s/%s is missing (cd scripts/node && npm ci)" % (node_modules, m))
    tmp = tempfile.mkdtemp(prefix="render_three_")
    plan = []  # per group: entries, reference first
    index = 0
    for g in groups:
        os.makedirs(g["out"], exist_ok=True)
        entries, labels = [], set()
        for text in [g["reference"]] + list(g["candidates"]):
            path, node, variant = parse_spec(text)
            label = "reference" if not entries else label_for(path, node, variant)
            while label in labels:
                label += "_"
            labels.add(label)
            entries.append({"path": os.path.abspath(path), "node": node, "variant": variant, "label": label, "out": g["out"],
                            "index": index, "rgba": os.path.join(tmp, "%d.rgba" % index),
                            "seams": os.path.join(tmp, "%d.seams.rgba" % index) if entries and seam_band > 0 else None})
            index += 1
        plan.append(entries)
    server, url_of = _serve([e["path"] for entries in plan for e in entries], node_modules)
    try:
        items = []
        for entries in plan:
            for j, e in enumerate(entries):
                item = {"url": url_of(e["path"]), "node": e["node"], "out": e["rgba"]}
                if e["variant"] is not None:
                    item["variant"] = e["variant"]
                if j == 0:
                    item["frame"] = url_of(e["path"])
                if e["seams"]:
                    item["seams"] = e["seams"]
                items.append(item)
        job_file = os.path.join(tmp, "job.json")
        with open(job_file, "w") as f:
            json.dump({"size": size, "views": views, "elevation": elevation, "items": items}, f)
        env = dict(os.environ, NODE_PATH=node_modules, CHROMIUM=chromium)
        page = "http://127.0.0.1:%d/page/three.html" % server.server_address[1]
        p = subprocess.run(["node", os.path.join(BROWSER_DIR, "three_run.js"), page, job_file], stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True, timeout=timeout, env=env)
        if p.returncode != 0:
            raise RuntimeError("three.js renderer failed (exit %d): %s" % (p.returncode, p.stderr[-3000:]))
        reports = {}
        for line in p.stdout.splitlines():
            if line.startswith("{"):
                r = json.loads(line)
                reports[r["index"]] = r
        revision = next((r.get("revision") for r in reports.values() if r.get("revision")), None)
        out = []
        for entries in plan:
            results = _compare(entries, reports, size, views, seam_band)
            out.append({"three": revision, "views": views, "size": size, "elevation": elevation,
                        "metric": {"psnr": "RGB over black, mean over views, dB (identical = %g)" % PSNR_IDENTICAL,
                                   "psnr_fg": "as psnr, over the pixels covered in either image only",
                                   "ssim": "grey, %dx%d uniform window, K1 0.01, K2 0.03, mean over views"
                                           % (SSIM_WINDOW, SSIM_WINDOW),
                                   "iou": "silhouette (alpha != 0) intersection over union, mean over views",
                                   "psnr_seam": "as psnr_fg, over the pixels within %d of a visible texture seam of "
                                                "the candidate, mean over the views that show one" % seam_band,
                                   "numpy": np is not None},
                        "reference": results[0], "candidates": results[1:]})
        return out
    finally:
        server.shutdown()
        server.server_close()
        shutil.rmtree(tmp, ignore_errors=True)


def render(reference, candidates, out, **options):
    """Renders `reference` and each candidate ('FILE' or 'FILE#node=K'); returns the result dict."""
    return render_batch([{"reference": reference, "candidates": candidates, "out": out}], **options)[0]


def print_result(result):
    ref = result["reference"]
    print("reference %s: loaded %s, coverage %.3f %s" % (ref["candidate"], ref["loaded"], ref.get("coverage", 0),
                                                         ref["errors"][:3] if ref["errors"] else ""))
    for c in result["candidates"]:
        if c["psnr"] is None:
            print("%s: FAILED %s" % (c["candidate"], c["errors"][:3]))
        else:
            seam = " (seam band %.2f dB)" % c["psnr_seam"] if c.get("psnr_seam") is not None else ""
            print("%s: loaded %s, coverage %.3f, PSNR %.2f dB (foreground %.2f dB%s), SSIM %.4f, IoU %.4f"
                  % (c["candidate"], c["loaded"], c["coverage"], c["psnr"], c["psnr_fg"], seam, c["ssim"], c["iou"]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--reference", help="original asset: frames the cameras, the images compared against")
    ap.add_argument("candidates", nargs="*", help="FILE, FILE#node=K, FILE#variant=NAME or FILE#node=K&variant=NAME")
    ap.add_argument("--out", help="directory for the PNGs")
    ap.add_argument("--batch", help='JSON file [{"reference", "candidates", "out"}, ...]: several groups in one '
                                    'browser session (instead of --reference/--out); --json then writes a list')
    ap.add_argument("--views", type=int, default=8)
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--elevation", type=float, default=25.0, help="camera elevation, degrees")
    ap.add_argument("--seam-band", type=int, default=2, metavar="PX",
                    help="psnr_seam: pixels within PX of a visible texture seam of the candidate (0 = off; default 2)")
    ap.add_argument("--json", help="write the results to this file")
    ap.add_argument("--node-modules", default=DEFAULT_NODE_MODULES)
    a = ap.parse_args()
    if a.views < 1 or a.size < SSIM_WINDOW or a.seam_band < 0:
        ap.error("--views must be >= 1, --size >= %d and --seam-band >= 0" % SSIM_WINDOW)
    if bool(a.batch) == bool(a.reference) or (a.reference and not a.out) or (a.batch and a.candidates):
        ap.error("give either --reference REF --out DIR [CANDIDATE ...] or --batch FILE.json")
    if a.batch:
        with open(a.batch) as f:
            groups = json.load(f)
    else:
        groups = [{"reference": a.reference, "candidates": a.candidates, "out": a.out}]
    try:
        results = render_batch(groups, a.views, a.size, a.elevation, a.node_modules, seam_band=a.seam_band)
    except (RuntimeError, ValueError, subprocess.TimeoutExpired) as e:
        print("render_three: %s" % e, file=sys.stderr)
        return 2
    for r in results:
        print_result(r)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(results if a.batch else results[0], f, indent=1)
    return 0 if all(r["reference"]["loaded"] for r in results) else 2


if __name__ == "__main__":
    sys.exit(main())
