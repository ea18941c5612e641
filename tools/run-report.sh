#!/usr/bin/env bash
# The main job on its built-in default: installs what is missing, builds, and runs wrsfov-bench on
# the `text` and `atrium` scenes (FOV, FOV+TAA and WRS; fovea 5°, 7.5°, 10°; mip and gauss), which
# writes the report to out/report/: table.md, results.csv, error-vs-time and error-vs-fovea plots,
# and crops with FLIP error maps. Extra arguments go to wrsfov-bench (see --help).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh build
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
./build/tools/wrsfov-bench --out out/report "$@"
echo "== report in $(pwd)/out/report (table.md, results.csv, *.png)"
