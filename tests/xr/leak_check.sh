#!/bin/sh
# Runs a sanitizer-built test with leak detection and fails on every leak allocated by wrsfov's own
# code: the first frame after the sanitizer's allocator (GCC's libasan, clang's libclang_rt) and after
# the standard library's templates (which an unoptimised build leaves as frames of the caller's binary)
# in each leak report must be a system library's (Debian's OpenXR loader 1.0.20 keeps about 1.6 kB from xrCreateInstance; the Mesa
# driver and the Vulkan loader keep theirs). A suppression cannot tell these apart, because every
# call into the runtime and the layer passes through the OpenXR loader's frames.
# usage: leak_check.sh PROGRAM [ARGS...]
log=$(mktemp)
LSAN_OPTIONS="${LSAN_OPTIONS:+$LSAN_OPTIONS:}exitcode=0" "$@" > "$log" 2>&1
rc=$?
cat "$log"
ours=$(awk '
  /leak of [0-9]+ byte/ { inleak = 1; next }
  inleak && /^ *#[0-9]+ / {
    if ($0 ~ /asan_|interceptor|libsanitizer|libclang_rt|\/include\/c\+\+\//) next
    if ($0 !~ /libopenxr_loader|libvulkan|libLLVM|<unknown module>|libstdc\+\+|libc\.so|ld-linux/) n++
    inleak = 0
  }
  END { print n + 0 }' "$log")
reported=$(grep -c "leak of [0-9]* byte" "$log")
rm -f "$log"
echo "leak_check: $reported leak reports, $ours allocated by wrsfov's code"
[ "$rc" -eq 0 ] && [ "$ours" -eq 0 ]
