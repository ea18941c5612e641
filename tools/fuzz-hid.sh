#!/bin/sh
# Builds the HID descriptor/report libFuzzer target with clang and runs it for a bounded time.
#   tools/fuzz-hid.sh [SECONDS]     (default 30)
# Crashes are written to build-fuzz/artifacts/; the script exits non-zero if the fuzzer found one.
set -eu
seconds=${1:-30}
case $seconds in *[!0-9]*|'') echo "usage: $0 [SECONDS]" >&2; exit 2;; esac
root=$(cd "$(dirname "$0")/.." && pwd)
build=${WRSFOV_FUZZ_BUILD:-$root/build-fuzz}
command -v clang++ >/dev/null || { echo "fuzz-hid: clang++ is needed (apt-get install clang)" >&2; exit 1; }
CC=clang CXX=clang++ cmake -S "$root/fuzz" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build" --target fuzz_hid -j2 >/dev/null
corpus=$build/corpus
mkdir -p "$corpus" "$build/artifacts"
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
echo "fuzz-hid: running for $seconds s (corpus $corpus)"
"$build/fuzz_hid" -max_total_time="$seconds" -max_len=8192 -timeout=10 -rss_limit_mb=2048 \
    -artifact_prefix="$build/artifacts/" -print_final_stats=1 "$corpus"
