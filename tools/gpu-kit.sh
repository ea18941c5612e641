#!/usr/bin/env bash
# Packs tools/gpu-bench.sh for a machine with a GPU that cannot build wrsfov (no network for the
# packages, another distribution): builds wrsfov-bench, wrsfov_gpu_tests and the OpenXR runtime
# (libwrsfov_xr.so) here, and writes one archive with them, Debian's hello_xr (libopenxr-utils), the
# shared libraries all of them load (the OpenXR loader among them; all but the C library's own, which
# the target's newer glibc provides), gpu-bench.sh and a run.sh. There:
#   tar xJf wrsfov-gpu-kit.tar.xz && wrsfov-gpu-kit/run.sh [OUT_DIR]
# runs, in about five minutes, the sweep at steady state, the GPU tests and hello_xr on the runtime
# with methods wrs and fov, each stage under a timeout, and writes OUT_DIR/summary.md (docs/speed.md
# "On a GPU"). WRSFOV_GPU_BENCH_DRY=1 run.sh sizes it for a CPU renderer (a dry run of the kit).
# Usage: tools/gpu-kit.sh [ARCHIVE]   (default out/wrsfov-gpu-kit.tar.xz; x86-64 targets only)
#   WRSFOV_KIT_XZ (default -6): the xz level.
set -euo pipefail
cd "$(dirname "$0")/.."
archive="${1:-out/wrsfov-gpu-kit.tar.xz}"
WRSFOV_BUILD_TARGETS="wrsfov-bench wrsfov_gpu_tests wrsfov_xr" bash tools/setup.sh build
hello=$(command -v hello_xr || true)
[ -n "$hello" ] || { echo "gpu-kit.sh: no hello_xr (Debian package libopenxr-utils)"; exit 1; }
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
kit="$stage/wrsfov-gpu-kit"
mkdir -p "$kit/bin" "$kit/lib" "$kit/tools" "$kit/xr"
cp build/tools/wrsfov-bench build/tests/core/wrsfov_gpu_tests "$hello" "$kit/bin/"
cp build/runtime/libwrsfov_xr.so "$kit/xr/"
cp tools/gpu-bench.sh "$kit/tools/"
git rev-parse --short HEAD >"$kit/COMMIT" 2>/dev/null || echo unknown >"$kit/COMMIT"
# What the binaries load, and the GL vendor-neutral dispatch libraries (libglvnd) that NVIDIA's
# Vulkan driver is loaded through, which a compute-only image may lack.
{
  ldd "$kit"/bin/* "$kit"/xr/*.so | awk '/=> \// {print $3}'
  for l in libGLX.so.0 libGLdispatch.so.0 libEGL.so.1 libOpenGL.so.0 libvulkan.so.1; do
    ldconfig -p | awk -v n="$l" '$1 == n && /x86-64/ && !done {print $NF; done = 1}'
  done
} | sort -u | while read -r lib; do
  case "$(basename "$lib")" in
    libc.so.* | libm.so.* | libdl.so.* | libpthread.so.* | librt.so.* | libresolv.so.* | libutil.so.* | ld-linux*) ;;
    *) cp -L "$lib" "$kit/lib/" ;;
  esac
done
cat >"$kit/run.sh" <<'RUN'
#!/usr/bin/env bash
# Runs tools/gpu-bench.sh with the carried binaries: ./run.sh [OUT_DIR] (default out/gpu-bench here).
# A library the machine has itself (the same name in its loader cache) is taken from the machine:
# its Vulkan loader and libglvnd are the ones its driver expects, its libstdc++ is at least as new.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
mkdir -p "$here/lib.machine"
for lib in "$here"/lib/*; do
  [ -e "$lib" ] || continue
  if ldconfig -p | awk -v n="$(basename "$lib")" '$1 == n {found = 1} END {exit !found}'; then
    mv "$lib" "$here/lib.machine/"
  fi
done
export LD_LIBRARY_PATH="$here/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
# NVIDIA's container toolkit installs its Vulkan manifest outside the loader's search path.
if [ -z "${VK_DRIVER_FILES:-}${VK_ICD_FILENAMES:-}" ]; then
  for j in /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json /etc/vulkan/icd.d/nvidia_icd.json \
           /usr/share/vulkan/icd.d/nvidia_icd.json; do
    if [ -f "$j" ]; then export VK_DRIVER_FILES="$j" VK_ICD_FILENAMES="$j"; break; fi
  done
fi
missing=$(ldd "$here/bin/wrsfov-bench" | grep 'not found' || true)
if [ -n "$missing" ]; then echo "run.sh: libraries not found:"; echo "$missing"; exit 1; fi
for f in "$here/bin/hello_xr" "$here/xr/libwrsfov_xr.so"; do
  m=$(ldd "$f" | grep 'not found' || true)
  if [ -n "$m" ]; then echo "run.sh: $(basename "$f") lacks libraries (its stage will fail):"; echo "$m"; fi
done
# The runtime's manifest, naming the library where the kit was unpacked.
cat >"$here/xr/wrsfov_xr.json" <<JSON
{
  "file_format_version": "1.0.0",
  "runtime": {
    "name": "wrsfov simulated HMD",
    "library_path": "$here/xr/libwrsfov_xr.so"
  }
}
JSON
# The statistics child lists the devices it finds when none is named like "_" (the variant key needs
# as many constants as eval::VariantKey has).
devices=$("$here/bin/wrsfov-bench" --cost-model-child device:_ classify:1,0,0,0,0,0,0,1,0 2>&1 || true)
echo "run.sh: $devices"
if ! printf '%s' "$devices" | grep -q '(devices: '; then
  echo "run.sh: no Vulkan device; the loader says:"
  VK_LOADER_DEBUG=error,driver "$here/bin/wrsfov-bench" --cost-model-child device:_ classify:1,0,0,0,0,0,0,1,0 2>&1 | tail -15
  echo "run.sh: where NVIDIA's driver is found but gives no vkCreateInstance, libglvnd had to be installed"
  echo "        in the machine's own library path (on an NVIDIA H200 image: libglvnd0, libglx0, libegl1, libopengl0)."
  exit 1
fi
# WRSFOV_GPU_TESTS= (empty) skips the tests; GTEST_FILTER picks some; WRSFOV_GPU_BENCH_DRY=1 sizes
# everything for a CPU renderer.
export WRSFOV_BENCH="$here/bin/wrsfov-bench" WRSFOV_GPU_TESTS="${WRSFOV_GPU_TESTS-$here/bin/wrsfov_gpu_tests}"
export WRSFOV_XR_RUNTIME_JSON="$here/xr/wrsfov_xr.json" WRSFOV_HELLO_XR="$here/bin/hello_xr"
export WRSFOV_COMMIT="$(cat "$here/COMMIT")"
out="${1:-$here/out/gpu-bench}"
case "$out" in /*) ;; *) out="$PWD/$out" ;; esac
exec bash "$here/tools/gpu-bench.sh" "$out"
RUN
chmod +x "$kit/run.sh"
mkdir -p "$(dirname "$archive")"
echo "== packing $(du -sh "$kit" | cut -f1) into $archive (xz, a few minutes)"
tar -C "$stage" -cf - wrsfov-gpu-kit | xz -T0 "${WRSFOV_KIT_XZ:--6}" >"$archive"
echo "== $archive: $(du -h "$archive" | cut -f1); there: tar xJf $(basename "$archive") && wrsfov-gpu-kit/run.sh"
