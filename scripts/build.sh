#!/usr/bin/env bash
# Configures and builds lodbake into ./build (Release). LODBAKE_WERROR=ON turns warnings into errors.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DLODBAKE_WERROR="${LODBAKE_WERROR:-OFF}" >/dev/null
cmake --build build -j"$(nproc)"
