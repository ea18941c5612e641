#!/bin/sh
# wrsfov-bench --quick end to end: every output file is written and the table has every cell.
# usage: bench_quick_test.sh WRSFOV_BENCH OUT_DIR [MORE wrsfov-bench OPTIONS]
set -eu
bench="$1"
out="$2"
shift 2
rm -rf "$out"
"$bench" --quick --out "$out" "$@" > "$out.log" 2>&1 || { cat "$out.log"; exit 1; }
grep -q "cell 4/4" "$out.log" || { echo "no progress lines"; cat "$out.log"; exit 1; }
for f in results.csv table.md jod_vs_time_text_mip.png error_vs_time_text_mip.png error_vs_time_atrium_mip.png error_vs_fovea_text_mip.png \
         error_vs_fovea_atrium_mip.png eta_text_mip.png eta_atrium_mip.png crops_text_mip_5.png crops_atrium_mip_5.png; do
  [ -s "$out/$f" ] || { echo "missing or empty: $out/$f"; exit 1; }
done
# header + 2 scenes x 1 mode x 2 foveas x 6 methods
rows=$(wc -l < "$out/results.csv")
[ "$rows" -eq 25 ] || { echo "results.csv has $rows lines, expected 25"; exit 1; }
# every timing and ratio is a finite positive number (the pyramid may take no measurable time; wrs
# and the oracles have no separate foveate pass)
awk -F, 'NR > 1 { for (i = 6; i <= 15; i++) if (!($i + 0 > 0) && i != 7 && !(i == 8 && ($2 == "wrs" || $2 == "oracle" || $2 == "oracle-q"))) { print "bad value in column " i ": " $0; exit 1 } }' \
  "$out/results.csv"
# JOD (column 22, beside PSNR): a score in (0, 10] for every method
head -1 "$out/results.csv" | grep -q ",psnr,jod,ssim," || { echo "no jod column beside psnr"; exit 1; }
awk -F, 'NR > 1 && !($22 > 0 && $22 <= 10) { print "bad JOD: " $0; exit 1 }' "$out/results.csv"
# η_q (columns 35, 36): 1 for the retention oracle itself and 0 for fov wherever that oracle gains
head -1 "$out/results.csv" | grep -q ",eta_q,eta_q_near_gaze,retain_share,jod_frames,jod_near_gaze_psnr,worth_sweep$" || { echo "no eta_q, retain_share or jod_frames columns"; exit 1; }
awk -F, 'NR > 1 && ($2 == "oracle-q" || $2 == "fov") { want = $2 == "fov" ? 0 : 1
  for (i = 35; i <= 36; i++) if ($i != "nan" && ($i - want > 1e-9 || want - $i > 1e-9)) { print "eta_q of " $2 ": " $0; exit 1 } }' \
  "$out/results.csv"
# retain_share (column 37): none for methods without the retain pass, every tile for the oracle (no
# sparse retention: it chooses among equally sharp samples), a share in (0, 1] for wrs and oracle-q
awk -F, 'NR > 1 { m = $2; v = $37
  if ((m == "fov" || m == "wrs-paper") && v != "nan") { print "retain_share of " m ": " $0; exit 1 }
  if (m == "oracle" && v != 1) { print "retain_share of oracle: " $0; exit 1 }
  if ((m == "wrs" || m == "oracle-q") && !(v > 0 && v <= 1)) { print "retain_share of " m ": " $0; exit 1 } }' \
  "$out/results.csv"
grep -q "Equal-quality fovea" "$out/table.md"
grep -q "^## Summary" "$out/table.md"
grep -q "^| oracle | 5.0°" "$out/table.md"
grep -q "^| oracle-q | 5.0°" "$out/table.md"
grep -q "^| wrs-paper | 5.0°" "$out/table.md"
grep -q "^| wrs | 5.0°" "$out/table.md"
# error by eccentricity: 24 cells x 5 bands, the shares of one cell summing to 1
grep -q "^## Error by eccentricity" "$out/table.md"
grep -q "^| oracle gain share |" "$out/table.md"
grep -q "^| oracle-q gain share |" "$out/table.md"
grep -q "^| η_q wrs |" "$out/table.md"
rows=$(wc -l < "$out/ecc_bands.csv")
[ "$rows" -eq 121 ] || { echo "ecc_bands.csv has $rows lines, expected 121"; exit 1; }
awk -F, 'NR > 1 { k = $1 FS $2 FS $3 FS $4; s[k] += $7 } END { for (k in s) if (s[k] < 0.999999 || s[k] > 1.000001) { print "band shares of " k " sum to " s[k]; exit 1 } }'   "$out/ecc_bands.csv"
echo "bench --quick: all outputs present"
