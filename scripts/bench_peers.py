#!/usr/bin/env python3
"""Peer comparison helper for scripts/bench_peers.sh: runs `compare ORIGINAL OUT [--lod K] --json`
for each (asset, ratio, tool, file, lod) row given as JSON on stdin, prints a Markdown table
(triangles, draw calls, lit PBR and base-colour PSNR, relative Hausdorff, silhouette IoU, file bytes) and a
verdict per asset/ratio: ours must beat, in PBR PSNR (compare's lit physically based render, with
every material channel), every peer output with >= our triangle count."""
import json
import os
import subprocess
import sys


def measure(compare, original, out, lod, extra):
    args = [compare, original, out, "--json"] + extra
    if lod:
        args += ["--lod", str(lod)]
    p = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode not in (0, 1):
        return {"error": p.stderr.strip()[-300:]}
    j = json.loads(p.stdout)
    b = j["counts"]["b"]
    return {"triangles": b["triangles"], "drawCalls": b["drawCalls"], "psnr": j["images"]["pbr"]["psnr"],
            "basePsnr": j["images"]["baseColor"]["psnr"],
            "relHausdorff": j["geometry"]["relHausdorff"], "iou": j["images"]["baseColor"]["iou"], "bytes": b["fileBytes"], "texels": b["texels"]}


def main():
    compare = sys.argv[1]
    extra = sys.argv[2:]
    rows = json.load(sys.stdin)
    results = []
    for r in rows:
        m = measure(compare, r["original"], r["file"], r.get("lod", 0), extra) if os.path.exists(r["file"]) else {"error": "no output"}
        results.append(dict(r, **m))
    print("| asset | ratio | tool | triangles | draw calls | PBR PSNR (dB) | base-colour PSNR (dB) | rel. Hausdorff | silhouette IoU | bytes |")
    print("|---|---|---|---:|---:|---:|---:|---:|---:|---:|")
    for r in results:
        if "error" in r:
            print("| %s | %s | %s | failed: %s | | | | | | |" % (r["asset"], r["ratio"], r["tool"], r["error"].replace("|", "/")[:80]))
            continue
        print("| %s | %s | %s | %d | %d | %.2f | %.2f | %.4f | %.4f | %d |" % (
            r["asset"], r["ratio"], r["tool"], r["triangles"], r["drawCalls"], r["psnr"], r["basePsnr"], r["relHausdorff"], r["iou"],
            r["bytes"]))
    print()
    losses = 0
    for key in sorted({(r["asset"], r["ratio"]) for r in results}):
        group = [r for r in results if (r["asset"], r["ratio"]) == key and "error" not in r]
        ours = [r for r in group if r["tool"] == "lodbake"]
        if not ours:
            print("%s @ %s: no lodbake output" % key)
            losses += 1
            continue
        o = ours[0]
        beaten = [r for r in group if r["tool"] != "lodbake" and r["triangles"] >= o["triangles"] and r["psnr"] >= o["psnr"]]
        if beaten:
            losses += 1
            print("%s @ %s: LOSS: lodbake %.2f dB with %d triangles; %s" % (
                key[0], key[1], o["psnr"], o["triangles"],
                ", ".join("%s %.2f dB with %d triangles" % (r["tool"], r["psnr"], r["triangles"]) for r in beaten)))
        else:
            print("%s @ %s: win: lodbake %.2f dB with %d triangles, 1 draw call" % (key[0], key[1], o["psnr"], o["triangles"]))
    json.dump(results, open(os.environ.get("BENCH_JSON", "/dev/null"), "w"), indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
