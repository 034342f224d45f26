"""speed: the whole chain (`lodbake --ratio R`) per asset, median of --reps: wall, CPU, peak RSS and
the per-stage seconds of its report, beside the peers run in the same harness run on the same
input at each ratio of the chain (a peer's time is the sum over the ratios: one file per level, as
a user scripting it would run it). With --against the second build runs each asset right after
the first. With --threads 1,0 every thread count runs and the outputs are checked byte-identical.

With --extension-cost every asset whose materials use KHR_materials_* extensions also runs (first
build, first thread count) as a copy without them, and the entry records pack's CPU time with and
without: what the extension channels cost (CPU seconds; goal: at most 30% of pack's time).

Goals (issue 33): <= 3 s on every shared asset under 20k triangles, <= 15 s on 2CylinderEngine and
StanfordBunny, >= 10x faster than the Blender bake recipe."""
import json
import os

from . import common
from lodbake_test import glb_with_json  # noqa: E402 (tests/cli is on sys.path through common)

QUICK_ASSETS = ["seamball"]
QUICK_PEERS = ("gltfpack-debian", "gltfpack-npm")


def add_arguments(p):
    p.add_argument("--reps", type=int, default=3, help="runs per measurement, the median is kept (default 3)")
    p.add_argument("--threads", default="0", help="lodbake --threads values to run, comma-separated (default 0 = all cores); "
                   "outputs must be byte-identical across them")
    p.add_argument("--peers", help="comma-separated subset of gltfpack-debian, gltfpack-npm, blender-decimate, blender-bake "
                   "(default: every one installed; --quick: gltfpack only)")
    p.add_argument("--chain-flags", default="", help="extra lodbake flags for both builds (write --chain-flags=--flag)")
    p.add_argument("--extension-cost", action="store_true", help="also run each asset that uses material extensions "
                   "without them, and record pack's time both ways")


def default_assets(args):
    if args.quick:
        return QUICK_ASSETS
    return common.shared_asset_names() + ["walker"]


def stage_times(report):
    """{tool: {key: seconds}} of a lodbake report's stages, plus the chain's total."""
    out = {s.get("tool", "?"): {k: round(v, 3) for k, v in s.get("time", {}).items()} for s in report.get("stages", [])}
    out["total"] = round(report.get("time", {}).get("total", 0.0), 3)
    return out


def median_stages(reports):
    """Per stage and key, the median over the reps."""
    keys = {(s, k) for r in reports for s, t in r.items() if isinstance(t, dict) for k in t}
    out = {}
    for s, k in sorted(keys):
        out.setdefault(s, {})[k] = round(common.median([r[s][k] for r in reports if k in r.get(s, {})]), 3)
    out["total"] = round(common.median([r["total"] for r in reports]), 3)
    return out


def run_lodbake(build, src, work, name, threads, args):
    """-> the row of one build and thread count: median figures, stage split, output hash."""
    out = os.path.join(work, "%s.%s.t%s.lod.glb" % (name, build.label, threads))
    rep = out[:-len(".glb")] + ".json"
    cmd = [build.tool("lodbake"), "-i", src, "-o", out, "--ratio", args.ratio, "--threads", threads, "--quiet",
           "--report", rep] + args.chain_flags.split()
    runs, reports = [], []
    for _ in range(args.reps):
        r = common.timed(cmd)
        if r["rc"] != 0:
            return {"tool": "lodbake", "build": build.label, "threads": int(threads), "error": r["error"]}
        runs.append(r)
        reports.append(stage_times(common.read_json(rep)))
    med = sorted(runs, key=lambda r: r["wall"])[(len(runs) - 1) // 2]
    report = common.read_json(rep)
    return {"tool": "lodbake", "build": build.label, "threads": int(threads), "wall": med["wall"], "cpu": med["cpu"],
            "peakMB": med["peakMB"], "walls": [r["wall"] for r in runs], "stages": median_stages(reports),
            "levels": [lv["triangles"] for lv in report["stages"][-1].get("levels", [])],
            "inputTriangles": report["stages"][0].get("input", {}).get("triangles"),
            "bytes": os.path.getsize(out), "sha256": common.sha256(out)}


# Material extensions whose channels the bake carries; variants are a choice of materials, not a channel.
def material_extensions(doc):
    return sorted({e for m in doc.get("materials", []) for e in m.get("extensions", {})
                   if e.startswith("KHR_materials_") and e != "KHR_materials_variants"})


def strip_material_extensions(doc):
    names = set(material_extensions(doc))
    for m in doc.get("materials", []):
        for e in names:
            m.get("extensions", {}).pop(e, None)
    for key in ("extensionsUsed", "extensionsRequired"):
        if key in doc:
            doc[key] = [e for e in doc[key] if e not in names]


def without_extensions(src, work, label):
    """A copy of src without its material extensions (None when it has none). A .gltf's external
    files are linked beside the copy."""
    d = os.path.join(work, "noext-" + label)
    os.makedirs(d, exist_ok=True)
    if not material_extensions(common.Gltf(src).json):
        return None
    out = os.path.join(d, os.path.basename(src))
    if src.endswith(".glb"):
        with open(src, "rb") as f:
            glb = f.read()
        with open(out, "wb") as f:
            f.write(glb_with_json(glb, strip_material_extensions))
        return out
    with open(src) as f:
        doc = json.load(f)
    strip_material_extensions(doc)
    for item in doc.get("buffers", []) + doc.get("images", []):
        uri = item.get("uri", "")
        if uri and not uri.startswith("data:"):
            link = os.path.join(d, uri)
            os.makedirs(os.path.dirname(link), exist_ok=True)
            if not os.path.lexists(link):
                os.symlink(os.path.join(os.path.dirname(os.path.abspath(src)), uri), link)
    with open(out, "w") as f:
        json.dump(doc, f)
    return out


def pack_cpu(report_path):
    """Pack's CPU seconds in a lodbake report: every level's steps (UVs, page, mesh, bake, material)
    and the measure. CPU, not wall time: the figure holds on a machine that is not quiet."""
    pack = next(s for s in common.read_json(report_path)["stages"] if s.get("tool") == "pack")
    return sum(sum(lv.get("cpuSeconds", {}).values()) for lv in pack["levels"]) + pack["time"].get("measureCpu", 0)


def extension_cost(build, src, work, label, threads, args, ours):
    """Pack's CPU seconds (of the last rep) with and without the material extensions."""
    plain = without_extensions(src, work, label)
    if plain is None or not ours or "error" in ours:
        return None
    row = run_lodbake(build, plain, work, label + ".noext", threads, args)
    if "error" in row:
        return {"error": row["error"]}
    report = lambda name: os.path.join(work, "%s.%s.t%s.lod.json" % (name, build.label, threads))
    with_, without = pack_cpu(report(label)), pack_cpu(report(label + ".noext"))
    return {"extensions": material_extensions(common.Gltf(src).json), "packCpuWith": round(with_, 3),
            "packCpuWithout": round(without, 3), "cost": round(with_ / without - 1, 3) if without > 0 else None}


def run_peer(name, make, src, work, label, args):
    outs = [os.path.join(work, "%s.%s.%s.glb" % (label, name, r)) for r in args.ratio.split(",")]
    cmds = [make(src, o, r) for o, r in zip(outs, args.ratio.split(","))]
    r = common.timed_reps(cmds, args.reps)
    row = {"tool": name, "ratios": args.ratio}
    row.update(r)
    if "error" not in r:
        row["bytes"] = sum(os.path.getsize(o) for o in outs if os.path.exists(o))
    return row


def run(args, builds, results):
    work = os.path.join(args.work, "speed")
    os.makedirs(work, exist_ok=True)
    inputs = common.Inputs(args.work, builds[0])
    peers = common.peers_available()
    wanted = args.peers.split(",") if args.peers else (QUICK_PEERS if args.quick else list(peers))
    unknown = [p for p in wanted if p not in ("gltfpack-debian", "gltfpack-npm", "blender-decimate", "blender-bake")]
    if unknown:
        raise SystemExit("bench: unknown peer(s) %s" % ", ".join(unknown))
    results["settings"].update({"reps": args.reps, "ratio": args.ratio, "threads": args.threads,
                                "chainFlags": args.chain_flags, "peers": [p for p in wanted if p in peers],
                                "peersMissing": [p for p in wanted if p not in peers]})
    for name in args.assets or default_assets(args):
        label, src = inputs.resolve(name)
        common.log("speed: %s" % label)
        entry = {"name": label, "file": src, "triangles": common.triangles(src), "rows": []}
        for b in builds:
            for t in args.threads.split(","):
                entry["rows"].append(run_lodbake(b, src, work, label, t, args))
        if args.extension_cost:
            cost = extension_cost(builds[0], src, work, label, args.threads.split(",")[0], args, entry["rows"][0])
            if cost:
                entry["extensionCost"] = cost
        for p in wanted:
            if p in peers:
                entry["rows"].append(run_peer(p, peers[p], src, work, label, args))
        ours = [r for r in entry["rows"] if r["tool"] == "lodbake" and "error" not in r]
        for b in builds:
            hashes = {r["sha256"] for r in ours if r["build"] == b.label}
            entry.setdefault("identicalAcrossThreads", {})[b.label] = len(hashes) <= 1
        results["assets"].append(entry)
        print(format_asset(entry), flush=True)


def _first(rows, **match):
    return next((r for r in rows if all(r.get(k) == v for k, v in match.items()) and "error" not in r), None)


def format_asset(entry):
    """One asset's rows as plain text (the run's progress; the report makes the tables)."""
    lines = ["%s (%d triangles)" % (entry["name"], entry["triangles"])]
    for r in entry["rows"]:
        tag = r["tool"] + (" [%s, threads %d]" % (r["build"], r["threads"]) if r["tool"] == "lodbake" else "")
        if "error" in r:
            lines.append("  %-36s FAILED %s" % (tag, r["error"].splitlines()[-1][:120] if r["error"] else ""))
            continue
        lines.append("  %-36s %8.2f s wall %8.2f s CPU %8.1f MB peak" % (tag, r["wall"], r["cpu"], r["peakMB"]))
    cost = entry.get("extensionCost")
    if cost and "error" not in cost:
        lines.append("  pack CPU with %s: %.2f s, without: %.2f s (extension channels %+.0f%%)"
                     % (", ".join(cost["extensions"]), cost["packCpuWith"], cost["packCpuWithout"], 100 * cost["cost"]))
    ours = _first(entry["rows"], tool="lodbake", build="bin")
    if ours:
        for r in entry["rows"]:
            if r["tool"] != "lodbake" and "error" not in r and r["wall"] > 0:
                lines.append("  ours / %-29s %8.2fx" % (r["tool"], ours["wall"] / r["wall"]))
    return "\n".join(lines)
