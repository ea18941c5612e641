#!/bin/sh
# hello_xr (the Khronos sample client, -g Vulkan2 -vc Stereo) on the wrsfov runtime, headless, under
# the Khronos Vulkan validation layer and the OpenXR core validation layer: it must run 300 frames,
# exit cleanly when the runtime asks it to stop, leave 0 validation messages of either layer, and
# record a 300-frame sequence that wrsfov-bench evaluates. Every hello_xr run has EXIT_CHECK
# (exit_stdio_check.c) preloaded: its exit may not wait for a stream another thread holds.
# usage: hello_xr_test.sh RUNTIME_JSON WRSFOV_BENCH OUT_DIR EXIT_CHECK
# WRSFOV_XR_PRELOAD (sanitizer builds): libraries to preload into the programs that load the runtime
# (the sanitizer runtimes must come first in a program that was not built with them).
set -u
json="$1"
bench="$2"
out="$3"
exit_check="$4"
rm -rf "$out"
mkdir -p "$out"
. "$(dirname "$0")/../cli_check.sh"
. "$(dirname "$0")/hello_xr_stdin.sh"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
export XR_RUNTIME_JSON="$json"

preload="${WRSFOV_XR_PRELOAD:-}"
CLI_FIXED=1 cli_check runtime_list 0 "XR_EXT_eye_gaze_interaction" env LD_PRELOAD="$preload" openxr_runtime_list
hello_preload="${preload:+$preload:}$exit_check"

# Only the runtime's frame limit can end a run (hello_xr_stdin.sh).
run_hello() {
    hello_xr_until_ended "$out/hello_xr.log" \
        env WRSFOV_XR_WIDTH=192 WRSFOV_XR_HEIGHT=192 WRSFOV_XR_FRAMES=300 WRSFOV_XR_RECORD="$out/seq" \
        WRSFOV_VALIDATION=1 XR_ENABLE_API_LAYERS=XR_APILAYER_LUNARG_core_validation \
        timeout 300 env LD_PRELOAD="$hello_preload" hello_xr -g Vulkan2 -vc Stereo
}
CLI_FIXED=1 cli_check hello_xr 0 "session ended: 300 frames ended, 300 composited, 0 shown as submitted, 0 not composited" run_hello
log="$out/hello_xr.log"
check() {  # check NAME COMMAND...: a shell condition on the hello_xr log
    name=$1
    shift
    count=$((count + 1))
    if "$@"; then echo "ok   $name"; else echo "FAIL $name"; fails=$((fails + 1)); fi
}
check vulkan_validation_counted grep -q "Vulkan validation on: counting" "$log"
check vulkan_validation_clean grep -q "Vulkan validation: 0 errors, 0 warnings" "$log"
# After the session (and the runtime's messenger) is gone, hello_xr's own debug callback prints what
# the layer still reports, e.g. objects the runtime left on the device at vkDestroyDevice.
check vulkan_teardown_clean sh -c "! grep -q -e 'Validation Error' -e 'ERROR: (' '$log'"
check openxr_validation_active grep -q "Core Validation output type" "$log"
check openxr_validation_clean sh -c "! grep -q -e VALID_ERROR -e 'VUID-' '$log'"
check session_exited grep -q "XR_SESSION_STATE_IDLE->XR_SESSION_STATE_EXITING" "$log"
check recorded grep -q "recorded 300 frames to $out/seq" "$log"
check frame_count grep -q '"frame_count": 300' "$out/seq/sequence.json"
check last_frame test -s "$out/seq/000299_R_color.png" -a -s "$out/seq/000299_R_output.png"
check no_extra_frame test ! -e "$out/seq/000300_L_color.png"
check gaze_rows test "$(wc -l < "$out/seq/gaze.csv")" -eq 301

# A desktop window (under Xvfb) with the preview's overlays, gaze from the mouse: 60 frames, a
# screenshot of the window, still 0 validation messages.
run_window() {
    hello_xr_until_ended "$out/hello_xr_window.log" \
        env WRSFOV_XR_WIDTH=128 WRSFOV_XR_HEIGHT=128 WRSFOV_XR_FRAMES=60 WRSFOV_XR_OUTPUT=window \
        WRSFOV_XR_GAZE=mouse WRSFOV_XR_SCREENSHOT="$out/window.png" WRSFOV_VALIDATION=1 \
        timeout 300 xvfb-run -a -s "-screen 0 1280x1024x24" env LD_PRELOAD="$hello_preload" hello_xr -g Vulkan2 -vc Stereo
}
CLI_FIXED=1 cli_check hello_xr_window 0 "session ended: 60 frames ended, 60 composited" run_window
check window_opened grep -q "gaze mouse, window" "$out/hello_xr_window.log"
check window_validation_clean grep -q "Vulkan validation: 0 errors, 0 warnings" "$out/hello_xr_window.log"
check window_screenshot test "$(stat -c %s "$out/window.png" 2>/dev/null || echo 0)" -gt 2000

# XR_KHR_vulkan_enable (hello_xr -g Vulkan): the application makes its own Vulkan instance and device;
# the validation layer goes in through the loader (VK_INSTANCE_LAYERS) and reports to hello_xr's
# debug-report callback, which prints ERROR:/WARNING: lines.
run_v1() {
    hello_xr_until_ended "$out/hello_xr_vulkan1.log" \
        env WRSFOV_XR_WIDTH=128 WRSFOV_XR_HEIGHT=128 WRSFOV_XR_FRAMES=60 WRSFOV_XR_OUTPUT=headless \
        VK_INSTANCE_LAYERS=VK_LAYER_KHRONOS_validation \
        XR_ENABLE_API_LAYERS=XR_APILAYER_LUNARG_core_validation \
        timeout 300 env LD_PRELOAD="$hello_preload" hello_xr -g Vulkan -vc Stereo
}
CLI_FIXED=1 cli_check hello_xr_vulkan1 0 "session ended: 60 frames ended, 60 composited, 0 shown as submitted, 0 not composited" run_v1
check vulkan1_validation_active grep -q 'Inserted device layer "VK_LAYER_KHRONOS_validation"' "$out/hello_xr_vulkan1.log"
check vulkan1_validation_clean sh -c "! grep -q -e 'ERROR:' -e 'WARNING:' '$out/hello_xr_vulkan1.log'"
check vulkan1_openxr_validation_clean sh -c "! grep -q -e VALID_ERROR -e 'VUID-' '$out/hello_xr_vulkan1.log'"

# Device faults in the runtime (WRSFOV_FAULT, docs/bad-input.md "Device faults"): a pipeline the driver
# cannot make refuses one frame, which the session counts and goes on from; an object it cannot make
# when the session makes its compositor fails xrCreateSession with a message naming it. Neither one
# takes the application down. (hello_xr leaves after a failed xrCreateSession with its stdin thread
# still waiting, so that run goes without EXIT_CHECK: that exit is hello_xr's, not the runtime's.)
run_fault() {  # run_fault NAME FAULT PRELOAD
    hello_xr_until_ended "$out/$1.log" \
        env WRSFOV_FAULT="$2" WRSFOV_XR_WIDTH=96 WRSFOV_XR_HEIGHT=96 WRSFOV_XR_FRAMES=30 WRSFOV_XR_OUTPUT=headless \
        timeout 120 env LD_PRELOAD="$3" hello_xr -g Vulkan2 -vc Stereo
}
CLI_FIXED=1 cli_check hello_xr_pipeline_fault 0 "session ended: 30 frames ended, 29 composited, 0 shown as submitted, 1 not composited" \
    run_fault hello_xr_pipeline_fault pipeline:3 "$hello_preload"
check pipeline_fault_named grep -q "vkCreateComputePipelines failed: VK_ERROR_OUT_OF_DEVICE_MEMORY (logged once per reason)" \
    "$out/hello_xr_pipeline_fault.log"
CLI_FIXED=1 cli_check hello_xr_object_fault 1 \
    "session: compositor: the passes' pipeline layout: vkCreatePipelineLayout failed: VK_ERROR_OUT_OF_HOST_MEMORY" \
    run_fault hello_xr_object_fault object:2 "$preload"

# The recording round-trips through the benchmark as scene `sequence` (release build only: the
# sanitizer build's benchmark takes a minute and tests nothing the release run does not).
if [ -z "$preload" ]; then
    CLI_FIXED=1 cli_check bench_sequence 0 "192x192 per eye, 300 frames" \
        "$bench" --sequence "$out/seq" --out "$out/report" --fovea 5 --modes mip --methods fov,wrs
    check bench_rows test "$(grep -c '^sequence,' "$out/report/results.csv")" -eq 2
fi
cli_summary
