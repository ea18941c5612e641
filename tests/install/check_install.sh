#!/bin/sh
# The installed tree as an integrator gets it (tests/install/CMakeLists.txt). Each check is named.
# usage: check_install.sh BUILD_DIR SOURCE_DIR OUT_DIR
set -u
build=$1 src=$2 out=$3
rm -rf "$out"
mkdir -p "$out"
. "$src/tests/cli_check.sh"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
jobs=$(nproc)
prefix="$out/prefix"
# The Khronos validation layer under programs that make their own instance (the example does).
validated() { VK_INSTANCE_LAYERS=VK_LAYER_KHRONOS_validation "$@"; }
no_validation_messages() {  # no_validation_messages LOG
    ! grep -q -E "Validation (Error|Warning)|VUID-" "$1"
}
files_present() {  # files_present ROOT PATH...
    root=$1
    shift
    for f in "$@"; do
        [ -e "$root/$f" ] || { echo "missing: $root/$f"; return 1; }
    done
    echo "all present under $root"
}
exports_only_wrsfov() {  # every exported symbol of the library demangles into wrsfov::
    others=$(nm -DC --defined-only "$1" | awk '$2 != "A"' | grep -v -E " (wrsfov::|vtable for wrsfov::|typeinfo for wrsfov::|typeinfo name for wrsfov::)" || true)
    [ -z "$others" ] || { echo "exported outside wrsfov::"; echo "$others" | head; return 1; }
    echo "$(nm -D --defined-only "$1" | wc -l) symbols, all in wrsfov::"
}
layout="lib/libwrsfov_compositor.so lib/libwrsfov_compositor.so.0.1 lib/libwrsfov_gaze.so.0.1
 lib/libwrsfov_xr.so lib/libwrsfov_xr_layer.so
 include/wrsfov/stereo_compositor.h include/wrsfov/settings.h include/wrsfov/submission.h include/wrsfov/image.h
 include/wrsfov/layers/frame.h include/wrsfov/gaze/source.h
 lib/cmake/wrsfov/wrsfovConfig.cmake lib/cmake/wrsfov/wrsfovConfigVersion.cmake lib/cmake/wrsfov/wrsfovTargets.cmake
 lib/pkgconfig/wrsfov.pc lib/pkgconfig/wrsfov-gaze.pc
 bin/wrsfov-bench bin/wrsfov-demo bin/wrsfov-gaze bin/wrsfov-preview bin/wrsfov-stress
 share/openxr/1/openxr_wrsfov.json share/openxr/1/api_layers/explicit.d/XrApiLayer_wrsfov_foveation.json
 share/doc/wrsfov/README.md share/doc/wrsfov/integrating.md share/doc/wrsfov/examples/stereo_frame.cpp"

# ---- cmake --install into a scratch prefix ------------------------------------------------------
cli_check install 0 "" cmake --install "$build" --prefix "$prefix"
cli_check install_layout 0 "all present" files_present "$prefix" $layout
cli_check install_soname 0 "SONAME.*libwrsfov_compositor.so.0.1" readelf -d "$prefix/lib/libwrsfov_compositor.so"
cli_check install_exports_compositor 0 "all in wrsfov::" exports_only_wrsfov "$prefix/lib/libwrsfov_compositor.so"
cli_check install_exports_gaze 0 "all in wrsfov::" exports_only_wrsfov "$prefix/lib/libwrsfov_gaze.so"
# The internal static libraries, the compositor's and shaders' headers and test-only headers stay out.
cli_check install_no_internals 1 "" sh -c "{ ls '$prefix/lib' | grep -E '\\.a\$'; ls -R '$prefix/include' | grep -E 'compositor:|shaders:|gpu_rig|bindings|xr_|reference_impl'; } | grep ."
# Each installed header compiles on its own (one compiler a header, as many at a time as there are cores).
headers_compile_alone() {
    (cd "$prefix/include" && find wrsfov -name '*.h') | xargs -P "$jobs" -I{} sh -c \
        'echo "#include <{}>" | c++ -std=c++20 -fsyntax-only -x c++ -I"$1/include" -I"$1/include/wrsfov" - ||
         { echo "does not compile alone: {}"; exit 255; }' sh "$prefix" || return 1
    echo "every header compiles alone"
}
cli_check install_headers_alone 0 "every header compiles alone" headers_compile_alone

# ---- the example, built with find_package against the prefix, run under validation ---------------
ex="$out/example"
cli_check example_configure 0 "" cmake -S "$prefix/share/doc/wrsfov/examples" -B "$ex" -DCMAKE_PREFIX_PATH="$prefix"
cli_check example_build 0 "" cmake --build "$ex" -j "$jobs"
cli_check example_run 0 "wrsfov-example: 60 frames composited" validated "$ex/wrsfov-example" 60 "$out/example_out"
cli_check example_history_kept 0 "^    60 .* kept\$" cat "$out/example_run.log"
cli_check example_no_validation_messages 0 "" no_validation_messages "$out/example_run.log"
cli_check example_validation_layer_loaded 0 'Insert instance layer "VK_LAYER_KHRONOS_validation"' \
    env VK_LOADER_DEBUG=layer VK_INSTANCE_LAYERS=VK_LAYER_KHRONOS_validation "$ex/wrsfov-example" 2
cli_check example_wrote_images 0 "" test -s "$out/example_out_left.ppm"
# find_package refuses a version it cannot promise (0.x: the minor must match).
mkdir -p "$out/wrong_version"
printf 'cmake_minimum_required(VERSION 3.25)\nproject(v LANGUAGES CXX)\nfind_package(wrsfov 0.2 REQUIRED)\n' >"$out/wrong_version/CMakeLists.txt"
cli_check example_wrong_version_refused 1 "wrsfov" cmake -S "$out/wrong_version" -B "$out/wrong_version/b" -DCMAKE_PREFIX_PATH="$prefix"

# ---- pkg-config ---------------------------------------------------------------------------------
pc() { PKG_CONFIG_PATH="$prefix/lib/pkgconfig" pkg-config "$@"; }
cli_check pkgconfig_version 0 "0.1.0" pc --modversion wrsfov
cli_check pkgconfig_build 0 "" sh -c "c++ -std=c++20 -o '$out/pc_example' '$prefix/share/doc/wrsfov/examples/stereo_frame.cpp' \$(PKG_CONFIG_PATH='$prefix/lib/pkgconfig' pkg-config --cflags --libs wrsfov-gaze)"
cli_check pkgconfig_run 0 "wrsfov-example: 3 frames composited" env LD_LIBRARY_PATH="$prefix/lib" "$out/pc_example" 3

# ---- the Debian package -------------------------------------------------------------------------
cli_check deb_build 0 "package: .*wrsfov_0.1.0_amd64.deb generated" cpack -G DEB -B "$out/deb" --config "$build/CPackConfig.cmake"
deb="$out/deb/wrsfov_0.1.0_amd64.deb"
cli_check deb_depends 0 "Depends:.*libvulkan1.*" dpkg-deb -I "$deb"
cli_check deb_depends_opencv 0 "libopencv-core" cat "$out/deb_depends.log"
cli_check deb_extract 0 "" dpkg -x "$deb" "$out/root"
cli_check deb_layout 0 "all present" files_present "$out/root/usr" $layout
cli_check deb_manifest_relative 0 '"library_path": "../../../lib/libwrsfov_xr.so"' cat "$out/root/usr/share/openxr/1/openxr_wrsfov.json"
cli_check deb_example_build 0 "" sh -c "cmake -S '$out/root/usr/share/doc/wrsfov/examples' -B '$out/deb_example' -DCMAKE_PREFIX_PATH='$out/root/usr' && cmake --build '$out/deb_example' -j $jobs"
cli_check deb_example_run 0 "wrsfov-example: 3 frames composited" env LD_LIBRARY_PATH="$out/root/usr/lib" "$out/deb_example/wrsfov-example" 3
cli_check deb_tool_runs 0 "wrsfov-gaze" env LD_LIBRARY_PATH="$out/root/usr/lib" "$out/root/usr/bin/wrsfov-gaze" --help

# ---- the compositor-only build: Vulkan, glm and glslang, nothing else ----------------------------
co="$out/compositor_only"
cli_check co_configure 0 "" cmake -S "$src" -B "$co/build" -DWRSFOV_COMPOSITOR_ONLY=ON -DCMAKE_BUILD_TYPE=Release
cli_check co_no_other_dependencies 1 "" grep -E "^(OpenCV_DIR|GTest_DIR|OpenXR_DIR|HIDAPI_FOUND|GLFW_FOUND)" "$co/build/CMakeCache.txt"
cli_check co_build 0 "" cmake --build "$co/build" -j "$jobs"
cli_check co_install 0 "" cmake --install "$co/build" --prefix "$co/prefix"
cli_check co_layout 0 "all present" files_present "$co/prefix" lib/libwrsfov_compositor.so.0.1 \
    include/wrsfov/stereo_compositor.h lib/cmake/wrsfov/wrsfovConfig.cmake lib/pkgconfig/wrsfov.pc
cli_check co_no_gaze 1 "" test -e "$co/prefix/lib/libwrsfov_gaze.so"
cli_check co_links_vulkan_only 1 "" sh -c "readelf -d '$co/prefix/lib/libwrsfov_compositor.so' | grep NEEDED | grep -v -E 'libvulkan|libstdc|libm\\.|libgcc_s|libc\\.'"
cli_check co_consumer_build 0 "" sh -c "cmake -S '$src/tests/install/compositor_only' -B '$co/consumer' -DCMAKE_PREFIX_PATH='$co/prefix' && cmake --build '$co/consumer' -j $jobs"
cli_check co_consumer_run 0 "output grey as submitted" "$co/consumer/compositor-only-consumer"
# Asking that install for the gaze component fails at find_package, naming it.
cli_check co_gaze_component_missing 1 "component gaze is not in this install" cmake -S "$src/examples" -B "$co/example" -DCMAKE_PREFIX_PATH="$co/prefix"

cli_summary
