"""scale: large inputs made by subdividing shared assets (cached in --work).
Textured inputs (default duck-1M; avocado-11M is the ten-million one) run simplify -> parameterize
-> texture-refine -> pack as separate tools, pack on parameterize's output too ("pack-norefine"),
then the whole chain in one process (lodbake; --chain-only inputs run it alone), each with wall,
CPU, peak RSS, GB of peak per million input triangles and its report's time split, beside Debian
gltfpack -si at each ratio.
Geometry-only inputs (default bunny-1M and bunny-4M, the Stanford bunny subdivided twice and
three times) run simplify --ratio 0.01 beside Debian's and npm's gltfpack -si 0.01, and
agsphere-build --ratio 0.5,0.3 without and with --view 1,0,0. Also compare's own cost on the
Stanford bunny against gltfpack -si 0.5 of it (defaults: 200k samples per side, 16 views).

Goals (issue 33): a 1M textured input <= 30 s whole chain, < 1 GB peak per million input
triangles at every stage and in lodbake, 10M within 24 GB; simplify <= 2x Debian gltfpack on the
1.1M and 4.4M bunnies; compare < 30 s."""
import os

from . import common

DEFAULT_ASSETS = ["duck-1M", "bunny-1M", "bunny-4M"]
QUICK_ASSETS = ["Duck", "StanfordBunny"]


def add_arguments(p):
    p.add_argument("--reps", type=int, default=1, help="runs per measurement, the median is kept (default 1)")
    p.add_argument("--simplify-ratio", default="0.01", help="geometry-only inputs: the one level (default 0.01)")
    p.add_argument("--threads", default="0", help="--threads of every stage (default 0 = all cores)")
    p.add_argument("--no-agsphere", action="store_true", help="skip agsphere-build on the geometry-only inputs")
    p.add_argument("--no-compare", action="store_true", help="skip compare's own timing")
    p.add_argument("--chain-only", nargs="+", default=[], metavar="ASSET",
                   help="these textured inputs run the whole chain (lodbake) alone, not each stage too (the "
                        "ten-million input's stages one by one would add most of an hour)")


def row(tool, r, tris, report=None, build=None):
    out = {"tool": tool}
    if build:
        out["build"] = build
    out.update(r)
    if "error" not in r:
        out["gbPerMTriangles"] = round(r["peakMB"] / 1024.0 / (tris / 1e6), 3)
        if report and os.path.exists(report):
            rep = common.read_json(report)
            out["time"] = {k: round(v, 3) for k, v in rep.get("time", {}).items()}
            if "stages" in rep:  # lodbake: each stage's split
                out["stages"] = {s.get("tool"): {k: round(v, 3) for k, v in s.get("time", {}).items()} for s in rep["stages"]}
    return out


def chain_rows(b, src, w, tris, args, chain_only=False):
    """Every stage as its own tool (unless `chain_only`), then lodbake: one row each."""
    n = os.path.join(w, "%s" % b.label)
    common_flags = ["--threads", args.threads, "--quiet"]
    steps = [
        ("simplify", [b.tool("simplify"), "-i", src, "-o", n + ".mr.glb", "--ratio", args.ratio]),
        ("parameterize", [b.tool("parameterize"), "-i", n + ".mr.glb", "-o", n + ".uv.glb"]),
        ("texture-refine", [b.tool("texture-refine"), "-i", n + ".uv.glb", "-o", n + ".tex.glb"]),
        ("pack", [b.tool("pack"), "-i", n + ".tex.glb", "-o", n + ".lod.glb"]),
        ("pack-norefine", [b.tool("pack"), "-i", n + ".uv.glb", "-o", n + ".norefine.lod.glb"]),
        ("lodbake", [b.tool("lodbake"), "-i", src, "-o", n + ".chain.lod.glb", "--ratio", args.ratio]),
    ]
    if chain_only:
        steps = steps[-1:]
    rows = []
    for tool, cmd in steps:
        rep = "%s.%s.json" % (n, tool)
        common.log("scale:   %s %s" % (b.label, tool))
        rows.append(row(tool, common.timed_reps([cmd + common_flags + ["--report", rep]], args.reps), tris, rep, b.label))
        if "error" in rows[-1] and tool in ("simplify", "parameterize"):
            break  # the later stages have no input
    return rows


def simplify_rows(b, src, w, tris, args):
    n = os.path.join(w, b.label)
    rows = []
    rep = n + ".simplify.json"
    common.log("scale:   %s simplify" % b.label)
    rows.append(row("simplify", common.timed_reps([[b.tool("simplify"), "-i", src, "-o", n + ".mr.glb", "--ratio",
                                                    args.simplify_ratio, "--threads", args.threads, "--quiet",
                                                    "--report", rep]], args.reps), tris, rep, b.label))
    if not args.no_agsphere:
        for tool, extra in (("agsphere-build", []), ("agsphere-build --view", ["--view", "1,0,0"])):
            rep = n + ".agsphere%s.json" % ("-view" if extra else "")
            common.log("scale:   %s %s" % (b.label, tool))
            cmd = [b.tool("agsphere-build"), "-i", src, "-o", rep[:-5] + ".glb", "--ratio", "0.5,0.3", "--threads",
                   args.threads, "--quiet", "--report", rep] + extra
            rows.append(row(tool, common.timed_reps([cmd], args.reps), tris, rep, b.label))
    return rows


def peer_rows(src, w, tris, ratios, args, names):
    peers = common.peers_available()
    rows = []
    for p in names:
        if p in peers:
            common.log("scale:   %s" % p)
            cmds = [peers[p](src, os.path.join(w, "%s.%s.glb" % (p, r)), r) for r in ratios]
            rows.append(dict(row(p, common.timed_reps(cmds, args.reps), tris), ratios=",".join(ratios)))
    return rows


def compare_entry(builds, inputs, args):
    """compare's cost on a ~104k-triangle pair: the Stanford bunny against gltfpack -si 0.5 of it."""
    label, src = inputs.resolve("StanfordBunny")
    w = os.path.join(args.work, "scale", "compare")
    os.makedirs(w, exist_ok=True)
    half = os.path.join(w, "bunny-half.glb")
    common.run_checked(["gltfpack", "-i", src, "-o", half, "-si", "0.5"])
    tris = common.triangles(src) + common.triangles(half)
    entry = {"name": "compare: StanfordBunny vs gltfpack -si 0.5", "file": src, "triangles": tris, "role": "compare", "rows": []}
    for b in builds:
        common.log("scale: compare %s" % b.label)
        rep = os.path.join(w, b.label + ".json")
        r = common.timed_reps([[b.tool("compare"), src, half, "--report", rep]], args.reps)
        entry["rows"].append(row("compare", r, tris, rep, b.label))
    return entry


def run(args, builds, results):
    inputs = common.Inputs(args.work, builds[0])
    results["settings"].update({"reps": args.reps, "ratio": args.ratio, "simplifyRatio": args.simplify_ratio,
                                "threads": args.threads})
    for name in args.assets or (QUICK_ASSETS if args.quick else DEFAULT_ASSETS):
        label, src = inputs.resolve(name)
        tris = common.triangles(src)
        textured = common.has_texcoords(src)
        common.log("scale: %s (%d triangles, %s)" % (label, tris, "textured" if textured else "geometry only"))
        w = os.path.join(args.work, "scale", label)
        os.makedirs(w, exist_ok=True)
        entry = {"name": label, "file": src, "triangles": tris, "role": "chain" if textured else "simplify", "rows": []}
        for b in builds:
            if textured:
                entry["rows"] += chain_rows(b, src, w, tris, args, name in args.chain_only or label in args.chain_only)
            else:
                entry["rows"] += simplify_rows(b, src, w, tris, args)
        if textured:
            entry["rows"] += peer_rows(src, w, tris, args.ratio.split(","), args, ["gltfpack-debian"])
        else:
            entry["rows"] += peer_rows(src, w, tris, [args.simplify_ratio], args, ["gltfpack-debian", "gltfpack-npm"])
        results["assets"].append(entry)
    if not args.no_compare and common.shared_asset_file("StanfordBunny"):
        results["assets"].append(compare_entry(builds, inputs, args))
