"""quality: every level of the chain rendered by three.js (scripts/render_three.py: one fixed PBR
setup, --views cameras around the original's bounding sphere) against the original: PSNR, SSIM
and silhouette IoU, plus compare's relative Hausdorff distance (geometry) and, for our levels, compare's PBR PSNR
and whether it orders the levels as three.js does (rankAgreement). Beside each level
k >= 1: gltfpack -si (our triangles / input triangles) -sp -se 1 (npm gltfpack 1.3; permissive,
no error limit, so it reaches the count) and, where Blender is installed, Blender's Decimate and
the Blender bake recipe at the same ratio. With --against both builds' levels are rendered in the
same browser session and a level that got worse is flagged. --posed adds, for animated inputs,
compare's posed Hausdorff and silhouette IoU of each level at the start, middle and end of
animation 0.

The chain runs with --chain-flags (default --lod0-density: the renders look at every level close
up, as the peers keep the original textures on every level; --chain-flags= measures the shipping
default). Renders are deterministic, so these figures do not depend on the machine's load."""
import json
import os
import subprocess
import sys

from . import common

QUICK_ASSETS = ["seamball"]
DEFAULT_ASSETS = ["Duck", "Avocado", "CesiumMilkTruck", "2CylinderEngine", "BoxTextured", "ChrKnight",
                  "ShapeCollection", "StanfordBunny", "walker"]
RENDER = os.path.join(common.SOURCE, "scripts/render_three.py")
WORSE_PSNR_DB = 0.1  # --against: a level whose PSNR drops more than this is flagged worse
WORSE_SSIM = 0.002   # ... or whose SSIM drops more than this
ORDER_SLACK_DB = 0.3  # a level may render this much closer than the level before it (bake noise)


def add_arguments(p):
    p.add_argument("--views", type=int, default=8, help="render views (default 8; --quick: 4)")
    p.add_argument("--size", type=int, default=256, help="render side in pixels (default 256)")
    p.add_argument("--chain-flags", default="--lod0-density", help="extra lodbake flags (default --lod0-density; "
                   "write --chain-flags= for none)")
    p.add_argument("--peers", help="comma-separated subset of gltfpack-npm, gltfpack-debian, blender-decimate, blender-bake, "
                   "or none: our levels only (default: gltfpack-npm and the Blender ones installed)")
    p.add_argument("--chain-timeout", type=float, help="seconds: a chain that takes longer is recorded as failed "
                   "and left out (default: no limit)")
    p.add_argument("--no-geometry", action="store_true", help="skip compare's Hausdorff distance (its PBR "
                   "render of our levels still runs)")
    p.add_argument("--posed", action="store_true", help="animated inputs: posed Hausdorff and IoU of our levels")


def levels_of(path):
    """Node ids of a pack output's levels: node 0 and its MSFT_lod ids."""
    nodes = common.Gltf(path).json["nodes"]
    return [0] + list(nodes[0].get("extensions", {}).get("MSFT_lod", {}).get("ids", []))


def compare(build, original, path, lod, extra):
    cmd = [build.tool("compare"), original, path, "--json"] + (["--lod", str(lod)] if lod else []) + extra
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode not in (0, 1):
        return None
    return json.loads(p.stdout)


def chain(build, src, work, name, args):
    """-> our rows (one per level, files and nodes to render) or an error row."""
    out = os.path.join(work, "%s.%s.lod.glb" % (name, build.label))
    rep = out[:-4] + ".json"
    try:
        p = subprocess.run([build.tool("lodbake"), "-i", src, "-o", out, "--ratio", args.ratio, "--quiet", "--report", rep]
                           + args.chain_flags.split(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                           timeout=args.chain_timeout)
    except subprocess.TimeoutExpired:
        return [{"tool": "lodbake", "build": build.label, "error": "took over %g s (--chain-timeout)" % args.chain_timeout}]
    if p.returncode != 0:
        return [{"tool": "lodbake", "build": build.label, "error": p.stderr.strip()[-300:]}]
    levels = common.read_json(rep)["stages"][-1]["levels"]
    return [{"tool": "lodbake", "build": build.label, "lod": k, "triangles": lv["triangles"], "file": out, "node": node,
             "bytes": lv.get("bytes")} for k, (lv, node) in enumerate(zip(levels, levels_of(out)))]


def peer_rows(src, work, name, tris, ours, wanted):
    peers = common.peers_available()
    extra = {"gltfpack-npm": ["-sp", "-se", "1"], "gltfpack-debian": []}
    rows = []
    for lv in ours:
        if lv.get("lod", 0) == 0:
            continue
        ratio = "%.6f" % (lv["triangles"] / float(tris))
        for p in wanted:
            if p not in peers:
                continue
            out = os.path.join(work, "%s.%s.lod%d.glb" % (name, p, lv["lod"]))
            r = common.timed(peers[p](src, out, ratio, extra.get(p, [])))
            row = {"tool": p, "lod": lv["lod"], "ratio": float(ratio), "file": out, "node": -1}
            if r["rc"] != 0 or not os.path.exists(out):
                row["error"] = r.get("error", "no output")
            else:
                row.update(triangles=common.triangles(out), bytes=os.path.getsize(out))
            rows.append(row)
    return rows


def render(groups, work, args):
    """Renders every group in one browser session; -> per group the candidates' results."""
    batch, out = os.path.join(work, "batch.json"), os.path.join(work, "renders.json")
    with open(batch, "w") as f:
        json.dump(groups, f, indent=1)
    p = subprocess.run([sys.executable, RENDER, "--batch", batch, "--views", str(args.views), "--size", str(args.size),
                        "--json", out], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if not os.path.exists(out):
        raise SystemExit("bench: render_three.py failed (%d): %s" % (p.returncode, p.stderr[-2000:]))
    return common.read_json(out)


def flag_regressions(rows):
    """--against: per level, bin vs against; sets "worse" on bin's rows."""
    before = {r["lod"]: r for r in rows if r["tool"] == "lodbake" and r.get("build") == "against" and r.get("psnr") is not None}
    for r in rows:
        b = before.get(r.get("lod"))
        if r["tool"] == "lodbake" and r.get("build") == "bin" and b and r.get("psnr") is not None:
            r["psnrDelta"] = round(r["psnr"] - b["psnr"], 3)
            r["ssimDelta"] = round(r["ssim"] - b["ssim"], 5)
            r["worse"] = r["psnrDelta"] < -WORSE_PSNR_DB or r["ssimDelta"] < -WORSE_SSIM


def verdicts(rows):
    """Ours (bin) against every peer output with at least our triangles at the same level."""
    out = []
    for o in rows:
        if o["tool"] != "lodbake" or o.get("build") != "bin" or o.get("lod", 0) == 0 or o.get("psnr") is None:
            continue
        beaten = [r["tool"] for r in rows if r["tool"] not in ("lodbake",) and r.get("lod") == o["lod"]
                  and r.get("psnr") is not None and r["triangles"] >= o["triangles"] and r["psnr"] > o["psnr"]]
        out.append({"lod": o["lod"], "win": not beaten, "beatenBy": beaten})
    return out


def level_order(rows, slack=ORDER_SLACK_DB):
    """Our levels (bin) that render closer than the level before them by more than `slack` dB in
    three.js: a coarser level should never look better than a finer one."""
    levels = sorted((r for r in rows if r["tool"] == "lodbake" and r.get("build") == "bin" and r.get("psnr") is not None),
                    key=lambda r: r["lod"])
    return [{"lod": b["lod"], "above": round(b["psnr"] - a["psnr"], 3)}
            for a, b in zip(levels, levels[1:]) if b["psnr"] > a["psnr"] + slack]


def rank_agreement(rows, tie=0.1):
    """Whether compare's PBR mode and three.js order our levels (bin) alike: the pairs of levels
    whose PSNRs both renderers separate by more than `tie` dB, and those they order oppositely."""
    levels = [r for r in rows if r["tool"] == "lodbake" and r.get("build") == "bin"
              and r.get("psnr") is not None and r.get("comparePbrPsnr") is not None]
    pairs, opposite = 0, []
    for i, a in enumerate(levels):
        for b in levels[i + 1:]:
            d3, dc = a["psnr"] - b["psnr"], a["comparePbrPsnr"] - b["comparePbrPsnr"]
            if abs(d3) <= tie or abs(dc) <= tie:
                continue
            pairs += 1
            if (d3 > 0) != (dc > 0):
                opposite.append([a["lod"], b["lod"]])
    return {"pairs": pairs, "opposite": opposite}


def run(args, builds, results):
    if args.quick and "--views" not in sys.argv:
        args.views = 4
    work = os.path.join(args.work, "quality")
    os.makedirs(work, exist_ok=True)
    inputs = common.Inputs(args.work, builds[0])
    available = common.peers_available()
    if args.peers:
        wanted = [] if args.peers == "none" else args.peers.split(",")
    else:
        wanted = ["gltfpack-npm" if "gltfpack-npm" in available else "gltfpack-debian"]
        wanted += [] if args.quick else ["blender-decimate", "blender-bake"]
    results["settings"].update({"ratio": args.ratio, "views": args.views, "size": args.size, "chainFlags": args.chain_flags,
                                "peers": [p for p in wanted if p in available],
                                "peersMissing": [p for p in wanted if p not in available],
                                "renderer": "scripts/render_three.py", "geometry": not args.no_geometry})
    entries, groups = [], []
    for name in args.assets or (QUICK_ASSETS if args.quick else DEFAULT_ASSETS):
        label, src = inputs.resolve(name)
        common.log("quality: %s" % label)
        tris = common.triangles(src)
        rows = []
        for b in builds:
            rows += chain(b, src, work, label, args)
        ours = [r for r in rows if r.get("build") == "bin" and "error" not in r]
        rows += peer_rows(src, work, label, tris, ours, wanted)
        drawn = [r for r in rows if "error" not in r]
        groups.append({"reference": src, "out": os.path.join(work, label + ".png"),
                       "candidates": [r["file"] + ("#node=%d" % r["node"] if r["node"] >= 0 else "") for r in drawn]})
        entries.append(({"name": label, "file": src, "triangles": tris, "rows": rows}, drawn))
    common.log("quality: rendering %d groups" % len(groups))
    rendered = render(groups, work, args) if groups else []
    for (entry, drawn), result in zip(entries, rendered):
        for r, c in zip(drawn, result["candidates"]):
            r.update({k: c.get(k) for k in ("psnr", "psnr_fg", "psnr_seam", "ssim", "iou", "coverage")})
            if not c.get("loaded"):
                r["renderErrors"] = c.get("errors", [])[:3]
        results["settings"]["three"] = result.get("three")
        src = entry["file"]
        build_of = {b.label: b for b in builds}
        for r in drawn:
            # compare's PBR render beside three.js's, for our levels (rank_agreement), and its
            # Hausdorff distance unless --no-geometry.
            if not args.no_geometry or r["tool"] == "lodbake":
                views = str(args.views) if r["tool"] == "lodbake" else "0"
                geometry = ["--no-geometry"] if args.no_geometry else ["--samples", "100000"]
                j = compare(builds[0], src, r["file"], r["lod"] if r["tool"] == "lodbake" else 0,
                            ["--views", views] + geometry)
                if not args.no_geometry:
                    r["relHausdorff"] = j["geometry"]["relHausdorff"] if j else None
                if j and r["tool"] == "lodbake":
                    r["comparePbrPsnr"] = j["images"]["pbr"]["psnr"]
            if args.posed and r["tool"] == "lodbake" and common.Gltf(src).json.get("animations"):
                r["posed"] = {}
                for t in ("start", "middle", "end"):
                    j = compare(build_of[r["build"]], src, r["file"], r["lod"],
                                ["--animation", "0", "--time", t, "--views", "6"])
                    r["posed"][t] = j and {"hausdorff": j["geometry"]["hausdorff"], "iou": j["images"]["baseColor"]["iou"]}
            for k in ("file", "node"):
                r.pop(k, None)
        flag_regressions(entry["rows"])
        entry["verdicts"] = verdicts(entry["rows"])
        entry["rankAgreement"] = rank_agreement(entry["rows"])
        entry["outOfOrder"] = level_order(entry["rows"])
        results["assets"].append(entry)
