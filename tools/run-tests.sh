#!/usr/bin/env bash
# The test command: installs what is missing, builds, and runs every CTest suite three ways:
#   1. the release build, GPU suites on whatever Vulkan device is present (Mesa lavapipe without a
#      GPU) under the Khronos validation layer with synchronization validation on; any validation
#      message fails the test;
#   2. an AddressSanitizer + UndefinedBehaviorSanitizer build of the same suites (build-asan/);
#   3. the libFuzzer targets (clang): HID descriptors and reports, and the text files users hand
#      the tools (sequence.json, gaze.csv, gaze recordings), each for a bounded time.
# Usage: tools/run-tests.sh [--fast]   (--fast: stage 1 only)
#   WRSFOV_FUZZ_SECONDS (default 30) bounds each target of stage 3.
set -euo pipefail
cd "$(dirname "$0")/.."
fast=0
[ "${1:-}" = "--fast" ] && fast=1
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
# Lavapipe splits each dispatch across LP_NUM_THREADS threads, by default one per core; here one per
# test process: with two or three test processes on two cores the split dispatches' threads wait on
# each other (release suites with a warm shader cache 287 s against
# 272 s, sanitizer suites 301 s against 285 s). The results do not depend on it: lavapipe runs a
# queue's commands in order either way.
export LP_NUM_THREADS="${LP_NUM_THREADS:-1}"
start=$(date +%s)
at() { echo "(at $(($(date +%s) - start)) s)"; }

echo "== [1/3] release build, validation layer on (with synchronization validation) $(at)"
bash tools/setup.sh build
echo "== release suites $(at)"
# Synchronization validation finds missing barriers that a CPU driver, which runs the commands in
# order, never shows (it costs this stage no measurable time).
WRSFOV_VALIDATION=1 VK_LAYER_ENABLES=VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT \
    ctest --test-dir build --output-on-failure -j 2 --timeout 600
[ $fast -eq 1 ] && exit 0

echo "== [2/3] AddressSanitizer + UndefinedBehaviorSanitizer build $(at)"
# -O1, as the sanitizers' documentation suggests: 35-45 % less compile time than -O2 under
# instrumentation (eval/bench.cpp 12.8 s against 23.0 s), the largest part of this stage; the tests' and
# tools' own code at -O0 there (tests/CMakeLists.txt, tools/CMakeLists.txt, cli/CMakeLists.txt). Compiled by clang, which
# builds the instrumented code in 25-50 % less time than GCC (eval/sequence.cpp 14.8 s against 20.1 s,
# cli/cli.cpp 5.9 s against 11.7 s) and gives the code a second compiler's warnings; the release
# build stays with GCC. A build-asan/ configured with another compiler is made afresh.
if [ -f build-asan/CMakeCache.txt ] && ! grep -q "^CMAKE_CXX_COMPILER:.*clang++" build-asan/CMakeCache.txt; then
  rm -rf build-asan
fi
CC=clang CXX=clang++ bash tools/setup.sh build-asan -DWRSFOV_SANITIZE=ON -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
    -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG"
# Any ASan report or any undefined behaviour fails. Leak checking is on for the suites that do not
# touch Vulkan (tools/lsan.supp names system libraries that keep allocations until exit). For the
# Vulkan suites and the command-line scripts that run Vulkan tools it is off: the loader unloads
# the driver at vkDestroyInstance, so the driver's own leaks can only be reported from an
# "<unknown module>" that no suppression can name.
echo "== sanitizer suites $(at)"
asan="abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1"
export LSAN_OPTIONS="suppressions=$(pwd)/tools/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
vulkan_scripts="(_cli|_cli_faults|bench_quick)$"
# The rounding variants of the GPU-against-reference suite (Rounding.EveryPermittedRounding*: the same
# frames stepped once per permitted rounding of the CPU reference, ~4.5 minutes under the sanitizers)
# run in the release stage only; under the sanitizers Rounding.OddSizesToo and GpuVsCpu step the same
# reference code.
rounding_variants="Rounding\.EveryPermittedRounding"
# Likewise the benchmark's statistical check (Bench.WrsBeatsFovNearGazeAtFiveDegrees, 45 s under the
# sanitizers): a long run of the sweep's host path for a figure, a path bench_quick and the other Bench
# tests take there.
# And the CPU stress study's long runs (StressCpu.ShortRunOfEveryStream: 10^5 frames of every stream
# for its statistics; StressCpu.SafeHorizonOfTheShippingLayout: 2^25 steps for a horizon), figures of
# the shared math whose host path (the stream runner) stress_cli runs under the sanitizers.
# And two checks of the device's arithmetic rather than of a host path: sparse retention's output against
# retention in every tile over thirteen cases (Sparse.SameOutputAsRetentionInEveryTile, 22 s there; the
# other Sparse.* tests take sparse retention's host path under the sanitizers), and the device's fp16
# conversion against the hand one (HardwareHalf.SameBitsAsTheHandConversion).
release_only="$rounding_variants|Bench\.WrsBeatsFovNearGaze|StressCpu\.ShortRunOfEveryStream|StressCpu\.SafeHorizon"
release_only="$release_only|Sparse\.SameOutputAsRetentionInEveryTile|HardwareHalf\.SameBitsAsTheHandConversion"
ASAN_OPTIONS="detect_leaks=1:$asan" \
    ctest --test-dir build-asan --output-on-failure -j 2 --timeout 900 -LE gpu -E "$vulkan_scripts|$release_only"
# The command-line scripts without the gpu label (two short ones) run beside the GPU suites rather than
# after them, so that neither waits on the other's last test; their log follows the suites'.
scripts_log=build-asan/scripts-ctest.log
ASAN_OPTIONS="detect_leaks=0:$asan" \
    ctest --test-dir build-asan --output-on-failure -j 1 --timeout 900 -LE gpu -R "$vulkan_scripts" > "$scripts_log" 2>&1 &
scripts_pid=$!
gpu_rc=0
ASAN_OPTIONS="detect_leaks=0:$asan" \
    ctest --test-dir build-asan --output-on-failure -j 2 --timeout 900 -L gpu -E "$release_only" || gpu_rc=$?
scripts_rc=0
wait "$scripts_pid" || scripts_rc=$?
echo "== the command-line scripts (without the gpu label), run beside the GPU suites:"
cat "$scripts_log"
if [ "$gpu_rc" -ne 0 ] || [ "$scripts_rc" -ne 0 ]; then
  echo "== sanitizer stage failed (GPU suites: exit $gpu_rc, command-line scripts: exit $scripts_rc)"
  exit 1
fi

echo "== [3/3] fuzz targets, ${WRSFOV_FUZZ_SECONDS:-30} s each $(at)"
bash tools/fuzz.sh "${WRSFOV_FUZZ_SECONDS:-30}"
echo "== all test stages passed $(at)"
