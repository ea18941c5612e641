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
check bad_frames 2 "--frames 'ten'" "$bin" --frames ten
check negative 2 "--pixels" "$bin" --pixels -3
check bad_stream 2 "unknown stream 'nope'" "$bin" --streams constant,nope
check bad_format 2 "unknown format 'fp8'" "$bin" --formats fp8
check missing_value 2 "--out needs a value" "$bin" --out
check unknown_option 2 "unknown option '--fast'" "$bin" --fast
check nothing 2 "nothing to run" "$bin" --frames 0 --gpu-frames 0
check twice 2 "given twice" "$bin" --seed 1 --seed 2

[ "$fails" -eq 0 ] || { echo "$fails check(s) failed"; exit 1; }
