#!/usr/bin/env bash
# The speed kit for a machine with a GPU (docs/speed.md "On a GPU"): builds wrsfov-bench, then writes
# one directory with
#   speed/   the speed sweep at steady state: HMD stereo atrium (lateral, depth and motion), fov,
#            fov+taa, wrs-paper and wrs at 512^2, 1024^2 and 2048^2 per eye, times taken over frames
#            300-329 (3.3 s of the cell's gaze first, so the area the gaze visited is a user's), the
#            share of tiles that ran retention beside each time (scaling.md, scaling.csv)
#   cost/    the cost model for this GPU (its compiler's statistics where its driver gives them) and
#            for RADV's null devices, gfx1100 and vangogh, to set the prediction beside the measurement
#   README.md  the device, the commands and where each table is
# Usage: tools/gpu-bench.sh [OUT_DIR]   (default out/gpu-bench)
#   WRSFOV_GPU_BENCH_SIZES (default 512,1024,2048), WRSFOV_GPU_BENCH_FRAMES (default 330; the last 30
#   are timed) shrink a trial run. On a CPU renderer (Mesa lavapipe) it runs, says so, and its times
#   are a CPU's.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-out/gpu-bench}"
sizes="${WRSFOV_GPU_BENCH_SIZES:-512,1024,2048}"
frames="${WRSFOV_GPU_BENCH_FRAMES:-330}"
warmup=$((frames > 30 ? frames - 30 : frames / 2))
WRSFOV_BUILD_TARGETS=wrsfov-bench bash tools/setup.sh build
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
bench=./build/tools/wrsfov-bench
rm -rf "$out"
mkdir -p "$out"
start=$(date +%s)

echo "== 1/2: speed sweep at steady state ($sizes per eye, frames $warmup-$((frames - 1)) timed)"
"$bench" --scaling "$sizes" --frames "$frames" --warmup "$warmup" --methods fov,fov+taa,wrs-paper,wrs \
  --out "$out/speed" | tee "$out/speed.log" | grep --line-buffered -E '^\[|^wrsfov-bench'
device=$(sed -n 's/.*Measured on \*\*\([^*]*\)\*\*.*/\1/p' "$out/speed/scaling.md" | head -1)
[ -n "$device" ] || device="unknown"
case "$device" in
  *llvmpipe*|*lavapipe*|*SwiftShader*) echo "== note: $device renders on the CPU: these are a CPU's times" ;;
esac

echo "== 2/2: cost model on this device and on RADV's null devices"
# A real device's name without the driver's parenthesised suffix ("AMD Radeon RX 7900 XTX (RADV NAVI31)").
short=$(printf '%s' "$device" | sed 's/ (.*//')
"$bench" --cost-model --cost-targets "device:$short,gfx1100,vangogh" --out "$out/cost" | tee "$out/cost.log" \
  | grep --line-buffered -E '^\||^wrsfov-bench' || true

{
  echo "# wrsfov on $device"
  echo
  echo "$(date -u +%Y-%m-%d), $(($(date +%s) - start)) s, commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)."
  echo
  echo "- [speed sweep at steady state](speed/scaling.md): \`wrsfov-bench --scaling $sizes --frames $frames --warmup $warmup --methods fov,fov+taa,wrs-paper,wrs\`"
  echo "- [cost model](cost/cost_model.md): \`wrsfov-bench --cost-model --cost-targets device:$short,gfx1100,vangogh\`"
  echo
  sed -n '/^| size per eye/,/^$/p' "$out/speed/scaling.md"
  echo
  [ -f "$out/cost/cost_model.md" ] && sed -n '/^## Totals/,/^## [^T]/p' "$out/cost/cost_model.md" | sed '$d'
} > "$out/README.md"
cat "$out/README.md"
echo "== kit output in $out"
