#!/bin/sh
# Builds the libFuzzer targets with clang and runs each for a bounded time:
#   fuzz_hid   the HID report-descriptor parser and eye-tracker report decoding;
#   fuzz_text  sequence.json, a sequence's gaze.csv and gaze recordings (project CSV, Pupil, Tobii).
#   tools/fuzz.sh [SECONDS]     (default 30 per target)
# Crashes are written to build-fuzz/artifacts/; the script exits non-zero if a fuzzer found one.
set -eu
seconds=${1:-30}
case $seconds in *[!0-9]*|'') echo "usage: $0 [SECONDS]" >&2; exit 2;; esac
root=$(cd "$(dirname "$0")/.." && pwd)
build=${WRSFOV_FUZZ_BUILD:-$root/build-fuzz}
command -v clang++ >/dev/null || { echo "fuzz: clang++ is needed (apt-get install clang)" >&2; exit 1; }
CC=clang CXX=clang++ cmake -S "$root/fuzz" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build" --target fuzz_hid fuzz_text -j2 >/dev/null
corpus=$build/corpus
mkdir -p "$corpus" "$build/artifacts" "$build/corpus_text"
# Seed: the standard eye tracker's descriptor and a tracking report, in the target's input layout
# (two bytes of descriptor length, descriptor, report).
seed() {  # seed NAME HEXFILE...
    name=$1; shift
    hex=$(cat "$@" | tr -d ' \n\r')
    desc=$(tr -d ' \n\r' <"$1")
    len=$(( ${#desc} / 2 ))
    lenhex=$(printf '%02x%02x' $((len % 256)) $((len / 256)))
    fmt=
    for b in $(printf '%s%s' "$lenhex" "$hex" | sed 's/../& /g'); do fmt="$fmt$(printf '\\%03o' "0x$b")"; done
    printf "$fmt" >"$corpus/$name"
}
data=$root/tests/gaze/data
seed standard "$data/eyetracker_descriptor.hex" "$data/eyetracker_report.hex"
seed feature "$data/eyetracker_descriptor.hex" "$data/eyetracker_feature.hex"
# The two targets run at the same time, one core each (each fuzzer is one process): their log follows.
run() {  # run TARGET CORPUS MAX_LEN: in the background, its output in $build/TARGET.log
    echo "fuzz: $1 for $seconds s (corpus $2)"
    "$build/$1" -max_total_time="$seconds" -max_len="$3" -timeout=10 -rss_limit_mb=2048 \
        -artifact_prefix="$build/artifacts/$1-" -print_final_stats=1 "$2" >"$build/$1.log" 2>&1 &
}
run fuzz_hid "$corpus" 8192
hid_pid=$!
# fuzz_text seeds: a selector byte (fuzz_text.cpp: sequence.json; gaze.csv of 3 frames; project
# CSV, Pupil Labs, Tobii recordings), then the file.
text=$build/corpus_text
seeds=$root/fuzz/seeds
{ printf '\000'; cat "$seeds/sequence.json"; } >"$text/sequence_json"
{ printf '\011'; cat "$seeds/gaze.csv"; } >"$text/sequence_gaze"
{ printf '\006'; cat "$data/project_bad_rows.csv"; } >"$text/project_csv"
{ printf '\012'; cat "$data/pupil_gaze_positions.csv"; } >"$text/pupil"
{ printf '\016'; cat "$data/tobii_export.tsv"; } >"$text/tobii"
run fuzz_text "$text" 16384
text_pid=$!
hid_rc=0 text_rc=0
wait "$hid_pid" || hid_rc=$?
wait "$text_pid" || text_rc=$?
for t in fuzz_hid fuzz_text; do
    echo "== $t"
    cat "$build/$t.log"
done
if [ "$hid_rc" -ne 0 ] || [ "$text_rc" -ne 0 ]; then
    echo "fuzz: a target failed (fuzz_hid: exit $hid_rc, fuzz_text: exit $text_rc); inputs in $build/artifacts/" >&2
    exit 1
fi
