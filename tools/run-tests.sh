#!/usr/bin/env bash
# The test command: installs what is missing, builds, runs every CTest suite. GPU suites run on
# whatever Vulkan device is present (Mesa lavapipe without a GPU) under the Khronos validation
# layer, and fail on any validation error.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh build
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
export WRSFOV_VALIDATION=1
ctest --test-dir build --output-on-failure -j 2 --timeout 600
