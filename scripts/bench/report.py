"""Markdown from results files: `bench.py report R.json...` prints the tables; with --update FILE.md
it replaces each generated section of FILE.md (between `<!-- bench:SUITE -->` and
`<!-- /bench:SUITE -->`) by the tables of the newest results file of that suite, leaving the
hand-written text around them alone."""
import re
import sys

from . import common

TIMED = ("speed", "scale")  # suites whose figures depend on the machine's load
QUIET_LOAD = 0.5  # load average before the run, or share of a core other processes took during it: above, not quiet
PEER_NAMES = {"gltfpack-debian": "gltfpack (Debian)", "gltfpack-npm": "gltfpack (npm)",
              "blender-decimate": "Blender Decimate", "blender-bake": "Blender bake recipe"}


def fmt(x, spec="%.2f"):
    return "–" if x is None else spec % x


def contended(res):
    """A timed suite run on a machine that was not quiet: other processes took more than
    QUIET_LOAD of a core during the run (older results: the load average before or after it)."""
    m = res["machine"]
    if res["suite"] not in TIMED:
        return False
    if "otherCpuShare" in m:
        return m["loadAverageStart"][0] > QUIET_LOAD or m["otherCpuShare"] > QUIET_LOAD
    return max(m["loadAverageStart"][0], m.get("loadAverageEnd", [0])[0]) > QUIET_LOAD


def header(res):
    m = res["machine"]
    load = "%.2f → %.2f" % (m["loadAverageStart"][0], m.get("loadAverageEnd", [float("nan")])[0])
    if "otherCpuShare" in m:
        load += ", other processes %.2f of a core" % m["otherCpuShare"]
    builds = "; ".join("%s `%s` (%s)" % (b["label"], (b.get("commit") or "?")[:12], b["bin"]) for b in res["builds"])
    lines = ["_%s, %s: %s, %d cores, %s GiB, load average %s; %s; peers: %s._" % (
        res["suite"], res["started"][:16].replace("T", " "), m.get("cpu", "?"), m["cores"], m.get("memoryGiB", "?"), load,
        builds, ", ".join("%s" % v for v in res.get("peers", {}).values()) or "none"),
        "", "`python3 %s`" % " ".join(res["command"])]
    if contended(res):
        lines += ["", "**Contended machine (load average or other processes above %.1f of a core): these timings are not publishable figures; "
                      "re-run on a quiet machine.**" % QUIET_LOAD]
    missing = res.get("settings", {}).get("peersMissing")
    if missing:
        lines += ["", "Peers not installed in this run: %s." % ", ".join(PEER_NAMES.get(p, p) for p in missing)]
    return "\n".join(lines)


def stage_work(times):
    """Seconds of a stage's own work: its report's figures minus load, write, pack's measure (which
    lies inside its pack figure) and CPU-time figures."""
    return sum(v for k, v in times.items() if k not in ("load", "write", "measure", "total") and not k.endswith("Cpu"))


def speed_goal(entry):
    if entry["name"] in ("2CylinderEngine", "StanfordBunny"):
        return 15.0
    return 3.0 if entry["triangles"] < 20000 else None


def speed(res):
    peers = res["settings"].get("peers", [])
    out = ["| asset | triangles | build | threads | wall s | CPU s | peak MB | simplify | parameterize | texture-refine | "
           "pack (of which measure) | goal |", "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    for e in res["assets"]:
        for r in (r for r in e["rows"] if r["tool"] == "lodbake"):
            if "error" in r:
                out.append("| %s | %d | %s | %d | failed: %s |||||||" % (e["name"], e["triangles"], r["build"], r["threads"],
                                                                        last_line(r["error"])))
                continue
            s = r["stages"]
            goal = speed_goal(e)
            pack = s.get("pack", {})
            out.append("| %s | %d | %s | %d | %.2f | %.2f | %.0f | %s | %s | %s | %s (%s) | %s |" % (
                e["name"], e["triangles"], r["build"], r["threads"], r["wall"], r["cpu"], r["peakMB"],
                *[fmt(stage_work(s[t])) if t in s else "–" for t in ("simplify", "parameterize", "texture-refine")],
                fmt(stage_work(pack)) if pack else "–", fmt(pack.get("measure")),
                "≤ %g s: %s" % (goal, "met" if r["wall"] <= goal else "**not met**") if goal else ""))
        if not e.get("identicalAcrossThreads", {}).get("bin", True):
            out.append("| %s | **outputs differ between thread counts** |||||||||||" % e["name"])
    if peers:
        out += ["", "Peers in the same run (each ratio of the chain one run, summed), and ours / peer wall time:", "",
                "| asset | lodbake s | " + " | ".join("%s s | ours / it" % PEER_NAMES.get(p, p) for p in peers) + " |",
                "|---|---:|" + "---:|---:|" * len(peers)]
        for e in res["assets"]:
            ours = next((r for r in e["rows"] if r["tool"] == "lodbake" and r["build"] == "bin" and "error" not in r), None)
            cells = []
            for p in peers:
                r = next((r for r in e["rows"] if r["tool"] == p), None)
                if not r or "error" in r:
                    cells += ["failed" if r else "–", ""]
                else:
                    cells += ["%.2f" % r["wall"], "%.1f×" % (ours["wall"] / r["wall"]) if ours and r["wall"] > 0 else "–"]
            out.append("| %s | %s | %s |" % (e["name"], fmt(ours and ours["wall"]), " | ".join(cells)))
    costs = [(e["name"], e["extensionCost"]) for e in res["assets"] if "error" not in e.get("extensionCost", {"error": 1})]
    if costs:
        out += ["", "What the material extensions' channels cost pack (`--extension-cost`: the same asset without "
                    "its KHR_materials_* extensions; pack's CPU seconds, its levels and measure; goal ≤ 30%):", "",
                "| asset | extensions | pack CPU s | without | cost |", "|---|---|---:|---:|---:|"]
        for name, c in costs:
            out.append("| %s | %s | %.2f | %.2f | %+.0f%%%s |" % (
                name, ", ".join(e.replace("KHR_materials_", "") for e in c["extensions"]), c["packCpuWith"], c["packCpuWithout"],
                100 * c["cost"], "" if c["cost"] <= 0.3 else " (**above 30%**)"))
    if any(b["label"] == "against" for b in res["builds"]):
        out += ["", "| asset | bin wall s | against wall s | bin / against | same bytes |", "|---|---:|---:|---:|---|"]
        for e in res["assets"]:
            a = next((r for r in e["rows"] if r["tool"] == "lodbake" and r["build"] == "bin" and "error" not in r), None)
            b = next((r for r in e["rows"] if r["tool"] == "lodbake" and r["build"] == "against" and "error" not in r), None)
            if a and b:
                out.append("| %s | %.2f | %.2f | %.2f× | %s |" % (e["name"], a["wall"], b["wall"], a["wall"] / b["wall"],
                                                                  "yes" if a["sha256"] == b["sha256"] else "**no**"))
    return "\n".join(out)


def tool_name(r, against):
    if r["tool"] == "lodbake":
        return "lodbake (%s)" % r["build"] if against else "lodbake"
    return PEER_NAMES.get(r["tool"], r["tool"])


def last_line(error):
    return (error.splitlines() or [""])[-1][:80].replace("|", "/")


def quality(res):
    against = any(b["label"] == "against" for b in res["builds"])
    out = ["| asset | level | tool | triangles | PSNR dB | seam band dB | SSIM | IoU | rel. Hausdorff | compare PBR dB | bytes |"
           + (" Δ PSNR vs against |" if against else ""),
           "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|" + ("---:|" if against else "")]
    for e in res["assets"]:
        for r in e["rows"]:
            tool = tool_name(r, against)
            if "error" in r:
                out.append("| %s | %s | %s | failed: %s |||||||%s" % (e["name"], r.get("lod", ""), tool, last_line(r["error"]),
                                                                    "|" if against else ""))
                continue
            delta = ""
            if against:
                delta = " %s%s |" % (fmt(r.get("psnrDelta"), "%+.2f"), " **worse**" if r.get("worse") else "")
            out.append("| %s | %d | %s | %d | %s | %s | %s | %s | %s | %s | %s |%s" % (
                e["name"], r["lod"], tool, r["triangles"], fmt(r.get("psnr")), fmt(r.get("psnr_seam")),
                fmt(r.get("ssim"), "%.4f"), fmt(r.get("iou"), "%.4f"), fmt(r.get("relHausdorff"), "%.4f"),
                fmt(r.get("comparePbrPsnr")), fmt(r.get("bytes"), "%d"), delta))
    lines = []
    for e in res["assets"]:
        for v in e.get("verdicts", []):
            if not v["win"]:
                lines.append("- %s LOD%d: a peer with as many or more triangles renders closer: %s" % (
                    e["name"], v["lod"], ", ".join(PEER_NAMES.get(p, p) for p in v["beatenBy"])))
    wins = sum(v["win"] for e in res["assets"] for v in e.get("verdicts", []))
    total = sum(len(e.get("verdicts", [])) for e in res["assets"])
    out += ["", "lodbake renders closer than every peer output with at least its triangles on %d of %d levels." % (wins, total)]
    ranked = [e for e in res["assets"] if e.get("rankAgreement")]
    if ranked:
        pairs = sum(e["rankAgreement"]["pairs"] for e in ranked)
        opposite = ["%s LOD%d/LOD%d" % (e["name"], a, b) for e in ranked for a, b in e["rankAgreement"]["opposite"]]
        out += ["", "compare's PBR mode orders our levels as three.js does on %d of %d level pairs (ties within 0.1 dB "
                    "left out)%s." % (pairs - len(opposite), pairs, "; opposite: " + ", ".join(opposite) if opposite else "")]
    ordered = [e for e in res["assets"] if "outOfOrder" in e]
    if ordered:
        above = ["%s LOD%d +%.2f dB" % (e["name"], o["lod"], o["above"]) for e in ordered for o in e["outOfOrder"]]
        out += ["", "No level renders more than 0.3 dB closer than the level before it on %d of %d assets%s." % (
            len(ordered) - len({e["name"] for e in ordered if e["outOfOrder"]}), len(ordered),
            "; above the level before: " + ", ".join(above) if above else "")]
    posed = [(e, r) for e in res["assets"] for r in e["rows"] if r.get("posed")]
    if posed:
        out += ["", "| asset | level | build | posed Hausdorff start / middle / end | posed IoU start / middle / end |",
                "|---|---:|---|---|---|"]
        for e, r in posed:
            p = [r["posed"][t] or {} for t in ("start", "middle", "end")]
            out.append("| %s | %d | %s | %s | %s |" % (e["name"], r["lod"], r["build"],
                                                     " / ".join(fmt(x.get("hausdorff"), "%.4g") for x in p),
                                                     " / ".join(fmt(x.get("iou"), "%.4f") for x in p)))
    return "\n".join(out + ([""] + lines if lines else []))


def scale(res):
    out = ["| input | triangles | tool | build | wall s | CPU s | peak MB | GB per M triangles | split (s) |",
           "|---|---:|---|---|---:|---:|---:|---:|---|"]
    notes = []
    for e in res["assets"]:
        for r in e["rows"]:
            if "error" in r:
                out.append("| %s | %d | %s | %s | failed: %s |||||" % (e["name"], e["triangles"], r["tool"], r.get("build", ""),
                                                                      last_line(r["error"])))
                continue
            split = r.get("stages") and ", ".join("%s %.1f" % (t, stage_work(v)) for t, v in r["stages"].items()) or \
                ", ".join("%s %.2f" % (k, v) for k, v in r.get("time", {}).items() if not k.endswith("Cpu"))
            out.append("| %s | %d | %s | %s | %.2f | %.2f | %.0f | %.2f | %s |" % (
                e["name"], e["triangles"], PEER_NAMES.get(r["tool"], r["tool"]), r.get("build", ""), r["wall"], r["cpu"],
                r["peakMB"], r["gbPerMTriangles"], split))
        ok = {(r["tool"], r.get("build")): r for r in e["rows"] if "error" not in r}
        s, g = ok.get(("simplify", "bin")), ok.get(("gltfpack-debian", None))
        if e.get("role") == "simplify" and s and g and g["wall"] > 0:
            ratio = s["wall"] / g["wall"]
            notes.append("- %s: simplify / Debian gltfpack %.2f× wall, %.2f× CPU (goal ≤ 2×: %s)" % (
                e["name"], ratio, s["cpu"] / max(g["cpu"], 1e-9), "met" if ratio <= 2 else "**not met**"))
        c = ok.get(("lodbake", "bin"))
        if e.get("role") == "chain" and c:
            worst = max(r["gbPerMTriangles"] for (t, b), r in ok.items() if b == "bin")
            if e["triangles"] >= 5e6:  # the ten-million input: its goal is the machine's memory
                notes.append("- %s: whole chain %.1f s (%.1f min); peak %.1f GB (goal within 24 GB: %s)" % (
                    e["name"], c["wall"], c["wall"] / 60, c["peakMB"] / 1024, "met" if c["peakMB"] <= 24 * 1024 else "**not met**"))
                continue
            at_1m = ""
            if 0.9e6 <= e["triangles"] <= 1.2e6:
                at_1m = "; goal ≤ 30 s at 1M: %s" % ("met" if c["wall"] <= 30 else "**not met**")
            notes.append("- %s: whole chain %.1f s; largest peak %.2f GB per M input triangles (goal < 1: %s)%s" % (
                e["name"], c["wall"], worst, "met" if worst < 1 else "**not met**", at_1m))
    return "\n".join(out + ([""] + notes if notes else []))


def output(res):
    variants = res["settings"]["variants"]
    out = []
    for e in res["assets"]:
        for label, m in e["builds"].items():
            title = "%s (%d input triangles)%s" % (e["name"], e["triangles"], " [%s]" % label if len(e["builds"]) > 1 else "")
            if "error" in m:
                out += ["", "%s: skipped: %s" % (title, m["error"].splitlines()[-1][:120] if m["error"] else "")]
                continue
            out += ["", title, "", "| lod | triangles | ACMR before → after | " + " | ".join(
                "%s: geometry + images B, GPU kB" % v for v in variants) + " |", "|---:|---:|---|" + "---|" * len(variants)]
            for lv in m["levels"]:
                cells = []
                for v in variants:
                    c = lv["variants"].get(v)
                    cells.append("%d + %d, %.1f" % (c["geometryBytes"], c["imageBytes"], c["gpuBytes"] / 1e3) if c else "failed")
                out.append("| %d | %d | %.3f → %.3f | %s |" % (lv["lod"], lv["triangles"], lv["acmrBefore"], lv["acmrAfter"],
                                                               " | ".join(cells)))
            out += ["", "File bytes: " + ", ".join("%s %d" % (v, b) for v, b in m["files"].items())]
    return "\n".join(out).strip()


def hashes(res):
    e = res["assets"][0]
    text = "%d outputs hashed (scripts/output_hashes.sh)." % e["outputs"]
    if "differ" in e:
        text += (" All identical between the builds." if not e["differ"] else
                 " %d differ between the builds:\n\n" % len(e["differ"]) + "\n".join("- `%s`" % t for t in e["differ"]))
    return text


def render(res):
    body = globals()[res["suite"]](res)
    return header(res) + "\n\n" + body + "\n"


def update(path, results, allow_contended=False):
    """Replaces each <!-- bench:SUITE --> ... <!-- /bench:SUITE --> section by the newest results of
    that suite; sections without results are left as they are, and so are timed suites whose run
    was on a loaded machine unless allow_contended."""
    with open(path) as f:
        text = f.read()
    newest = {}
    for r in sorted(results, key=lambda r: r["started"]):
        if contended(r) and not allow_contended:
            common.log("report: %s run of %s was on a loaded machine; not written (--allow-contended)"
                       % (r["suite"], r["started"]))
            continue
        newest[r["suite"]] = r
    for suite, res in newest.items():
        pattern = re.compile(r"(<!-- bench:%s -->\n).*?(<!-- /bench:%s -->)" % (suite, suite), re.S)
        if not pattern.search(text):
            common.log("report: %s has no <!-- bench:%s --> section; skipped" % (path, suite))
            continue
        text = pattern.sub(lambda m: m.group(1) + render(res) + m.group(2), text)
    with open(path, "w") as f:
        f.write(text)


def main(args):
    results = [common.read_json(p) for p in args.results]
    for r in results:
        if r.get("schema") != common.SCHEMA:
            raise SystemExit("report: %s is not a %s results file" % (r.get("suite", "?"), common.SCHEMA))
    if args.update:
        update(args.update, results, args.allow_contended)
    else:
        sys.stdout.write("\n".join("## %s\n\n%s" % (r["suite"], render(r)) for r in results))
    return 0
