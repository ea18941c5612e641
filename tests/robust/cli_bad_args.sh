#!/bin/sh
# docs/bad-input.md, "Command lines": every bad argument of wrsfov-bench, wrsfov-demo and wrsfov-gaze
# ends with a non-zero exit status (2 usage, 1 run-time) and a message naming the problem, before any
# device work. usage: cli_bad_args.sh WRSFOV_BENCH WRSFOV_DEMO WRSFOV_GAZE GAZE_DATA_DIR OUT_DIR
set -u
bench=$1 demo=$2 gz=$3 data=$4 out=$5
rm -rf "$out"
mkdir -p "$out"
. "$(dirname "$0")/../cli_check.sh"
CLI_FIXED=1
check() {  # check NAME EXPECTED_RC PATTERN COMMAND...
    n=$1 w=$2 p=$3
    shift 3
    cli_check "$n" "$w" "$p" timeout 60 "$@"
}
: >"$out/afile"  # a regular file where a directory is needed

# ---- wrsfov-bench -------------------------------------------------------------------------------
check bench_option_missing_value 2 "--frames: missing value (N)" "$bench" --frames
check bench_option_unknown 2 "unknown option --bogus" "$bench" --bogus 1
for v in big 64x 8x8 0x0 99999x99999 -64x64 ""; do
    check "bench_size_'$v'" 2 "--size: '$v' is not WxH with W and H in 32..4096" "$bench" --size "$v"
done
for v in 0 -5 nan 100001 2.5 ""; do
    check "bench_frames_'$v'" 2 "--frames: '$v' is not an integer in 2..100000" "$bench" --frames "$v"
done
check bench_warmup_negative 2 "--warmup: '-1' is not an integer in 0..100000" "$bench" --warmup -1
check bench_frames_not_above_warmup 2 "--frames must exceed --warmup" "$bench" --frames 5 --warmup 5
check bench_heavy_every_zero 2 "--heavy-every: '0' is not an integer in 1..100000" "$bench" --heavy-every 0
for v in 10 5000 big -512 512,x 64x 1920x 1920x2160x2 0x0 32x64 64x5000 2.5 512,1920x10; do
    check "bench_scaling_'$v'" 2 "--scaling: '${v#512,}' is not S or WxH with each side in 64..4096" "$bench" --scaling "$v"
done
check "bench_scaling_''" 2 "--scaling needs at least one size" "$bench" --scaling ""
for v in -1 4294967296 seven ""; do
    check "bench_seed_'$v'" 2 "--seed: '$v' is not an integer in 0..4294967295" "$bench" --seed "$v"
done
for v in nan inf -inf 0 -5 61 abc; do
    check "bench_fovea_'$v'" 2 "--fovea: '$v' is not a number in (0, 60]" "$bench" --fovea "$v"
done
check bench_fovea_empty_list 2 "--fovea: missing value (DEG,...)" "$bench" --fovea ,
check bench_scenes_unknown 2 "--scenes: 'moon' is not one of text, atrium, dynamic, sequence" "$bench" --scenes moon
check bench_scenes_empty 2 "must not be empty" "$bench" --scenes ""
check bench_methods_unknown 2 "--methods: 'magic' is not one of fov, fov+taa, wrs-paper, wrs, oracle, oracle-q" "$bench" --methods magic
check bench_methods_empty 2 "--methods: missing value (NAME,...)" "$bench" --methods ,
check bench_modes_unknown 2 "--modes: 'blur' is not one of mip, gauss, none" "$bench" --modes blur
check bench_change_unknown 2 "--change: 'lab' is not one of off, lstar, de94" "$bench" --change lab
check bench_path_unknown 2 "--path: 'orbit' is not one of static, lateral, turn, yaw30, yaw60, yaw120, look-around" "$bench" --path orbit
check bench_out_not_a_directory 1 "cannot create $out/afile/sub" "$bench" --out "$out/afile/sub"
check bench_scene_sequence_without_dir 2 "scene 'sequence' needs --sequence DIR" "$bench" --scenes sequence
check bench_write_sequence_two_scenes 2 "--write-sequence writes one scene" "$bench" --write-sequence "$out/seq" --scenes text,atrium
check bench_write_sequence_empty 2 "--write-sequence: '' is not a directory name" "$bench" --write-sequence ""
check bench_sequence_missing 1 "sequence directory $out/none does not exist" "$bench" --sequence "$out/none"

# ---- wrsfov-demo --------------------------------------------------------------------------------
check demo_option_missing_value 2 "--fovea: missing value (DEG)" "$demo" --fovea
check demo_option_unknown 2 "unknown option --bogus" "$demo" --bogus 1
for v in big 16x 8x8 0x0 5000x5000 -16x16 ""; do
    check "demo_size_'$v'" 2 "--size: '$v' is not WxH with W and H in 16..4096" "$demo" --size "$v"
done
for v in 0 -5 nan 100001 1.5 ""; do
    check "demo_frames_'$v'" 2 "--frames: '$v' is not an integer in 1..100000" "$demo" --frames "$v"
done
for v in nan inf 0 -1 61 abc ""; do
    check "demo_fovea_'$v'" 2 "--fovea: '$v' is not a number in (0, 60]" "$demo" --fovea "$v"
done
check demo_mode_unknown 2 "--mode: 'blur' is not one of mip, gauss, none" "$demo" --mode blur
for v in -1 4294967296 seven ""; do
    check "demo_seed_'$v'" 2 "--seed: '$v' is not an integer in 0..4294967295" "$demo" --seed "$v"
done
for v in 0 -1 4294967296 100001 often; do
    check "demo_save_every_'$v'" 2 "--save-every: '$v' is not an integer in 1..100000" "$demo" --save-every "$v"
done
check demo_out_not_a_directory 1 "cannot create $out/afile/sub" "$demo" --out "$out/afile/sub"

# ---- wrsfov-gaze --------------------------------------------------------------------------------
check gaze_no_command 2 "no command: generate, stats, list, hid-decode or record" "$gz"
check gaze_generate_no_mode 2 "--mode is required" "$gz" generate --seconds 1 --out "$out/g.csv"
check gaze_generate_no_out 2 "--out is required" "$gz" generate --mode scene
check gaze_generate_option_missing_value 2 "--seconds: missing value (S)" "$gz" generate --mode scene --out "$out/g.csv" --seconds
check gaze_generate_unexpected_argument 2 "unexpected argument 'extra'" "$gz" generate --mode scene --out "$out/g.csv" extra
for v in nan inf -inf ten ""; do
    check "gaze_generate_seconds_'$v'" 2 "--seconds: '$v' is not a finite number" "$gz" generate --mode scene --out "$out/g.csv" --seconds "$v"
done
for v in 0 -1 3601 1e300; do
    check "gaze_generate_seconds_$v" 2 "seconds must be in (0, 3600]" "$gz" generate --mode scene --out "$out/g.csv" --seconds "$v"
done
for v in 0 -100 89 1001; do
    check "gaze_generate_rate_$v" 2 "tracker rate must be 90..1000 Hz" "$gz" generate --mode scene --seconds 1 --out "$out/g.csv" --rate "$v"
done
for v in -1 1.5 2e19; do
    check "gaze_generate_seed_$v" 2 "--seed: '$v' is not a non-negative integer below 1.8e19" "$gz" generate --mode scene --seconds 1 --out "$out/g.csv" --seed "$v"
done
check gaze_generate_latency_negative 2 "tracker latency must be in [0, 1) s" "$gz" generate --mode scene --seconds 1 --out "$out/g.csv" --latency-ms -1
check gaze_generate_latency_huge 2 "tracker latency must be in [0, 1) s" "$gz" generate --mode scene --seconds 1 --out "$out/g.csv" --latency-ms 1000
check gaze_generate_noise_negative 2 "tracker noise must be in [0, 10) degrees" "$gz" generate --mode scene --seconds 1 --out "$out/g.csv" --noise-deg -0.1
check gaze_generate_noise_inf 2 "--noise-deg: 'inf' is not a finite number" "$gz" generate --mode scene --seconds 1 --out "$out/g.csv" --noise-deg inf
check gaze_generate_dropouts_negative 2 "dropouts need a rate in [0, 100]" "$gz" generate --mode scene --seconds 1 --out "$out/g.csv" --dropouts-per-s -1
check gaze_generate_blinks_huge 2 "blinks need 0 <= per_minute <= 120" "$gz" generate --mode scene --seconds 1 --out "$out/g.csv" --blinks-per-min 500
check gaze_generate_char_deg_zero 2 "reading needs char_deg > 0" "$gz" generate --mode reading --seconds 1 --out "$out/g.csv" --char-deg 0
check gaze_generate_line_chars_small 2 "--line-chars: '5' is not an integer in 10..1000" "$gz" generate --mode reading --seconds 1 --out "$out/g.csv" --line-chars 5
check gaze_generate_line_chars_huge 2 "--line-chars: '1e9' is not an integer in 10..1000" "$gz" generate --mode reading --seconds 1 --out "$out/g.csv" --line-chars 1e9
check gaze_generate_pursuit_inverted 2 "pursuit needs 0 < speed_min <= speed_max" "$gz" generate --mode pursuit --seconds 1 --out "$out/g.csv" --pursuit-speed 20 5
check gaze_generate_pursuit_one_value 2 "--pursuit-speed: missing values (MIN MAX)" "$gz" generate --mode pursuit --seconds 1 --out "$out/g.csv" --pursuit-speed 5
check gaze_generate_out_not_writable 1 "cannot create '$out/afile/g.csv'" "$gz" generate --mode scene --seconds 1 --out "$out/afile/g.csv"

check gaze_stats_no_file 2 "FILE is required" "$gz" stats
check gaze_stats_two_files 2 "unexpected argument 'b.csv'" "$gz" stats a.csv b.csv
check gaze_stats_missing_file 1 "cannot open gaze file '$out/none.csv'" "$gz" stats "$out/none.csv"
: >"$out/empty.csv"
check gaze_stats_empty_file 1 "no header line (empty file?)" "$gz" stats "$out/empty.csv"
printf '\001\002\377\376 not a gaze file\n' >"$out/binary.csv"
check gaze_stats_binary_file 1 "unrecognised header" "$gz" stats "$out/binary.csv"
printf 't_s,frame,valid,left_x,left_y,left_z,right_x,right_y,right_z\nnan,0,1,0,0,-1,0,0,-1\n0,0,1,0,0,-1e30,0,0,-1\n' >"$out/bad_rows.csv"
check gaze_stats_only_bad_rows 1 "no usable samples" "$gz" stats "$out/bad_rows.csv"
check gaze_stats_only_bad_rows_lines 1 "bad_rows.csv:3: skipped: left direction is not a unit vector" "$gz" stats "$out/bad_rows.csv"
check gaze_stats_directory 1 "$out" "$gz" stats "$out"
check gaze_generate_for_truncation 0 "wrote 2000 samples" "$gz" generate --mode fixation --seconds 2 --rate 1000 --seed 2 --out "$out/fix.csv"
head -c 50000 "$out/fix.csv" >"$out/truncated.csv"
check gaze_stats_truncated_file 0 "1 bad rows skipped" "$gz" stats "$out/truncated.csv"
check gaze_stats_format_unknown 2 "--format: 'matlab' is not one of auto, project, pupil, tobii" "$gz" stats "$out/fix.csv" --format matlab
check gaze_stats_format_mismatch 1 "lacks the 'Recording timestamp' column" "$gz" stats "$out/fix.csv" --format tobii
check gaze_stats_lambda_zero 2 "--lambda: '0' is not a number > 0" "$gz" stats "$out/fix.csv" --lambda 0
check gaze_stats_lambda_nan 2 "--lambda: 'nan' is not a number > 0" "$gz" stats "$out/fix.csv" --lambda nan
check gaze_stats_char_deg_negative 2 "--char-deg: '-1' is not a number > 0" "$gz" stats "$out/fix.csv" --reading --char-deg -1

check gaze_list_extra_argument 2 "unexpected argument 'now'" "$gz" list now

check gaze_hid_decode_no_descriptor 2 "--descriptor is required" "$gz" hid-decode
check gaze_hid_decode_descriptor_missing 1 "cannot open '$out/none.hex'" "$gz" hid-decode --descriptor "$out/none.hex"
: >"$out/empty.hex"
check gaze_hid_decode_descriptor_empty 1 "report descriptor is empty" "$gz" hid-decode --descriptor "$out/empty.hex"
printf '05 1\n' >"$out/odd.hex"
check gaze_hid_decode_descriptor_odd_hex 1 "hex token '1' is not whole bytes" "$gz" hid-decode --descriptor "$out/odd.hex"
head -c 5000 /dev/zero | tr '\000' '\300' >"$out/huge.bin"
check gaze_hid_decode_descriptor_huge 1 "more than the 4096" "$gz" hid-decode --descriptor "$out/huge.bin"
printf '05 01 09 02 A1 01 09 30 09 31 15 81 25 7F 75 08 95 02 81 06 C0\n' >"$out/mouse.hex"
check gaze_hid_decode_not_an_eye_tracker 0 "not an eye tracker" "$gz" hid-decode --descriptor "$out/mouse.hex"
d="$data/eyetracker_descriptor.hex"
check gaze_hid_decode_report_missing 1 "cannot open '$out/none.hex'" "$gz" hid-decode --descriptor "$d" --report "$out/none.hex"
check gaze_hid_decode_report_empty 1 "empty" "$gz" hid-decode --descriptor "$d" --report "$out/empty.hex"
{ cat "$data/eyetracker_report.hex"; printf ' 00\n'; } >"$out/long_report.hex"
check gaze_hid_decode_report_too_long 1 "42 bytes" "$gz" hid-decode --descriptor "$d" --report "$out/long_report.hex"
sed 's/^01/09/' "$data/eyetracker_report.hex" >"$out/other_id.hex"
check gaze_hid_decode_report_unknown_id 1 "report ID 9" "$gz" hid-decode --descriptor "$d" --report "$out/other_id.hex"
printf '03 00 00 00 00 00 00 00 00\n' >"$out/zero_screen.hex"
check gaze_hid_decode_feature_zero_screen 1 "not positive" "$gz" hid-decode --descriptor "$d" --feature "$out/zero_screen.hex"
printf '03 01\n' >"$out/short_feature.hex"
check gaze_hid_decode_feature_truncated 1 "\"feature\": {\"error\"" "$gz" hid-decode --descriptor "$d" --feature "$out/short_feature.hex"

check gaze_record_no_device 2 "--device is required" "$gz" record --out "$out/r.csv"
check gaze_record_seconds_negative 2 "--seconds: '-1' is not a number >= 0" "$gz" record --device /dev/hidraw-none --out "$out/r.csv" --seconds -1
check gaze_record_seconds_nan 2 "--seconds: 'nan' is not a number >= 0" "$gz" record --device /dev/hidraw-none --out "$out/r.csv" --seconds nan
check gaze_record_screen_zero 2 "--screen-mm: '0' is not a number > 0" "$gz" record --device /dev/hidraw-none --out "$out/r.csv" --screen-mm 0 300
check gaze_record_screen_one_value 2 "--screen-mm: missing values (W H)" "$gz" record --device /dev/hidraw-none --out "$out/r.csv" --screen-mm 500
check gaze_record_device_not_an_id 1 "is neither a path, an index nor VID:PID" "$gz" record --device banana --out "$out/r.csv"
check gaze_record_device_index_out_of_range 1 "device index 99999 is out of range" "$gz" record --device 99999 --out "$out/r.csv"
check gaze_record_device_bad_vid_pid 1 "is not VID:PID in hex" "$gz" record --device zz:yy --out "$out/r.csv"
check gaze_record_device_absent_vid_pid 1 "no eye-tracker collection" "$gz" record --device 1234:5678 --out "$out/r.csv"

# ---- every tool: --help and --version exit 0; a usage error points at --help; --config -------------
check bench_help 0 "--heavy-every N" "$bench" --help
check bench_help_defaults 0 "Default: text,atrium,dynamic." "$bench" --help
check bench_help_change 0 "lstar: the CIE L* difference" "$bench" --help
check demo_help 0 "Default: out/demo." "$demo" --help
check gaze_record_help 0 "--screen-mm W H" "$gz" record --help
CLI_FIXED=
check bench_version 0 "^wrsfov-bench [0-9][0-9.]*$" "$bench" --version
check demo_version 0 "^wrsfov-demo [0-9][0-9.]*$" "$demo" --version
CLI_FIXED=1
check bench_usage_error_points_to_help 2 "Run 'wrsfov-bench --help' for more information." "$bench" --frames 0
check gaze_usage_error_points_to_command_help 2 "Run 'wrsfov-gaze stats --help' for more information." "$gz" stats
check gaze_option_unknown 2 "unknown option --bogus" "$gz" --bogus
check bench_fovea_list_bad_item 2 "--fovea: 'nan' is not a number in (0, 60]" "$bench" --fovea 5,nan,10
check bench_fovea_attached_value 2 "--fovea: '-inf' is not a number in (0, 60]" "$bench" --fovea=-inf
printf 'frames = 12\nwarmup = 12\n' >"$out/frames.toml"  # both keys read, or no error
check bench_config_values 2 "--frames must exceed --warmup" "$bench" --config "$out/frames.toml"
printf 'scenes = "moon"\n' >"$out/moon.toml"
check bench_config_bad_value 2 "--scenes: 'moon' is not one of" "$bench" --config "$out/moon.toml"
printf 'frames = 12\nbogus = 1\n' >"$out/bogus.toml"
check bench_config_unknown_key 2 "--config: unknown key 'bogus'" "$bench" --config "$out/bogus.toml"
check bench_config_missing 1 "$out/none.toml was not readable" "$bench" --config "$out/none.toml"
# Lists: a TOML array keeps every item (each checked), and a list option given twice keeps both.
printf 'fovea = [70, 5]\n' >"$out/fovea_array.toml"
check bench_config_array_every_item_checked 2 "--fovea: '70' is not a number in (0, 60]" "$bench" --config "$out/fovea_array.toml"
printf 'scenes = ["text", "atrium"]\n' >"$out/scenes_array.toml"
check bench_config_array_keeps_every_item 2 "--write-sequence writes one scene" "$bench" --config "$out/scenes_array.toml" --write-sequence "$out/ws"
check bench_no_skip_accepted 2 "--frames must exceed --warmup" "$bench" --no-skip --frames 5 --warmup 5
check bench_list_option_twice_keeps_both 2 "scene 'sequence' needs --sequence DIR" "$bench" --scenes sequence --scenes text
# --saving-plot (no device): a missing or malformed saving.csv, a malformed or unmatched target.
check bench_saving_target_alone 2 "--saving-target is --saving-plot's" "$bench" --saving-target fov,0.4,30
check bench_saving_plot_missing 1 "cannot read $out/none.csv" "$bench" --saving-plot "$out/none.csv" --out "$out/sp"
printf 'scene,input,method\natrium,full,fov\n' >"$out/short.csv"
check bench_saving_plot_not_a_saving_csv 1 "no column \"inset_deg\" (not a saving.csv)" "$bench" --saving-plot "$out/short.csv" --out "$out/sp"
h=scene,input,method,inset_deg,pixels_rendered,render_ms,compose_ms,jod,near_gaze_psnr
printf '%s\natrium,full,fov,0,1000,8,1,10,inf\natrium,quad,fov,30,200,2,1,oops,30\n' "$h" >"$out/bad_jod.csv"
check bench_saving_plot_bad_number 1 "bad_jod.csv:3: column jod is not a number: \"oops\"" "$bench" --saving-plot "$out/bad_jod.csv" --out "$out/sp"
printf '%s,wide_density,jitter,temporal_instability\natrium,full,fov,0,1000,8,1,10,inf,0,0,0\natrium,quad,wrs,10,100,2,1,8,30,0.3,8,0.01\n' "$h" >"$out/ok.csv"
check bench_saving_plot_bad_target 2 "a target is METHOD,DENSITY,INSET[,JITTER]" "$bench" --saving-plot "$out/ok.csv" --saving-target fov --out "$out/sp"
check bench_saving_plot_unmatched_target 1 "for the target" "$bench" --saving-plot "$out/ok.csv" --saving-target fov,0.4,30 --out "$out/sp"
check bench_saving_plot_ok 0 "| wrs (jittered) | 10.0 % or less |" "$bench" --saving-plot "$out/ok.csv" --saving-target wrs,0.3,10,8 --out "$out/sp"
# --study (no device): a malformed cell column, rows without wrs, and two seeds of one cell summarised.
sh_="$h,wide_density,jitter,temporal_instability,head_path,head_deg_per_s,seed,split"
printf '%s\natrium,quad,wrs,10,100,2,1,8,30,0.3,8,0.01,yaw60,60,1,dev\n' "$sh_" >"$out/study_split.csv"
check bench_study_bad_split 1 "study_split.csv:2: split must be train or test, not \"dev\"" "$bench" --study "$out/study_split.csv" --out "$out/st"
printf '%s\natrium,full,fov,0,1000,8,1,10,inf,0,0,0\natrium,quad,fov,10,100,2,1,8,30,0.3,8,0.01\n' "$h,wide_density,jitter,temporal_instability" >"$out/study_fov.csv"
check bench_study_no_wrs 1 "study: no jittered quad views composed with wrs" "$bench" --study "$out/study_fov.csv" --out "$out/st"
for seed in 1 2; do
  printf '%s\ndynamic,full,fov,0,1000,8,1,10,inf,0,0,0,yaw60,60,%s,test\ndynamic,quad,fov,30,200,2,1,8.0,30,0.4,0,0.01,yaw60,60,%s,test\ndynamic,quad,taau,10,90,2,1,7.9,30,0.3,8,0.010,yaw60,60,%s,test\ndynamic,quad,wrs,10,90,2,1,8.%s,30,0.3,8,0.010,yaw60,60,%s,test\n' \
    "$sh_" "$seed" "$seed" "$seed" "$seed" "$seed" >"$out/study_s$seed.csv"
done
check bench_study_ok 0 "| test | dynamic yaw60 | 0.30 / 10° | 9.0 % | wrs | taau | 2 | 8.150 | 7.900 | +0.250 [-0.385, +0.885] | tie |" \
  "$bench" --study "$out/study_s1.csv,$out/study_s2.csv" --out "$out/st"
check bench_cost_quad_alone 2 "--cost-quad is a --cost-model cell of its own" "$bench" --cost-quad

echo "$count checks, $fails failed"
[ "$fails" -eq 0 ]
