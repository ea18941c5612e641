#!/bin/sh
# The API layer XR_APILAYER_WRSFOV_foveation on hello_xr -g Vulkan2, over the wrsfov runtime in
# pass-through mode (method = off: it records what it receives). Three runs of 60 frames: without the
# layer, with it (under the OpenXR core validation layer below it and the Vulkan validation layer),
# and with it disabled by its environment variable. The recordings are compared by
# wrsfov_xr_layer_frames_tests.
# Then the runtime and the layer installed into a scratch prefix (cmake --install) run hello_xr
# from there. Every hello_xr run has EXIT_CHECK (exit_stdio_check.c) preloaded: its exit may not
# wait for a stream another thread holds.
# usage: layer_test.sh RUNTIME_JSON LAYER_DIR FRAMES_TEST OUT_DIR BUILD_DIR EXIT_CHECK
set -u
json="$1"
layers="$2"
frames_test="$3"
out="$4"
build="$5"
exit_check="$6"
rm -rf "$out"
mkdir -p "$out"
. "$(dirname "$0")/../cli_check.sh"
. "$(dirname "$0")/hello_xr_stdin.sh"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
export XR_RUNTIME_JSON="$json"
# XR_API_LAYER_PATH replaces the default search path: keep Debian's explicit layers (core validation).
export XR_API_LAYER_PATH="$layers:/usr/share/openxr/1/api_layers/explicit.d"
preload="${WRSFOV_XR_PRELOAD:-}"
hello_preload="${preload:+$preload:}$exit_check"
run() {  # run NAME [VAR=VALUE...]: hello_xr for 60 frames, recorded into $out/NAME (log $out/NAME.log)
    name=$1
    shift
    hello_xr_until_ended "$out/$name.log" \
        env WRSFOV_XR_METHOD=off WRSFOV_XR_WIDTH=128 WRSFOV_XR_HEIGHT=128 WRSFOV_XR_FRAMES=60 \
        WRSFOV_XR_RECORD="$out/$name" WRSFOV_XR_OUTPUT=headless WRSFOV_VALIDATION=1 "$@" \
        timeout 300 env LD_PRELOAD="$hello_preload" hello_xr -g Vulkan2 -vc Stereo
}
check() {
    name=$1
    shift
    count=$((count + 1))
    if "$@"; then echo "ok   $name"; else echo "FAIL $name"; fails=$((fails + 1)); fi
}
CLI_FIXED=1 cli_check plain 0 "60 shown as submitted" run plain
CLI_FIXED=1 cli_check layer 0 "session ended: 60 of 60 frames foveated" run layer \
    XR_ENABLE_API_LAYERS=XR_APILAYER_WRSFOV_foveation:XR_APILAYER_LUNARG_core_validation
# The same over the runtime in its strict swapchain setting (swapchains = strict: sRGB images never
# MUTABLE_FORMAT, as Monado 21 makes them; four images): the layer reads them through sRGB views, with
# no validation message. (That those views give the same bits as UNORM ones: Import.* in the GPU suite;
# over the strict runtime, XrQuadViews.OfferedByTheLayerOnAStereoRuntime in xr_quad_through_layer.)
CLI_FIXED=1 cli_check strict 0 "session ended: 60 of 60 frames foveated" run strict \
    XR_ENABLE_API_LAYERS=XR_APILAYER_WRSFOV_foveation:XR_APILAYER_LUNARG_core_validation WRSFOV_XR_SWAPCHAINS=strict
CLI_FIXED=1 cli_check disabled 0 "60 shown as submitted" run disabled \
    XR_ENABLE_API_LAYERS=XR_APILAYER_WRSFOV_foveation DISABLE_XR_APILAYER_WRSFOV_foveation=1
# Faults inside the layer (its own device work only): the layer disables itself, the application
# runs on; device lost after a few frames, and out of memory when the compositor is made.
CLI_FIXED=1 cli_check lost 0 "60 shown as submitted" run lost \
    XR_ENABLE_API_LAYERS=XR_APILAYER_WRSFOV_foveation WRSFOV_LAYER_FAULT=lost:12
CLI_FIXED=1 cli_check oom 0 "60 shown as submitted" run oom \
    XR_ENABLE_API_LAYERS=XR_APILAYER_WRSFOV_foveation WRSFOV_LAYER_FAULT=alloc:1
# A pipeline (the first frame's first) or an object (as the compositor is made) that the driver cannot
# make: the layer disables itself with the message, the application runs on.
CLI_FIXED=1 cli_check pipeline 0 "60 shown as submitted" run pipeline \
    XR_ENABLE_API_LAYERS=XR_APILAYER_WRSFOV_foveation WRSFOV_LAYER_FAULT=pipeline:2
CLI_FIXED=1 cli_check object 0 "60 shown as submitted" run object \
    XR_ENABLE_API_LAYERS=XR_APILAYER_WRSFOV_foveation WRSFOV_LAYER_FAULT=object:1
check pipeline_disabled grep -q "disabled for this session: .*vkCreateComputePipelines failed: VK_ERROR_OUT_OF_DEVICE_MEMORY" \
    "$out/pipeline.log"
check object_disabled grep -q "disabled for this session: .*vkCreateDescriptorSetLayout failed: VK_ERROR_OUT_OF_HOST_MEMORY" \
    "$out/object.log"
check pipeline_teardown_clean sh -c "! grep -q 'Validation Error' '$out/pipeline.log'"
check lost_disabled grep -q "disabled for this session: .*VK_ERROR_DEVICE_LOST\|disabled for this session: .*device" "$out/lost.log"
check lost_some_foveated grep -Eq "session ended: ([1-9]|[1-5][0-9]) of 60 frames foveated" "$out/lost.log"
# The layer's own work is finished before its fence and semaphore are reused or destroyed, after a
# loss too (the injected loss lets the work run; a real one returns at once).
check lost_teardown_clean sh -c "! grep -q 'Validation Error' '$out/lost.log'"
check oom_teardown_clean sh -c "! grep -q 'Validation Error' '$out/oom.log'"
check oom_disabled grep -q "disabled for this session: compositor: .*OUT_OF_DEVICE_MEMORY" "$out/oom.log"
check oom_none_foveated grep -q "session ended: 0 of 60 frames foveated" "$out/oom.log"
check layer_gaze_from_runtime grep -q "gaze from the runtime's eye tracking" "$out/layer.log"
check layer_vulkan_clean grep -q "Vulkan validation: 0 errors, 0 warnings" "$out/layer.log"
check layer_teardown_clean sh -c "! grep -q -e 'Validation Error' -e 'ERROR: (' '$out/layer.log'"
check layer_openxr_validation_active grep -q "Core Validation output type" "$out/layer.log"
check layer_openxr_clean sh -c "! grep -q -e VALID_ERROR -e 'VUID-' '$out/layer.log'"
check strict_vulkan_clean grep -q "Vulkan validation: 0 errors, 0 warnings" "$out/strict.log"
check strict_clean sh -c "! grep -q -e 'Validation Error' -e 'ERROR: (' -e VALID_ERROR -e 'VUID-' '$out/strict.log'"
check disabled_silent sh -c "! grep -q 'wrsfov-layer' '$out/disabled.log'"
CLI_FIXED=1 cli_check frames 0 "PASSED" "$frames_test" "$out/plain" "$out/layer" "$out/disabled" "$out/lost"

CLI_FIXED=1 cli_check install 0 "Installing" cmake --install "$build" --prefix "$out/prefix"
check installed_layer_manifest test -s "$out/prefix/share/openxr/1/api_layers/explicit.d/XrApiLayer_wrsfov_foveation.json"
CLI_FIXED=1 cli_check installed 0 "session ended: 20 of 20 frames foveated" hello_xr_until_ended "$out/installed.log" \
    env XR_RUNTIME_JSON="$out/prefix/share/openxr/1/openxr_wrsfov.json" \
    XR_API_LAYER_PATH="$out/prefix/share/openxr/1/api_layers/explicit.d" \
    XR_ENABLE_API_LAYERS=XR_APILAYER_WRSFOV_foveation WRSFOV_XR_FRAMES=20 WRSFOV_XR_WIDTH=64 WRSFOV_XR_HEIGHT=64 \
    WRSFOV_XR_OUTPUT=headless timeout 300 env LD_PRELOAD="$hello_preload" hello_xr -g Vulkan2 -vc Stereo
cli_summary
