#!/usr/bin/env bash
# Builds (incrementally) and runs the whole test suite. Tests that need ../shared/assets skip
# with a message when it is absent.
# Then the sanitizer tree: build-asan (cmake -DLODBAKE_SANITIZE=ON, -O1 with line tables for the
# stack traces), only the tools and make-samples, and the tests labelled `sanitize` there.
# LODBAKE_SANITIZE_TESTS=OFF skips that part for a quick local run; CI runs it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
ctest --test-dir build --output-on-failure -j"$(nproc)" "$@"
if [ "${LODBAKE_SANITIZE_TESTS:-ON}" != OFF ]; then
  launcher=()
  if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
  cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLODBAKE_SANITIZE=ON \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DLODBAKE_WERROR="${LODBAKE_WERROR:-OFF}" \
    "${launcher[@]}" >/dev/null
  cmake --build build-asan -j"$(nproc)" \
    --target simplify agsphere-build parameterize texture-refine pack lodbake compare make-samples
  ctest --test-dir build-asan --output-on-failure -j"$(nproc)" -L sanitize
fi
