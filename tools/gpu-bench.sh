#!/usr/bin/env bash
# The speed kit for a machine with a GPU (docs/speed.md "On a GPU"): builds wrsfov-bench, then writes
# one directory with
#   speed/   the speed sweep at steady state: HMD stereo atrium (lateral, depth and motion), fov,
#            fov+taa, wrs-paper and wrs at 512^2 and 1024^2 per eye, times taken over frames 300-329
#            (3.3 s of the cell's gaze first, so the area the gaze visited is a user's), the share of
#            tiles that ran retention beside each time (scaling.md, scaling.csv)
#   dense/   fov and wrs with --dense-retention at the same sizes: what sparse retention saves
#   cost/    the cost model for this GPU (its compiler's statistics where its driver gives them) and
#            for RADV's null devices, gfx1100 and vangogh, to set the prediction beside the measurement
#   tests/   with WRSFOV_GPU_TESTS, the GPU tests against the CPU reference on this device, in shards
#            over the cores, once as they run in CI and once with WRSFOV_HARDWARE_HALF=0
#   README.md  the device, the commands and where each table is
# Usage: tools/gpu-bench.sh [OUT_DIR]   (default out/gpu-bench)
#   WRSFOV_GPU_BENCH_SIZES (default 512,1024; 2048 adds about 6 minutes: the sweep is bound by the
#   host, which uploads every method's images each frame), WRSFOV_GPU_BENCH_FRAMES (default 330; the
#   last 30 are timed), WRSFOV_GPU_BENCH_METHODS (default fov,fov+taa,wrs-paper,wrs).
#   WRSFOV_BENCH=PATH runs that wrsfov-bench instead of building one, WRSFOV_GPU_TESTS=PATH runs that
#   wrsfov_gpu_tests (tools/gpu-kit.sh carries both to a machine that cannot build).
#   On a CPU renderer (Mesa lavapipe) it runs, says so, and its times are a CPU's.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-out/gpu-bench}"
sizes="${WRSFOV_GPU_BENCH_SIZES:-512,1024}"
frames="${WRSFOV_GPU_BENCH_FRAMES:-330}"
methods="${WRSFOV_GPU_BENCH_METHODS:-fov,fov+taa,wrs-paper,wrs}"
warmup=$((frames > 30 ? frames - 30 : frames / 2))
if [ -n "${WRSFOV_BENCH:-}" ]; then
  bench="$WRSFOV_BENCH"
else
  WRSFOV_BUILD_TARGETS=wrsfov-bench bash tools/setup.sh build
  bench=./build/tools/wrsfov-bench
fi
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
rm -rf "$out"
mkdir -p "$out"
start=$(date +%s)

echo "== 1/4: speed sweep at steady state ($sizes per eye, frames $warmup-$((frames - 1)) timed)"
"$bench" --scaling "$sizes" --frames "$frames" --warmup "$warmup" --methods "$methods" \
  --out "$out/speed" | tee "$out/speed.log" | grep --line-buffered -E '^\[|^wrsfov-bench'
device=$(sed -n 's/.*Measured on \*\*\([^*]*\)\*\*.*/\1/p' "$out/speed/scaling.md" | head -1)
[ -n "$device" ] || device="unknown"
case "$device" in
  *llvmpipe*|*lavapipe*|*SwiftShader*) echo "== note: $device renders on the CPU: these are a CPU's times" ;;
esac

echo "== 2/4: fov and wrs with every tile retaining (--dense-retention)"
"$bench" --scaling "$sizes" --frames "$frames" --warmup "$warmup" --methods fov,wrs --dense-retention \
  --out "$out/dense" | tee "$out/dense.log" | grep --line-buffered -E '^\[|^wrsfov-bench'

echo "== 3/4: cost model on this device and on RADV's null devices"
# A real device's name without the driver's parenthesised suffix ("AMD Radeon RX 7900 XTX (RADV NAVI31)").
short=$(printf '%s' "$device" | sed 's/ (.*//')
"$bench" --cost-model --cost-targets "device:$short,gfx1100,vangogh" --out "$out/cost" | tee "$out/cost.log" \
  | grep --line-buffered -E '^\||^wrsfov-bench' || true

tests_summary=""
if [ -n "${WRSFOV_GPU_TESTS:-}" ]; then
  echo "== 4/4: GPU tests against the CPU reference, $(nproc) shards, with the device's fp16 conversion and without"
  mkdir -p "$out/tests"
  for half in default 0; do
    shards=$(nproc)
    for ((i = 0; i < shards; i++)); do
      ( if [ "$half" = 0 ]; then export WRSFOV_HARDWARE_HALF=0; fi
        GTEST_TOTAL_SHARDS=$shards GTEST_SHARD_INDEX=$i "$WRSFOV_GPU_TESTS" >"$out/tests/half-$half.$i.log" 2>&1 ) &
    done
    wait || true
    ok=$(cat "$out/tests/half-$half".*.log | grep -c '^\[       OK \]' || true)
    failed=$(cat "$out/tests/half-$half".*.log | grep -E '^\[  FAILED  \] [A-Za-z].*\(' | sed 's/, where GetParam.*//; s/ (.*//; s/^\[  FAILED  \] //' | sort -u || true)
    what=$([ "$half" = 0 ] && echo "WRSFOV_HARDWARE_HALF=0 (hand fp16 conversion)" || echo "as in CI (the device's fp16 conversion where the probe passes)")
    line="$what: $ok passed, $(printf '%s' "$failed" | grep -c . || true) failed${failed:+: $(echo $failed)}"
    echo "$line"
    tests_summary+="- $line"$'\n'
  done
fi

{
  echo "# wrsfov on $device"
  echo
  echo "$(date -u +%Y-%m-%d), $(($(date +%s) - start)) s, commit ${WRSFOV_COMMIT:-$(git rev-parse --short HEAD 2>/dev/null || echo unknown)}."
  echo
  echo "- [speed sweep at steady state](speed/scaling.md): \`wrsfov-bench --scaling $sizes --frames $frames --warmup $warmup --methods $methods\`"
  echo "- [dense retention](dense/scaling.md): the same with \`--methods fov,wrs --dense-retention\`"
  echo "- [cost model](cost/cost_model.md): \`wrsfov-bench --cost-model --cost-targets device:$short,gfx1100,vangogh\`"
  echo
  sed -n '/^| size per eye/,/^$/p' "$out/speed/scaling.md"
  echo
  sed -n '/^| size per eye/,/^$/p' "$out/dense/scaling.md"
  echo
  [ -f "$out/cost/cost_model.md" ] && sed -n '/^## Totals/,/^## [^T]/p' "$out/cost/cost_model.md" | sed '$d'
  if [ -n "$tests_summary" ]; then
    echo
    echo "GPU tests (tests/): "
    printf '%s' "$tests_summary"
  fi
} > "$out/README.md"
cat "$out/README.md"
echo "== kit output in $out"
