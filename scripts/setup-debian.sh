#!/usr/bin/env bash
# Installs everything lodbake needs on a fresh Debian 12 machine: the build toolchain, the
# libraries (Debian's packages) and the node tools used by tests and benchmarks.
set -euo pipefail
cd "$(dirname "$0")/.."
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq \
  cmake ninja-build g++ make pkg-config python3 time \
  libtinygltf-dev libdraco-dev libmeshoptimizer-dev libceres-dev libsuitesparse-dev libcgal-dev libeigen3-dev libjemalloc-dev \
  libopenimageio-dev openimageio-tools nlohmann-json3-dev libgtest-dev \
  gltfpack chromium python3-numpy python3-jsonschema dpkg-dev assimp-testmodels snakemake >/dev/null
if ! command -v npm >/dev/null 2>&1; then
  $SUDO apt-get install -y -qq nodejs npm >/dev/null
fi
# Khronos glTF-Validator, the peer tools, Babylon.js, three.js + playwright-core (browser tests and
# scripts/render_three.py: they drive Debian's chromium, never download a browser), pinned by
# scripts/node/package-lock.json. python3-numpy: render_three.py's PSNR/SSIM.
# python3-jsonschema: the report schema test; dpkg-dev: dpkg-shlibdeps for `cpack -G DEB`.
# Blender (a peer in scripts/bench.py's speed and quality suites) is optional: apt-get install blender.
(cd scripts/node && npm ci --silent --no-audit --no-fund)
echo "setup: dependencies installed"
