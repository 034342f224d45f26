"""hashes: sha256 of every tool's output on every generated sample and shared asset, with the flag
sets the tests use (scripts/output_hashes.sh), for --bin and, with --against, for the second
build: the list of outputs whose bytes differ. Issue 33 asks for byte-identical output before and
after a speed-up, or a quality table that shows no level worse where bytes change."""
import os
import subprocess

from . import common

SCRIPT = os.path.join(common.SOURCE, "scripts/output_hashes.sh")


def add_arguments(p):
    pass


def hash_list(build):
    p = subprocess.run(["bash", SCRIPT, build.bin], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        raise SystemExit("bench: output_hashes.sh failed: " + p.stderr[-500:])
    out = {}
    for line in p.stdout.splitlines():
        if line.startswith("#"):
            continue
        digest, _, tag = line.partition("  ")
        if tag:
            out[tag] = digest
        else:  # "<tag> exit <code>": a run that failed
            out[line.rsplit(" exit ", 1)[0]] = line
    return out


def run(args, builds, results):
    if args.assets or args.quick:
        common.log("hashes: output_hashes.sh always covers every sample and shared asset; --assets/--quick ignored")
    lists = {}
    for b in builds:
        common.log("hashes: %s" % b.bin)
        lists[b.label] = hash_list(b)
    entry = {"name": "all", "outputs": len(lists["bin"]), "hashes": lists["bin"]}
    if "against" in lists:
        a, b = lists["against"], lists["bin"]
        entry["differ"] = sorted(t for t in set(a) | set(b) if a.get(t) != b.get(t))
    results["assets"].append(entry)
