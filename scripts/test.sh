#!/usr/bin/env bash
# Builds (incrementally) and runs the whole test suite. Tests that need ../shared/assets skip
# with a message when it is absent.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
ctest --test-dir build --output-on-failure -j"$(nproc)" "$@"
