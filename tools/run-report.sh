#!/usr/bin/env bash
# The main job on its built-in default: installs what is missing, builds, runs wrsfov-demo.
# Extra arguments go to wrsfov-demo (see --help). Output: out/demo/ (summary.md, stats.csv, PNGs).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh build
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
./build/tools/wrsfov-demo --out out/demo "$@"
echo "== report in $(pwd)/out/demo"
