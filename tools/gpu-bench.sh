#!/usr/bin/env bash
# The check for a machine with a GPU (docs/speed.md "On a GPU"), made to fit in about five minutes:
# every stage runs under `timeout` within one budget, so a stage that hangs is reported as a timeout
# and the next one runs. In order:
#   speed/    the sweep at steady state, scene frames kept on the device (wrsfov-bench --scaling): HMD
#             stereo atrium (lateral, depth and motion), fov and wrs at 512^2, 1024^2, 2048^2 and
#             1920x2160 per eye, times over frames 300-329 after 3.3 s of the cell's gaze, beside the
#             copy kernels moving the same bytes (scaling.md, scaling.csv)
#   tests/    with WRSFOV_GPU_TESTS, the GPU tests against the CPU reference on this device, in shards
#             over the cores, as they run in CI
#   xr/       hello_xr (-g Vulkan2 -vc Stereo) on the wrsfov OpenXR runtime, headless, synthetic gaze,
#             2x1832x1920, method wrs and method fov: exit code and the runtime's composition time per
#             frame (its "session ended" line); a client that hangs at exit is reported as a timeout
#   saving/   the main job's atrium cell of the rendering saved (wrsfov-bench --saving): full
#             resolution against quad views and shading rates, render and composition times on this GPU
#   headset/  the wide-views issue's cell at 2x1920^2 without JOD (--saving --no-jod): the atrium at 100
#             degrees per eye, wide views at 0.3 jittered over 8 phases and a 10-degree inset, composed
#             with fov, taau and wrs: the composition time per frame the issue's goal reads (0.5 ms)
#   then, while the budget lasts: the tests again with WRSFOV_HARDWARE_HALF=0 (tests/), fov and wrs
#   with --dense-retention (dense/), and the cost model on this device and RADV's null devices (cost/)
#   summary.md  one table: sweep cells (ms, x copy, wrs - fov), tests passed/failed, hello_xr
#               exit codes and composition times; README.md: the device, the commands, the tables
# Usage: tools/gpu-bench.sh [OUT_DIR]   (default out/gpu-bench)
#   WRSFOV_GPU_BENCH_BUDGET_S (default 300): seconds for all stages together.
#   WRSFOV_GPU_BENCH_SIZES (default 512,1024,2048,1920x2160; S or WxH), WRSFOV_GPU_BENCH_FRAMES
#   (default 330; the last 30 are timed), WRSFOV_GPU_BENCH_METHODS (default fov,wrs).
#   WRSFOV_GPU_BENCH_XR_SIZE (default 1832x1920), WRSFOV_GPU_BENCH_XR_FRAMES (default 300).
#   WRSFOV_GPU_BENCH_DRY=1: a dry run sized for a CPU renderer (Mesa lavapipe): sizes 128,96x160,
#   40 frames, hello_xr at 192x192 for 60 frames, a few GPU tests (GTEST_FILTER given wins).
#   WRSFOV_BENCH=PATH runs that wrsfov-bench instead of building one, WRSFOV_GPU_TESTS=PATH runs that
#   wrsfov_gpu_tests, WRSFOV_XR_RUNTIME_JSON=PATH uses that runtime manifest (default: the build's),
#   WRSFOV_HELLO_XR=PATH that hello_xr (default: hello_xr on the PATH); tools/gpu-kit.sh carries all
#   four to a machine that cannot build.
set -uo pipefail
cd "$(dirname "$0")/.." || exit 1
out="${1:-out/gpu-bench}"
dry="${WRSFOV_GPU_BENCH_DRY:-0}"
if [ "$dry" = 1 ]; then
  sizes="${WRSFOV_GPU_BENCH_SIZES:-128,96x160}"
  frames="${WRSFOV_GPU_BENCH_FRAMES:-40}"
  xr_size="${WRSFOV_GPU_BENCH_XR_SIZE:-192x192}"
  xr_frames="${WRSFOV_GPU_BENCH_XR_FRAMES:-60}"
  export GTEST_FILTER="${GTEST_FILTER:-HardwareHalf.*:Import.*:Tiles.MonoViewsClassifyOneEye}"
else
  sizes="${WRSFOV_GPU_BENCH_SIZES:-512,1024,2048,1920x2160}"
  frames="${WRSFOV_GPU_BENCH_FRAMES:-330}"
  xr_size="${WRSFOV_GPU_BENCH_XR_SIZE:-1832x1920}"
  xr_frames="${WRSFOV_GPU_BENCH_XR_FRAMES:-300}"
fi
methods="${WRSFOV_GPU_BENCH_METHODS:-fov,wrs}"
budget="${WRSFOV_GPU_BENCH_BUDGET_S:-300}"
warmup=$((frames > 30 ? frames - 30 : frames / 2))
if [ -n "${WRSFOV_BENCH:-}" ]; then
  bench="$WRSFOV_BENCH"
else
  WRSFOV_BUILD_TARGETS="wrsfov-bench wrsfov_xr" bash tools/setup.sh build || exit 1
  bench=./build/tools/wrsfov-bench
fi
xr_json="${WRSFOV_XR_RUNTIME_JSON:-$PWD/build/runtime/wrsfov_xr.json}"
hello="${WRSFOV_HELLO_XR:-$(command -v hello_xr || true)}"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
rm -rf "$out"
mkdir -p "$out"
case "$out" in /*) ;; *) out="$PWD/$out" ;; esac
start=$(date +%s)
deadline=$((start + budget))
rows=""  # the summary's rows, Markdown

# stage_timeout CAP: seconds a stage may take (at most CAP, at most what is left of the budget);
# 0 when too little is left to start it.
stage_timeout() {
  local left=$((deadline - $(date +%s)))
  [ "$left" -gt "$1" ] && left=$1
  [ "$left" -lt 10 ] && left=0
  echo "$left"
}
# status_of RC: how a stage ended.
status_of() {
  case "$1" in
    0) echo "exit 0" ;;
    124 | 137) echo "timeout" ;;
    *) echo "exit $1" ;;
  esac
}

echo "== 1: sweep at steady state ($sizes per eye, $methods, frames $warmup-$((frames - 1)) timed)"
t=$(stage_timeout 120)
sweep_rc=-1
if [ "$t" -gt 0 ]; then
  s0=$(date +%s)
  timeout -k 5 "$t" "$bench" --scaling "$sizes" --frames "$frames" --warmup "$warmup" --methods "$methods" \
    --out "$out/speed" >"$out/speed.log" 2>&1
  sweep_rc=$?
  grep -E '^\[|^wrsfov-bench' "$out/speed.log"
  echo "   $(status_of $sweep_rc) in $(($(date +%s) - s0)) s"
fi
device=$(sed -n 's/.*Measured on \*\*\([^*]*\)\*\*.*/\1/p' "$out/speed/scaling.md" 2>/dev/null | head -1)
[ -n "$device" ] || device="unknown"
case "$device" in
  *llvmpipe*|*lavapipe*|*SwiftShader*) echo "== note: $device renders on the CPU: these are a CPU's times" ;;
esac
if [ -f "$out/speed/scaling.csv" ]; then
  # width,height,scene,method,mode,megapixels,total_ms,copy_ms,copy_floor_ms,B/px,floor B/px,x fov,x copy,...
  rows+=$(awk -F, -v st="$(status_of $sweep_rc)" 'NR > 1 {
      size = $1 "×" $2; key[NR] = size; m[NR] = $4; ms[NR] = $7; cp[NR] = $13
      if ($4 == "fov") fov[size] = $7
    }
    END {
      for (i = 2; i <= NR; ++i) {
        d = (m[i] != "fov" && key[i] in fov) ? sprintf("%+.3f", ms[i] - fov[key[i]]) : ""
        printf "| sweep | %s | %s | %.3f | %.2f | %s | %s |\n", key[i], m[i], ms[i], cp[i], d, st
      }
    }' "$out/speed/scaling.csv")$'\n'
else
  rows+="| sweep | $sizes | $methods | | | | $(status_of $sweep_rc) (no scaling.csv; speed.log) |"$'\n'
fi

# run_tests NAME [VAR=VALUE]: the GPU tests in shards over the cores; adds a summary row.
run_tests() {
  local name=$1 env_set=${2:-} shards cap t0
  shards=$(nproc)
  cap=90
  local t
  t=$(stage_timeout "$cap")
  local what
  what=$([ "$name" = ci ] && echo "GPU tests, as in CI" || echo "GPU tests, $env_set")
  if [ "$t" -eq 0 ]; then
    rows+="| $what | | | | | | skipped: budget spent |"$'\n'
    return
  fi
  t0=$(date +%s)
  for ((i = 0; i < shards; i++)); do
    ( [ -n "$env_set" ] && export "${env_set?}"
      GTEST_TOTAL_SHARDS=$shards GTEST_SHARD_INDEX=$i timeout -k 5 "$t" "$WRSFOV_GPU_TESTS" \
        >"$out/tests/$name.$i.log" 2>&1 ) &
  done
  local timedout=0
  for job in $(jobs -p); do
    wait "$job"
    case $? in 124 | 137) timedout=$((timedout + 1)) ;; esac
  done
  local ok failed nfailed
  ok=$(cat "$out/tests/$name".*.log | grep -c '^\[       OK \]' || true)
  failed=$(cat "$out/tests/$name".*.log | grep -E '^\[  FAILED  \] [A-Za-z].*\(' |
    sed 's/, where GetParam.*//; s/ (.*//; s/^\[  FAILED  \] //' | sort -u || true)
  nfailed=$(printf '%s' "$failed" | grep -c . || true)
  local line="$ok passed, $nfailed failed${failed:+: $(echo $failed)}"
  [ "$timedout" -gt 0 ] && line+="; $timedout of $shards shards timed out after $t s"
  echo "   $what: $line ($(($(date +%s) - t0)) s)"
  rows+="| $what | | | | | | $line |"$'\n'
}

if [ -n "${WRSFOV_GPU_TESTS:-}" ]; then
  echo "== 2: GPU tests against the CPU reference, $(nproc) shards${GTEST_FILTER:+, filter $GTEST_FILTER}"
  mkdir -p "$out/tests"
  run_tests ci
fi

echo "== 3: hello_xr on the wrsfov runtime, ${xr_size} per eye, $xr_frames frames, wrs and fov"
mkdir -p "$out/xr"
xr_w=${xr_size%x*}
xr_h=${xr_size#*x}
for m in wrs fov; do
  if [ -z "$hello" ] || [ ! -f "$xr_json" ]; then
    rows+="| hello_xr | ${xr_w}×${xr_h} | $m | | | | skipped: no hello_xr or runtime manifest |"$'\n'
    continue
  fi
  t=$(stage_timeout 40)
  if [ "$t" -eq 0 ]; then
    rows+="| hello_xr | ${xr_w}×${xr_h} | $m | | | | skipped: budget spent |"$'\n'
    continue
  fi
  log="$out/xr/hello_xr_$m.log"
  # hello_xr quits when stdin ends: its stdin is a fifo held open and never written, so only the
  # runtime's frame limit ends the session; once the log shows the session ended, the fifo's writer is
  # closed, so that hello_xr's key-press thread leaves getchar() and releases stdin's lock, which
  # exit() takes on glibc 2.39 and later (docs/openxr-runtime.md, "Teardown").
  rm -f "$out/xr/stdin"
  mkfifo "$out/xr/stdin"
  exec 3<>"$out/xr/stdin"
  t0=$(date +%s)
  env XR_RUNTIME_JSON="$xr_json" WRSFOV_XR_WIDTH="$xr_w" WRSFOV_XR_HEIGHT="$xr_h" WRSFOV_XR_METHOD="$m" \
    WRSFOV_XR_OUTPUT=headless WRSFOV_XR_GAZE=generator WRSFOV_XR_GAZE_MODE=scene WRSFOV_XR_FRAMES="$xr_frames" \
    timeout -k 5 "$t" "$hello" -g Vulkan2 -vc Stereo <"$out/xr/stdin" >"$log" 2>&1 3>&- &
  pid=$!
  while kill -0 "$pid" 2>/dev/null && ! grep -q "session ended" "$log" 2>/dev/null; do sleep 0.2; done
  exec 3>&-
  wait "$pid"
  rc=$?
  ended=$(grep -o 'session ended: [0-9]* frames ended, [0-9]* composited' "$log" | head -1 | sed 's/session ended: //')
  ms=$(sed -n 's/.*; compositor \([0-9.]*\) ms per frame from xrEndFrame to completion.*/\1/p' "$log" | head -1)
  [ -n "$ms" ] && ms=$(printf '%.3f' "$ms")
  st=$(status_of $rc)
  [ "$st" = timeout ] && st="timeout after $t s"
  echo "   $m: $st, ${ended:-no session end logged}, composition ${ms:-?} ms per frame ($(($(date +%s) - t0)) s)"
  rows+="| hello_xr | ${xr_w}×${xr_h} | $m | ${ms:-n/a} | | | $st; ${ended:-no session end logged} |"$'\n'
done

# The diagnosis of hello_xr's hang at exit, checked where it was seen: the same run with stdin left open
# after the session ended. On glibc 2.39 and later it is expected to time out (exit() waits for stdin's
# lock); on older C libraries it exits 0.
glibc=$(ldd --version 2>/dev/null | head -1 | sed 's/.* //')
t=$(stage_timeout 25)
if [ -n "$hello" ] && [ -f "$xr_json" ] && [ "$t" -gt 0 ]; then
  log="$out/xr/hello_xr_stdin_open.log"
  rm -f "$out/xr/stdin"
  mkfifo "$out/xr/stdin"
  exec 3<>"$out/xr/stdin"
  env XR_RUNTIME_JSON="$xr_json" WRSFOV_XR_WIDTH=192 WRSFOV_XR_HEIGHT=192 WRSFOV_XR_METHOD=wrs \
    WRSFOV_XR_OUTPUT=headless WRSFOV_XR_FRAMES=30 \
    timeout -k 5 "$t" "$hello" -g Vulkan2 -vc Stereo <"$out/xr/stdin" >"$log" 2>&1 3>&-
  rc=$?
  exec 3>&-
  st=$(status_of $rc)
  echo "   stdin left open after the session (glibc ${glibc:-?}): $st"
  rows+="| hello_xr, stdin left open (glibc ${glibc:-?}) | 192×192 | wrs | | | | $st (expected: timeout on glibc ≥ 2.39, 0 before) |"$'\n'
fi

echo "== 4: rendering saved (--saving): the atrium at full resolution, as quad views and at shading rates"
# The main job's cell (docs/metrics.md, "Rendering saved") on this device: its render times are this GPU's.
if [ "$dry" = 1 ]; then saving=(--size 128x128 --frames 16 --warmup 4 --jod-frames 6 --inset-degs 10,20 --rate-degs 10)
else saving=(--size 504x504 --frames 90 --warmup 10 --jod-frames 10 --inset-degs 5,10,20,30 --rate-degs 10,20); fi
t=$(stage_timeout 120)
if [ "$t" -gt 0 ]; then
  # fov, wrs and the oracle only: a fourth composition (the retention oracle, whose JOD the main job
  # reports) would take the stage past its timeout at this size (89 s for three methods on an H200).
  timeout -k 5 "$t" "$bench" --saving --scenes atrium --hmd-fov 40 --path lateral --methods fov,wrs,oracle "${saving[@]}" --out "$out/saving" \
    >"$out/saving.log" 2>&1
  st=$(status_of $?)
  echo "   $st"
  head=$(sed -n '/^## Headline/,/^Goal/p' "$out/saving/saving.md" 2>/dev/null | grep '^- ' | head -1 | sed 's/|/\\|/g')
  rows+="| rendering saved (atrium) | ${saving[1]} | fov, wrs, oracle | | | | $st; ${head:-no headline} |"$'\n'
else
  echo "   skipped: budget spent"
  rows+="| rendering saved (atrium) | | | | | | skipped: budget spent |"$'\n'
fi

echo "== 4b: a headset's jittered quad views (--saving --no-jod): 100 degrees per eye, the wide-views issue's cell"
# The composition time the wide-views issue's goal reads (wrs on jittered quad views at 2x1920^2, at most
# 0.5 ms), beside fov (composition alone) and taau on the same views.
if [ "$dry" = 1 ]; then headset=(--size 128x128 --frames 12 --warmup 4)
else headset=(--size 1920x1920 --frames 40 --warmup 10); fi
t=$(stage_timeout 90)
if [ "$t" -gt 0 ]; then
  timeout -k 5 "$t" "$bench" --saving --no-jod --no-rate --scenes atrium --hmd-fov 100 --inset-degs 10 --wide-scale 0.3 \
    --jitter 8 --methods fov,taau,wrs "${headset[@]}" --out "$out/headset" >"$out/headset.log" 2>&1
  st=$(status_of $?)
  echo "   $st"
  # compose_ms: the median compositor time per frame, both eyes (PassTimes::total).
  ms=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next } $c["input"] == "quad" {
         printf "%s%s %.3f ms", sep, $c["method"], $c["compose_ms"]; sep = ", " }' "$out/headset/saving.csv" 2>/dev/null)
  rows+="| headset, jittered quad views (0.3, 10°) | ${headset[1]} | fov, taau, wrs | | | | $st; composition ${ms:-n/a} |"$'\n'
else
  echo "   skipped: budget spent"
  rows+="| headset, jittered quad views | | | | | | skipped: budget spent |"$'\n'
fi

if [ -n "${WRSFOV_GPU_TESTS:-}" ]; then
  echo "== 5: GPU tests with the hand fp16 conversion (WRSFOV_HARDWARE_HALF=0)"
  run_tests half0 WRSFOV_HARDWARE_HALF=0
fi

echo "== 6: fov and wrs with every tile retaining (--dense-retention)"
t=$(stage_timeout 60)
if [ "$t" -gt 0 ]; then
  timeout -k 5 "$t" "$bench" --scaling "$sizes" --frames "$frames" --warmup "$warmup" --methods fov,wrs \
    --dense-retention --out "$out/dense" >"$out/dense.log" 2>&1
  echo "   $(status_of $?)"
else
  echo "   skipped: budget spent"
fi

echo "== 7: cost model on this device and on RADV's null devices"
# A real device's name without the driver's parenthesised suffix ("AMD Radeon RX 7900 XTX (RADV NAVI31)").
short=$(printf '%s' "$device" | sed 's/ (.*//')
t=$(stage_timeout 60)
if [ "$t" -gt 0 ]; then
  timeout -k 5 "$t" "$bench" --cost-model --cost-targets "device:$short,gfx1100,vangogh" --out "$out/cost" \
    >"$out/cost.log" 2>&1
  echo "   $(status_of $?)"
else
  echo "   skipped: budget spent"
fi

took=$(($(date +%s) - start))
{
  echo "# wrsfov GPU check on $device"
  echo
  echo "$(date -u +%Y-%m-%d), $took s of a $budget s budget, commit ${WRSFOV_COMMIT:-$(git rev-parse --short HEAD 2>/dev/null || echo unknown)}$([ "$dry" = 1 ] && echo ", dry run (WRSFOV_GPU_BENCH_DRY=1)")."
  echo "Sweep: \`wrsfov-bench --scaling $sizes --frames $frames --warmup $warmup --methods $methods\`, atrium, HMD"
  echo "stereo, fovea 5°, mip; ms per frame for both eyes (medians of the timed frames), ×copy against a copy"
  echo "kernel moving the method's bytes in the same run. hello_xr: composition time per frame from xrEndFrame to"
  echo "completion, as the runtime logs it at session end."
  echo
  echo "| check | size per eye | method | ms | ×copy | wrs − fov ms | result |"
  echo "|---|---|---|---|---|---|---|"
  printf '%s' "$rows"
} >"$out/summary.md"
{
  echo "# wrsfov on $device"
  echo
  echo "$(date -u +%Y-%m-%d), $took s, commit ${WRSFOV_COMMIT:-$(git rev-parse --short HEAD 2>/dev/null || echo unknown)}."
  echo
  echo "- [summary](summary.md)"
  echo "- [speed sweep at steady state](speed/scaling.md): \`wrsfov-bench --scaling $sizes --frames $frames --warmup $warmup --methods $methods\`"
  echo "- [dense retention](dense/scaling.md): the same with \`--methods fov,wrs --dense-retention\`"
  echo "- [cost model](cost/cost_model.md): \`wrsfov-bench --cost-model --cost-targets device:$short,gfx1100,vangogh\`"
  echo "- hello_xr logs: xr/"
  for f in "$out/speed/scaling.md" "$out/dense/scaling.md"; do
    [ -f "$f" ] && { echo; sed -n '/^| size per eye/,/^$/p' "$f"; }
  done
  [ -f "$out/cost/cost_model.md" ] && { echo; sed -n '/^## Totals/,/^## [^T]/p' "$out/cost/cost_model.md" | sed '$d'; }
} >"$out/README.md"
echo
cat "$out/summary.md"
echo "== GPU check output in $out ($took s)"
