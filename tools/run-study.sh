#!/usr/bin/env bash
# The moving-content study (docs/metrics.md, "The moving-content study"): a headset's 100° per eye,
# cells of scene and head motion, each at several seeds, each seed's frames composed on the same
# views by fov, taau (after FSR 2) and wrs, and the cell's target: fov on
# unjittered 0.4 / 30° quad views. Then wrsfov-bench --study pairs the methods over the seeds (95 %
# intervals), finds the pixels each needs to reach its cell's target and judges the goals on the test
# cells. Writes out/study/ (study.md, study.csv, study.png; each run's saving.csv and saving.md under
# runs/).
#   train cells (where parameters are chosen: wrs's steady display weight and landed footprint were
#   searched on dynamic turn, its full speed on both; taau's on the atrium's lateral cell,
#   docs/retention.md): dynamic turn, atrium yaw60
#   test cells: atrium yaw120, dynamic yaw60, dynamic look-around, thin look-around, photo turn
# Usage: tools/run-study.sh [OUT]   (default out/study)
#   STUDY_SIZE (320: 3.2 px/deg at the centre, for this machine's time; the main job's headset cells run
#   768), STUDY_FRAMES (120), STUDY_SCORED (40: JOD and temporal instability over the last 40 frames),
#   STUDY_SEEDS ("1 2 3"), STUDY_CELLS (the cells above, as split:scene:path, e.g. "test:thin:yaw30"),
#   STUDY_METHODS (fov,taau,wrs; add taau-simple or oracle), STUDY_ARGS (more wrsfov-bench options for
#   every run, e.g. --landed-weights), STUDY_TARGET (1; 0: no target runs, for a variant of a method
#   compared with an earlier study's rows), STUDY_JOBS (2: runs side by side, one lavapipe thread each).
# On this 2-core machine without a GPU the default study takes 30-60 minutes (24 min for six cells
# beside the test suite on one day's machine, 52 on a slower day's; seven cells since).
set -euo pipefail
cd "$(dirname "$0")/.."
WRSFOV_BUILD_TARGETS=wrsfov-bench bash tools/setup.sh build
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
bench=./build/tools/wrsfov-bench
out=${1:-out/study}
size=${STUDY_SIZE:-320}
frames=${STUDY_FRAMES:-120}
scored=${STUDY_SCORED:-40}
seeds=${STUDY_SEEDS:-1 2 3}
jobs_max=${STUDY_JOBS:-2}
methods=${STUDY_METHODS:-fov,taau,wrs}
read -r -a extra <<< "${STUDY_ARGS:-}"
targets=${STUDY_TARGET:-1}
cells=${STUDY_CELLS:-"train:dynamic:turn train:atrium:yaw60 test:atrium:yaw120 test:dynamic:yaw60 test:dynamic:look-around test:thin:look-around test:photo:turn"}
rm -rf "$out"
mkdir -p "$out/runs"
start=$(date +%s)
failed="$out/.failed"
: > "$failed"
run() {  # run NAME ARGS...: one --saving run in the background once fewer than jobs_max run
  local name=$1
  shift
  while [ "$(jobs -rp | wc -l)" -ge "$jobs_max" ]; do wait -n || true; done
  echo "$name: started (at $(($(date +%s) - start)) s)"
  { local t0=$SECONDS
    if LP_NUM_THREADS=1 "$bench" --saving "$@" --out "$out/runs/$name" > "$out/runs/$name.log" 2>&1; then
      echo "$name: done in $((SECONDS - t0)) s"
    else
      echo "$name: FAILED (exit $?), see $out/runs/$name.log"; echo "$name" >> "$failed"
    fi; } &
}
common=(--hmd-fov 100 --size "${size}x${size}" --frames "$frames" --jod-frames "$scored" --no-rate)
for c in $cells; do
  IFS=: read -r split scene path <<< "$c"
  if [ "$scene" = photo ]; then
    motion=(--scenes photo --photo-motion "$path")
  else
    motion=(--scenes "$scene" --path "$path")
  fi
  for seed in $seeds; do
    cellargs=("${motion[@]}" "${common[@]}" --seed "$seed" --split "$split" ${extra[@]+"${extra[@]}"})
    tag="$split-$scene-$path-s$seed"
    run "$tag-wide0.3" "${cellargs[@]}" --inset-degs 10 --wide-scale 0.3 --jitter 8 --methods "$methods"
    run "$tag-wide0.2" "${cellargs[@]}" --inset-degs 10 --wide-scale 0.2 --jitter 8 --methods "$methods"
    [ "$targets" = 0 ] || run "$tag-target" "${cellargs[@]}" --inset-degs 30 --wide-scale 0.4 --methods fov
  done
done
wait
if [ -s "$failed" ]; then
  echo "== runs failed: $(tr '\n' ' ' < "$failed")"
  exit 1
fi
rm -f "$failed"
csvs=$(find "$out/runs" -name saving.csv | sort | paste -sd, -)
if [ "$targets" = 0 ]; then
  echo "== runs in $(pwd)/$out/runs after $(($(date +%s) - start)) s (no target runs: no study summary)"
  exit 0
fi
"$bench" --study "$csvs" --out "$out" | grep -E '^wrsfov-bench|^- '
echo "== study in $(pwd)/$out (study.md, study.png) after $(($(date +%s) - start)) s"
