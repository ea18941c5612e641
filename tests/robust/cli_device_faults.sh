#!/bin/sh
# docs/bad-input.md, "Device faults": the tools under injected device faults (WRSFOV_FAULT, see
# vk::FaultInjection) stop with exit status 1 and a message that names the fault, never crash or hang.
# usage: cli_device_faults.sh WRSFOV_BENCH WRSFOV_DEMO OUT_DIR
set -u
bench=$1 demo=$2 out=$3
rm -rf "$out"
mkdir -p "$out"
. "$(dirname "$0")/../cli_check.sh"
CLI_FIXED=1
check() {  # check NAME EXPECTED_RC PATTERN FAULT COMMAND...
    n=$1 w=$2 p=$3 f=$4
    shift 4
    cli_check "$n" "$w" "$p" env WRSFOV_FAULT="$f" timeout 120 "$@"
}
demo_args() { echo "--size 16x16 --frames 3 --out $out/demo_$1"; }
bench_args() {
    echo "--scenes text --methods fov,wrs --fovea 5 --modes mip --size 32x32 --frames 3 --warmup 1 --out $out/bench_$1"
}

# shellcheck disable=SC2046  # the argument lists are split on purpose
check demo_fault_spec_malformed 1 "WRSFOV_FAULT='alloc=1' is not alloc:N, lost:N, pipeline:N and/or object:N" "alloc=1" "$demo" $(demo_args spec)
check demo_no_fault 0 "wrote" "" "$demo" $(demo_args none)
cli_check demo_summary_table_header 0 "| method | PSNR (dB) | near-gaze PSNR" cat "$out/demo_no_fault.log"
check demo_oom_first_allocation 1 "compositor frame parameters: vkAllocateMemory" "alloc:1" "$demo" $(demo_args oom1)
check demo_oom_swapchain_image 1 "VK_ERROR_OUT_OF_DEVICE_MEMORY" "alloc:8" "$demo" $(demo_args oom8)
check demo_oom_during_frames 1 "VK_ERROR_OUT_OF_DEVICE_MEMORY" "alloc:20" "$demo" $(demo_args oom20)
check demo_lost_at_start 1 "VK_ERROR_DEVICE_LOST" "lost:1" "$demo" $(demo_args lost1)
check demo_lost_while_compositing 1 "the Vulkan device was lost (VK_ERROR_DEVICE_LOST): this compositor refuses" \
    "lost:10" "$demo" $(demo_args lost10)
check demo_lost_in_a_readback 1 "queue submission failed: VK_ERROR_DEVICE_LOST" "lost:12" "$demo" $(demo_args lost12)
check demo_pipeline_probe_falls_back 0 "wrote" "pipeline:1" "$demo" $(demo_args pipe1)
check demo_pipeline_in_a_frame 1 "): vkCreateComputePipelines failed: VK_ERROR_OUT_OF_DEVICE_MEMORY" \
    "pipeline:2" "$demo" $(demo_args pipe2)
check bench_oom_first_allocation 1 "compositor frame parameters: vkAllocateMemory" "alloc:1" "$bench" $(bench_args oom1)
check bench_lost_in_a_frame 1 "VK_ERROR_DEVICE_LOST" "lost:10" "$bench" $(bench_args lost10)

echo "$count checks, $fails failed"
[ "$fails" -eq 0 ]
