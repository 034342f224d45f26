#!/usr/bin/env python3
"""lodbake's benchmark harness: one entry, one suite per measurement kind, one JSON file per run.

    python3 scripts/bench.py SUITE --bin DIR [--against DIR] [--out results.json] [--reps N]
                             [--assets NAME ...] [--quick] [suite flags]
    python3 scripts/bench.py report results.json... [--update docs/benchmarks.md]

Suites (`python3 scripts/bench.py SUITE --help` lists each one's flags):
  speed    whole-chain wall time, CPU, peak RSS and stage split per asset, beside the peers
  quality  three.js renders of every level against the original: ours vs gltfpack and Blender
  scale    1M-10M triangle inputs: every stage and lodbake (time, GB per M triangles);
           simplify vs gltfpack and agsphere-build on the subdivided bunnies
  output   bytes per level and format (plain, Draco, meshopt, quantized, KTX2), GPU estimate, ACMR
  hashes   sha256 of every tool's output (scripts/output_hashes.sh) for --bin and --against
Inputs (--assets): a file, a folder name of ../shared/assets, a make-samples sample (walker, ...)
or NAME-xN, the shared asset subdivided N times (aliases duck-1M, bunny-1M, bunny-4M, avocado-3M,
avocado-11M), made once and cached in --work. Benchmarks, not tests: figures are for a quiet
machine; the results file records the load average before and after every run.
"""
import argparse
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench import common, hashes, output, quality, report, scale, speed  # noqa: E402

SUITES = {"speed": speed, "quality": quality, "scale": scale, "output": output, "hashes": hashes}


def parse(argv):
    ap = argparse.ArgumentParser(prog="bench.py", description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__.split("\n\n", 1)[1])
    sub = ap.add_subparsers(dest="suite", required=True)
    for name, module in SUITES.items():
        p = sub.add_parser(name, help=module.__doc__.split("\n")[0], description=module.__doc__)
        p.add_argument("--bin", required=True, help="bin dir of the build measured")
        p.add_argument("--against", help="bin dir of a second build measured in the same run (e.g. an older commit)")
        p.add_argument("--out", help="results file (default WORK/SUITE-YYYYmmdd-HHMMSS.json)")
        p.add_argument("--assets", nargs="+", help="inputs (default: the suite's set)")
        p.add_argument("--quick", action="store_true", help="a smoke run: the suite's smallest set, one rep")
        p.add_argument("--work", default=os.path.join(common.SOURCE, "out/bench"),
                       help="outputs and cached inputs (default out/bench)")
        p.add_argument("--ratio", default="0.5,0.1,0.02", help="the chain's levels (default 0.5,0.1,0.02)")
        module.add_arguments(p)
    p = sub.add_parser("report", help="Markdown tables from results files",
                       description="Prints Markdown tables for results files, or with --update rewrites the "
                                   "generated sections of a Markdown file (between <!-- bench:SUITE --> and "
                                   "<!-- /bench:SUITE -->) from them.")
    p.add_argument("results", nargs="+")
    p.add_argument("--update", metavar="FILE.md", help="rewrite the generated sections of FILE.md in place")
    p.add_argument("--allow-contended", action="store_true",
                   help="--update: also write speed and scale runs taken on a loaded machine (marked as such)")
    return ap.parse_args(argv)


def main(argv=None):
    args = parse(sys.argv[1:] if argv is None else argv)
    if args.suite == "report":
        return report.main(args)
    if args.quick and "--reps" not in sys.argv:
        args.reps = 1
    args.work = os.path.abspath(args.work)
    os.makedirs(args.work, exist_ok=True)
    out = args.out or os.path.join(args.work, "%s-%s.json" % (args.suite, time.strftime("%Y%m%d-%H%M%S")))
    started = time.monotonic()
    build_list = common.builds(args)
    results = common.start_results(args.suite, args, build_list)
    try:
        SUITES[args.suite].run(args, build_list, results)
    finally:
        common.finish_results(results, out, started)
    print(report.render(results))
    return 0


if __name__ == "__main__":
    sys.exit(main())
