#!/usr/bin/env bash
# Configures and builds lodbake into ./build (Release), through ccache when it is installed.
# LODBAKE_WERROR=ON turns warnings into errors.
set -euo pipefail
cd "$(dirname "$0")/.."
launcher=()
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DLODBAKE_WERROR="${LODBAKE_WERROR:-OFF}" "${launcher[@]}" >/dev/null
cmake --build build -j"$(nproc)"
