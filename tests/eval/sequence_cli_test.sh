#!/bin/sh
# wrsfov-bench --write-sequence then --sequence: the atrium goes out as a sequence directory and
# comes back as the `sequence` scene of a sweep. The write takes its options from a --config file.
# usage: sequence_cli_test.sh WRSFOV_BENCH OUT_DIR
set -eu
bench="$1"
out="$2"
rm -rf "$out"
mkdir -p "$out"
# The scene, size and length come from a --config file (TOML), the directory from the command line.
printf '# wrsfov-bench options\nscenes = "atrium"\nsize = "64x48"\nframes = 6\n' > "$out/write.toml"
"$bench" --config "$out/write.toml" --write-sequence "$out/seq" > "$out/write.log" 2>&1 ||
  { cat "$out/write.log"; exit 1; }
grep -q "writing atrium, 64x48 per eye, 6 frames" "$out/write.log" || { cat "$out/write.log"; exit 1; }
for f in sequence.json gaze.csv 000000_L_color.png 000005_R_color.png 000005_R_depth.exr 000005_L_motion.exr; do
  [ -s "$out/seq/$f" ] || { echo "missing or empty: $out/seq/$f"; cat "$out/write.log"; exit 1; }
done
[ ! -e "$out/seq/000006_L_color.png" ] || { echo "wrote a frame too many"; exit 1; }
grep -q '"width": 64' "$out/seq/sequence.json"
# header + 6 rows
[ "$(wc -l < "$out/seq/gaze.csv")" -eq 7 ] || { echo "gaze.csv should have 7 lines"; exit 1; }
"$bench" --sequence "$out/seq" --out "$out/report" --fovea 5 --modes mip > "$out/bench.log" 2>&1 ||
  { cat "$out/bench.log"; exit 1; }
grep -q "64x48 per eye, 6 frames" "$out/bench.log" || { cat "$out/bench.log"; exit 1; }
# header + 1 scene x 1 mode x 1 fovea x 6 methods, all of scene `sequence`
[ "$(wc -l < "$out/report/results.csv")" -eq 7 ] || { cat "$out/report/results.csv"; exit 1; }
[ "$(grep -c '^sequence,' "$out/report/results.csv")" -eq 6 ] || { cat "$out/report/results.csv"; exit 1; }
# A broken sequence is refused with a message naming the file.
rm "$out/seq/000003_R_depth.exr"
if "$bench" --sequence "$out/seq" --out "$out/report2" > "$out/bad.log" 2>&1; then
  echo "a sequence without 000003_R_depth.exr was accepted"; exit 1
fi
grep -q "000003_R_depth.exr" "$out/bad.log" || { cat "$out/bad.log"; exit 1; }
echo "sequence CLI: write, evaluate and refuse all as expected"
