#!/bin/sh
# End-to-end checks of wrsfov-gaze: cli_test.sh BINARY DATA_DIR OUT_DIR
set -u
bin=$1 data=$2 out=$3
mkdir -p "$out"
. "$(dirname "$0")/../cli_check.sh"
check() { cli_check "$@"; }  # check NAME EXPECTED_RC PATTERN COMMAND...

check generate 0 "wrote 10000 samples" "$bin" generate --mode fixation --seconds 10 --rate 1000 --seed 3 \
    --out "$out/fix.csv" --plot "$out/fix.png"
check generate_again 0 "" "$bin" generate --mode fixation --seconds 10 --rate 1000 --seed 3 --out "$out/fix2.csv"
check same_seed_same_file 0 "" cmp "$out/fix.csv" "$out/fix2.csv"
check generate_other_seed 0 "" "$bin" generate --mode fixation --seconds 10 --rate 1000 --seed 4 --out "$out/fix3.csv"
check other_seed_differs 1 "" cmp -s "$out/fix.csv" "$out/fix3.csv"
check plots_written 0 "" test -s "$out/fix.png" -a -s "$out/fix_velocity.png"
check header 0 "t_s,frame,valid,left_x,left_y,left_z,right_x,right_y,right_z,label" head -n 1 "$out/fix.csv"
check stats 0 "microsaccade rate" "$bin" stats "$out/fix.csv"
check stats_reading_gen 0 "" "$bin" generate --mode reading --seconds 30 --rate 500 --seed 1 --out "$out/read.csv"
check stats_reading 0 "regressions" "$bin" stats "$out/read.csv" --reading --char-deg 0.3 --line-spacing-deg 1
check stats_pupil 0 "3 bad rows skipped" "$bin" stats "$data/pupil_gaze_positions.csv"
check stats_pupil_lines 0 "pupil_gaze_positions.csv:6: skipped" "$bin" stats "$data/pupil_gaze_positions.csv"
check stats_tobii 0 "Tobii Pro Lab TSV" "$bin" stats "$data/tobii_export.tsv"
check stats_missing 1 "cannot open" "$bin" stats "$out/none.csv"
check generate_bad_mode 2 "--mode: 'dance' is not one of fixation, scene, reading, pursuit" "$bin" generate --mode dance --seconds 1 --out "$out/x.csv"
check generate_bad_rate 2 "rate must be 90..1000" "$bin" generate --mode scene --seconds 1 --rate 5000 --out "$out/x.csv"
check hid_decode 0 '"gaze_point_um": \[250000, 140000\]' "$bin" hid-decode --descriptor "$data/eyetracker_descriptor.hex" \
    --report "$data/eyetracker_report.hex" --feature "$data/eyetracker_feature.hex"
check hid_decode_ts 0 '"timestamp_us": 123456789' "$bin" hid-decode --descriptor "$data/eyetracker_descriptor.hex" \
    --report "$data/eyetracker_report.hex"
check hid_decode_screen 0 '"screen_um": \[600000, 340000\]' "$bin" hid-decode \
    --descriptor "$data/eyetracker_descriptor.hex" --feature "$data/eyetracker_feature.hex"
head -c 30 "$data/eyetracker_descriptor.hex" >"$out/truncated.hex"
check hid_decode_truncated 1 "truncated\|not closed" "$bin" hid-decode --descriptor "$out/truncated.hex"
printf '01 02 03\n' >"$out/short_report.hex"
check hid_decode_short_report 1 "truncated" "$bin" hid-decode --descriptor "$data/eyetracker_descriptor.hex" \
    --report "$out/short_report.hex"
check list 0 "" "$bin" list
check record_missing 1 "recorded no samples" "$bin" record --device /dev/hidraw-none --out "$out/rec.csv" --seconds 0.6
check unknown_command 2 "unknown command 'frobnicate' (generate, stats, list, hid-decode, record, help)" "$bin" frobnicate
check help 0 "generate" "$bin" --help
check help_command 0 "hid-decode" "$bin" help
check help_command_generate 0 "--pursuit-speed" "$bin" help generate
check generate_help 0 "Default: 5 20\." "$bin" generate --help
check version 0 "^wrsfov-gaze [0-9][0-9.]*$" "$bin" --version
check seed_as_1e3 0 "seed 1000," "$bin" generate --mode fixation --seconds 1 --seed 1e3 --out "$out/seed.csv"
[ "$fails" -eq 0 ] || { echo "$fails check(s) failed"; exit 1; }
