#!/usr/bin/env bash
# The main job on its built-in default: installs what is missing, builds, and runs wrsfov-bench at a
# pixel density where foveation matters, 300 frames (3.3 s of gaze) per cell, fovea 5°, foveation mip:
#   out/report/monitor/  monitor mode (the paper's 76°x60° desktop setting) at 1024x768, scene text
#                        (reading): fov, wrs-paper, wrs and the two oracle bounds; static content, so no
#                        stale-pixel tracking (its evaluation-only buffers would count in the times)
#   out/report/hmd/      HMD stereo at 12.1 px/deg (the central 40°x40° of each eye, 504x504), scene
#                        dynamic (moving boxes, a light change, lateral head motion): fov, fov+taa,
#                        wrs-paper, wrs, the oracle and the retention oracle (oracle-q)
#   out/report/speed/    time and bytes at 512^2, 1024^2 and 2048^2 per eye (HMD stereo, atrium with
#                        depth and motion): fov, fov+taa, wrs-paper, wrs (scaling.md, scaling.png), and the
#                        static cost model of the same passes on an RX 7900 XTX (gfx1100) and a Steam Deck
#                        (vangogh) from RADV's null device (cost_model.md, cost_model.csv; a few seconds,
#                        skipped with the reason where the null device is missing; sparse retention's
#                        share of retention tiles measured over frames 300-329 at 512^2 per eye)
#   out/report/steady/   fov and wrs at 512^2 per eye at steady state: timed over frames 300-329, after
#                        3.3 s of gaze, so the area the gaze visited (where wrs runs retention) is a
#                        user's (the sweep above times frames 5-19)
#   out/report/headset/  the same at a headset's field of view (100 degrees per eye, 768x768, the atrium):
#                        the target, quad views at 0.4 of the density with a 30-degree inset composed
#                        without temporal reuse (fov, unjittered), against wide views at 0.3 and 0.2 rendered
#                        jittered over 8 phases with a 10-degree inset (9.5 % and 4.6 % of full resolution's
#                        pixels) composed with fov, taau (temporal upsampling as engines ship it, after FSR 2),
#                        taau-simple (the first, simpler upsampler) and wrs; moving/: dynamic with the head
#                        yawing at 60 degrees a second (384x384);
#                        JOD against pixels, one curve per method (jod_vs_pixels.png, .md: the fewest pixels
#                        at which each reaches the target); the index says whether wrs reaches the
#                        target's JOD with at most 10 % of the pixels (the wide-views issue's goal)
#   out/report/saving/   what rendering foveated saves (wrsfov-bench --saving): the atrium at the HMD
#                        cell's density (12.6 px/deg, 504x504 over 40x40 degrees) and the text page at the
#                        monitor's, each rendered at full resolution, as quad views (wide views at 0.4 of
#                        the density, insets of 5-30 degrees on the gaze) and at gaze-centred shading rates
#                        (atrium), composed with fov, wrs, the oracle and oracle-q: pixels, render and composition
#                        time, JOD, near-gaze PSNR, eta, and the inset wrs needs to match fov's at 30 and 20
#                        degrees (saving.md, saving.csv, saving.png). Short runs (0.5-0.7 s of gaze, JOD
#                        over the last 20 frames), to keep the job's time; --frames 300 gives the full
#                        measure, --outcomes what retention did where the inset left (docs/metrics.md)
# The two cells also report FovVideoVDP JOD per method and the fovea each method at 5 degrees is worth
# (the fov fovea of equal JOD, and of equal near-gaze PSNR; fov swept over 5-15 degrees), both over the
# last 30 frames of the cell (fovea_worth.csv, table.md).
# Each has table.md (summary first), results.csv, plots and crops; out/report/index.md links them.
# Order: the speed stages alone, then the other cells two at a time, longest first (below).
# With arguments, runs one wrsfov-bench with them instead (see wrsfov-bench --help), into out/report.
set -euo pipefail
cd "$(dirname "$0")/.."
# Only what the report runs: the tests are the test command's to build.
WRSFOV_BUILD_TARGETS=wrsfov-bench bash tools/setup.sh build
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
bench=./build/tools/wrsfov-bench
if [ "$#" -gt 0 ]; then
  "$bench" --out out/report "$@"
  echo "== report in $(pwd)/out/report (table.md, results.csv, *.png)"
  exit 0
fi
rm -rf out/report
mkdir -p out/report
start=$(date +%s)
common=(--frames 300 --fovea 5 --modes mip --copy-every 10)
# FovVideoVDP JOD and the fovea each method is worth (fov also at 7.5-15 degrees) over the last
# $jod_frames frames of each cell: JOD over all 290 counted frames, and the sweep over them, would
# take the job well past its time on this machine (docs/metrics.md, "In the benchmark").
jod_frames=30
worth=(--jod-frames "$jod_frames" --fovea-worth 7.5,10,12.5,15)
# The speed stages run alone: their times are what they measure. The other cells run two at a time:
# with one lavapipe thread each (LP_NUM_THREADS, below) a cell keeps one of this machine's 2 cores busy
# (99 % of a core, measured alone for the headset target and a jittered headset cell), so two side by
# side keep both (docs/metrics.md, "The main job's time"); their quality figures are the same either
# way, their times are taken on a shared CPU (ratios
# against the copy kernel in the same submission hold, absolute milliseconds do not: read speed/).
# They start longest first, each as soon as one of the two running ends (no stage waits for its
# slower cell), and each says how long it took. Lavapipe splits a dispatch across one thread per cell
# rather than one per core (LP_NUM_THREADS), so that two cells do not keep four threads on two cores.
rcdir=out/report/.cells
mkdir -p "$rcdir"
cell() {  # cell NAME ARGS...: one wrsfov-bench in the background once fewer than two run, its lines prefixed with NAME
  local name=$1
  shift
  while [ "$(jobs -rp | wc -l)" -ge 2 ]; do wait -n || true; done
  echo "$name: started (at $(($(date +%s) - start)) s)"
  { local t0=$SECONDS rc=0
    LP_NUM_THREADS="${LP_NUM_THREADS:-1}" "$bench" "$@" 2>&1 | grep --line-buffered -E '^\[|^saving|^wrsfov-bench' | sed -u "s|^|$name: |" || rc=$?
    echo "$name: done in $((SECONDS - t0)) s (exit $rc)"
    echo "$rc" > "$rcdir/$name"; } &
}
wait_cells() {  # waits for every cell; fails if any failed
  wait
  local failed=()
  for f in "$rcdir"/*; do [ "$(cat "$f")" = 0 ] || failed+=("$(basename "$f")"); done
  rm -rf "$rcdir"
  [ ${#failed[@]} -eq 0 ] || { echo "== cells failed: ${failed[*]} (their lines above)"; exit 1; }
}
stage() { echo "== $1 (at $(($(date +%s) - start)) s): $2"; }
stage 1/3 "speed, HMD stereo, atrium, 512^2 to 2048^2 per eye; then at steady state, 512^2 per eye, frames 300-329"
"$bench" --scaling 512,1024,2048 --methods fov,fov+taa,wrs-paper,wrs --cost-model --out out/report/speed \
  | grep --line-buffered -E '^\[|^wrsfov-bench'
"$bench" --scaling 512 --frames 330 --warmup 300 --methods fov,wrs --out out/report/steady \
  | grep --line-buffered -E '^\[|^wrsfov-bench'
# What compositing a headset's frames costs (a few seconds, no GPU needed): the headset cell's quad views
# (100° per eye, wide views at 0.3 of the density jittered over 8 phases, a 10° inset) at 2 x 1920^2 and
# at the Steam Deck's 2 x 1832x1920, fov, taau and wrs, from the compiler's statistics on RADV's null device.
"$bench" --cost-model --cost-quad --hmd-fov 100 --wide-scale 0.3 --inset-degs 10 --jitter 8 --size 1920x1920 \
  --methods fov,taau,wrs --out out/report/headset/cost | grep --line-buffered -E '^wrsfov-bench'
stage 2/3 "eight cells, two at a time, longest first: monitor mode (text, 1024x768); HMD stereo (dynamic, 504x504 per eye over 40x40 degrees); rendering saved on the text (monitor mode, 13.5 px/deg) and the atrium (HMD stereo, 12.6 px/deg); a headset's field of view (atrium, 100 degrees per eye at 768x768): jittered wide views at 0.3 and 0.2, the unjittered target, and moving content (dynamic, the head yawing at 60 degrees a second, 384x384)"
cell monitor --monitor --size 1024x768 --scenes text --methods fov,wrs-paper,wrs,oracle,oracle-q --no-stale "${common[@]}" \
  "${worth[@]}" --out out/report/monitor
cell hmd --hmd-fov 40 --size 504x504 --scenes dynamic --path lateral --methods fov,fov+taa,wrs-paper,wrs,oracle,oracle-q \
  "${common[@]}" "${worth[@]}" --out out/report/hmd
cell text --saving --scenes text --monitor --size 1024x768 --frames 45 --warmup 5 --jod-frames 20 \
  --inset-degs 5,10,20,30 --no-rate --out out/report/saving/text
cell atrium --saving --scenes atrium --hmd-fov 40 --size 504x504 --path lateral --frames 60 --warmup 10 --jod-frames 20 \
  --inset-degs 5,10,20,30 --rate-degs 20 --out out/report/saving/atrium
headset=(--saving --scenes atrium --hmd-fov 100 --size 768x768 --frames 60 --jod-frames 20 --no-rate)
cell jittered "${headset[@]}" --inset-degs 10 --wide-scale 0.3 --jitter 8 --methods fov,taau,taau-simple,wrs \
  --out out/report/headset/jittered
cell sparser "${headset[@]}" --inset-degs 10 --wide-scale 0.2 --jitter 8 --methods fov,taau,wrs \
  --out out/report/headset/sparser
# Moving content: dynamic's moving boxes with the head yawing at 60 °/s, the jittered 0.3 / 10° views at
# 384x384 per eye (half the headset cell's density, for the job's time), a test cell (seed 1).
cell moving --saving --scenes dynamic --path yaw60 --hmd-fov 100 --size 384x384 --frames 60 --jod-frames 20 --no-rate \
  --inset-degs 10 --wide-scale 0.3 --jitter 8 --methods fov,taau,taau-simple,wrs --split test --out out/report/headset/moving
cell target "${headset[@]}" --inset-degs 30 --methods fov --out out/report/headset/target
wait_cells
stage 3/3 "a headset's field of view: JOD against pixels across its three cells"
"$bench" --saving-plot out/report/headset/target/saving.csv,out/report/headset/jittered/saving.csv,out/report/headset/sparser/saving.csv \
  --saving-target fov,0.4,30 --out out/report/headset | grep -E '^wrsfov-bench'
{
  echo "# wrsfov report"
  echo
  echo "Two cells at a pixel density where foveation matters and a speed sweep, $(($(date +%s) - start)) s on this machine:"
  echo
  echo "- [monitor mode, text (reading), 1024x768](monitor/table.md)"
  echo "- [HMD stereo, dynamic scene, 12.1 px/deg](hmd/table.md)"
  echo "- [speed: time and bytes at 512^2, 1024^2, 2048^2 per eye](speed/scaling.md)"
  echo "- [cost model: the same passes on gfx1100 and vangogh, static estimate](speed/cost_model.md)"
  echo "- [speed at steady state: fov and wrs at 512^2 per eye after 3.3 s of gaze](steady/scaling.md)"
  echo "- [rendering saved: quad views and shading rates, atrium at 12.6 px/deg](saving/atrium/saving.md) and"
  echo "  [text at the monitor's density](saving/text/saving.md)"
  echo "- [a headset's compositing cost: fov, taau and wrs on its quad views, static estimate](headset/cost/cost_model.md)"
  echo "- [a headset's field of view: JOD against pixels](headset/jod_vs_pixels.md) from jittered wide views at"
  echo "  [0.3](headset/jittered/saving.md) and [0.2](headset/sparser/saving.md) composed with fov, taau and wrs (and taau-simple at 0.3),"
  echo "  against [the unjittered 30° target](headset/target/saving.md)"
  echo
  echo "## rendering saved"
  echo
  for s in atrium text; do
    sed -n '/^## Headline/,/^## Every composition/p' "out/report/saving/$s/saving.md" | sed '1d;$d'
  done
  echo
  echo "## a headset's field of view (100° per eye, atrium, 768x768: 5.6 px/deg at the centre)"
  echo
  echo "JOD against the pixels rendered, one curve per method ([every row](headset/jod_vs_pixels.md)):"
  echo
  echo "![JOD against pixels](headset/jod_vs_pixels.png)"
  echo
  sed -n '/^The target:/,/^## Every row/p' out/report/headset/jod_vs_pixels.md | sed '$d'
  awk -F, 'FNR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    $c["input"] == "full" { full = $c["pixels_rendered"]; next }
    FILENAME ~ /target/ { target = $c["jod"]; next }
    { d = $c["wide_density"]; m = $c["method"]; px[d] = $c["pixels_rendered"] / full; jod[m, d] = $c["jod"]
      inst[m, d] = $c["temporal_instability"]
      if (m == "wrs" && $c["jod"] >= target && (best == "" || px[d] < best)) { best = px[d]; bestJod = $c["jod"]; bestD = d } }
    END {
      met = best != "" && best <= 0.10
      printf "Goal (wrs reaches the 30°/0.4 target without temporal reuse, JOD %.2f, with at most 10 %% of full " \
             "resolution'"'"'s pixels): **%s**", target, met ? "met" : "not met"
      if (best != "") printf ": wrs %.2f JOD with %.1f %% of the pixels (wide density %s).", bestJod, 100 * best, bestD
      else printf ": no wrs row reaches it."
      for (d in px) {
        printf " At %.1f %% of the pixels: wrs %.2f against taau %.2f JOD (fov on the same jittered views %.2f); " \
               "temporal instability wrs %.4f, taau %.4f (%+.0f %%).", 100 * px[d], jod["wrs", d], jod["taau", d],
               jod["fov", d], inst["wrs", d], inst["taau", d], 100 * (inst["wrs", d] / inst["taau", d] - 1)
        if (("taau-simple", d) in jod)
          printf " The first upsampler, taau-simple: %.2f JOD, instability %.4f.", jod["taau-simple", d], inst["taau-simple", d]
      }
      printf "\n"
    }' out/report/headset/target/saving.csv out/report/headset/sparser/saving.csv out/report/headset/jittered/saving.csv
  echo
  echo "## moving content: dynamic, the head yawing at 60°/s (100° per eye, 384x384, jittered 0.3 / 10°; [every row](headset/moving/saving.md))"
  echo
  awk -F, 'FNR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    $c["input"] == "quad" { printf "- %s: JOD %.2f, temporal instability %.4f\n", $c["method"], $c["jod"], $c["temporal_instability"] }' \
    out/report/headset/moving/saving.csv
  echo
  for cell in monitor hmd; do
    echo "## $cell"
    echo
    sed -n '/^## Summary/,/^## Columns/p' "out/report/$cell/table.md" | sed '1d;$d'
    echo "FovVideoVDP JOD per method (foveated, over the last $jod_frames frames) and near-gaze PSNR over the same"
    echo "frames; PSNR over the 290 counted frames (fov (sweep), the fovea-worth sweep: over the $jod_frames frames):"
    echo
    echo "| method | fovea | JOD | near PSNR, same frames | PSNR |"
    echo "|---|---|---|---|---|"
    awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
      { printf "| %s%s | %s° | %.2f | %.2f | %.2f |\n", $c["method"], ($c["worth_sweep"] == 1 ? " (sweep)" : ""),
        $c["fovea_deg"], $c["jod"], $c["jod_near_gaze_psnr"], $c["psnr"] }' "out/report/$cell/results.csv"
    echo
  done
  echo "## a headset's compositing cost (static estimate, RADV null device)"
  echo
  echo "Per frame, both eyes: the headset cell's quad views (0.3 / 10°, 8 phases) at 2×1920² and the Steam Deck's 2×1832×1920"
  echo "([per pass](headset/cost/cost_model.md)):"
  echo
  { sed -n '/^## Totals per frame/,/^## GPUs/p' out/report/headset/cost/cost_model.md | grep -E '^\|' | head -2
    grep -E '^\| (gfx1100 \| 2x1920x1920|vangogh \| 2x1832x1920) ' out/report/headset/cost/cost_model.md; } || true
  echo
  echo "## speed"
  echo
  sed -n '/^| size per eye/,$p' out/report/speed/scaling.md
  echo
  echo "## speed at steady state (frames 300-329)"
  echo
  sed -n '/^| size per eye/,/^$/p' out/report/steady/scaling.md
} > out/report/index.md
cat out/report/index.md
echo "== report in $(pwd)/out/report (index.md, monitor/, hmd/, speed/, steady/, saving/, headset/)"
