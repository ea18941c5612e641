#!/bin/sh
# Runs the preview's window tests inside one Xvfb server.
# usage: preview_window_test.sh TEST_PROGRAM PREVIEW_PROGRAM OUT_DIR
set -eu
if ! command -v xvfb-run >/dev/null 2>&1; then
  echo "preview_window_test: xvfb-run is missing (Debian package xvfb)" >&2
  exit 1
fi
mkdir -p "$3"
export WRSFOV_PREVIEW_BIN="$2"
export WRSFOV_PREVIEW_OUT="$3"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
exec xvfb-run -a -s "-screen 0 1280x1024x24" "$1"
