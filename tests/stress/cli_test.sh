#!/bin/sh
# End-to-end checks of wrsfov-stress: cli_test.sh BINARY OUT_DIR
set -u
bin=$1 out=$2
rm -rf "$out"
mkdir -p "$out"
. "$(dirname "$0")/../cli_check.sh"
check() { cli_check "$@"; }  # check NAME EXPECTED_RC PATTERN COMMAND...

check small_run 0 "All [0-9]* checks pass" "$bin" --quick --frames 3000 --pixels 4 --gpu-frames 30 --gpu-width 4 \
    --formats chosen,f32,wsum16 --out "$out/report"
check progress 0 "\[cpu\] 100 %" cat "$out/small_run.log"
check table 0 "| constant | pipeline |" cat "$out/report/report.md"
check csv 0 "constant,pipeline,wsum16," cat "$out/report/report.csv"
check gpu_csv 0 "^0,constant," cat "$out/report/gpu.csv"
check horizon_csv 0 "^weights,chosen,1,1," cat "$out/report/horizon.csv"
check plots 0 "" test -s "$out/report/wsum_constant.png" -a -s "$out/report/wsum_out-of-range.png"
check cpu_only 0 "" "$bin" --quick --frames 2000 --pixels 2 --gpu-frames 0 --streams constant,spikes --formats chosen
check help 0 "--gpu-frames" "$bin" --help
check help_defaults 0 "Default: 1000000\." "$bin" --help
check bad_frames 2 "--frames: 'ten' is not 0 or an integer in 2\.\.4294967295" "$bin" --frames ten
check one_frame 2 "--frames: '1' is not 0 or an integer" "$bin" --frames 1
check negative 2 "--pixels: '-3' is not an integer in 1\.\.65536" "$bin" --pixels -3
check bad_stream 2 "--streams: 'nope' is not one of constant, " "$bin" --streams constant,nope
check stream_twice 2 "--streams: 'spikes' is listed twice" "$bin" --streams spikes,constant,spikes
check bad_format 2 "--formats: 'fp8' is not one of chosen, " "$bin" --formats fp8
check missing_value 2 "--out: missing value (DIR)" "$bin" --out
check unknown_option 2 "unknown option --fast" "$bin" --fast
check nothing 2 "nothing to run" "$bin" --frames 0 --gpu-frames 0
check twice 2 "--seed: given 2 times; give it once" "$bin" --seed 1 --seed 2
check version 0 "^wrsfov-stress [0-9][0-9.]*$" "$bin" --version

[ "$fails" -eq 0 ] || { echo "$fails check(s) failed"; exit 1; }
