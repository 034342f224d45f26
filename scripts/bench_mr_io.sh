#!/usr/bin/env bash
# Benchmark (not a test): the time to read a stage output (e.g. simplify's .mr.glb, levels and
# pairs included, as parameterize reads it) and to encode and write it again, with lodbake's
# own reader and writer. Builds a small timing program against BIN's libraries once.
# Usage: scripts/bench_mr_io.sh FILE.glb    BUILD=build-dir (default build) RUNS=n (best of n)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build}
RUNS=${RUNS:-2}
IN=${1:?usage: scripts/bench_mr_io.sh FILE.glb}
PROG=$BUILD/bench_mr_io
SRC=$BUILD/bench_mr_io.cpp
cat >"$SRC.new" <<'CPP'
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <optional>

#include "lodbake/gltf/gltf.h"

using Clock = std::chrono::steady_clock;

// Wall and CPU seconds of one step.
struct Span {
    Clock::time_point wall = Clock::now();
    std::clock_t cpu = std::clock();
    void take(double& bestWall, double& bestCpu) const {
        double w = std::chrono::duration<double>(Clock::now() - wall).count();
        double c = double(std::clock() - cpu) / CLOCKS_PER_SEC;
        if (w < bestWall) bestWall = w, bestCpu = c;
    }
};

int main(int argc, char** argv) {
    if (argc != 4) return 2;
    const int runs = std::atoi(argv[3]);
    double read[2] = {1e30, 0}, encode[2] = {1e30, 0}, write[2] = {1e30, 0};
    size_t bytes = 0, levels = 0;
    for (int r = 0; r < runs; ++r) {
        Span t;
        std::optional<lodbake::Multires> mr;
        lodbake::Asset a = lodbake::readGltf(argv[1], {}, &mr);
        t.take(read[0], read[1]);
        const lodbake::Multires* m = mr ? &*mr : nullptr;
        levels = m ? m->levels.size() : 0;
        t = Span();
        bytes = lodbake::encodeGlb(argv[2], a, m).size();
        t.take(encode[0], encode[1]);
        t = Span();
        lodbake::writeGltf(argv[2], a, m);
        t.take(write[0], write[1]);
    }
    std::printf("%s: %.1f MB, %zu levels (best of %d, wall / cpu): read %.2f / %.2f s, encode %.2f / %.2f s, "
                "encode + write %.2f / %.2f s\n",
                argv[1], double(bytes) / 1e6, levels, runs, read[0], read[1], encode[0], encode[1], write[0], write[1]);
}
CPP
LIBS="$BUILD/liblodbake_gltf.a $BUILD/liblodbake_core.a"
if [ ! -x "$PROG" ] || ! cmp -s "$SRC" "$SRC.new" || [ "$BUILD/liblodbake_gltf.a" -nt "$PROG" ]; then
  mv "$SRC.new" "$SRC"
  TINYGLTF=$(grep -o '[^ ]*libtinygltf[^ ]*' "$BUILD/build.ninja" | head -1)
  g++ -std=c++17 -O2 -Ilib/include "$SRC" -o "$PROG" $LIBS "$TINYGLTF" -ldraco -lmeshoptimizer -lpthread
else
  rm -f "$SRC.new"
fi
OUTFILE=$(mktemp --suffix=.glb)
trap 'rm -f "$OUTFILE"' EXIT
"$PROG" "$IN" "$OUTFILE" "$RUNS"
