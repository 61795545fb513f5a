#!/usr/bin/env bash
# The installed SDK as a consumer sees it (docs/install.md):
#   1. `cmake --install` of the build tree into a scratch prefix, and what
#      landed there (header, libmbx with its soname, CLI, CMake package, .pc,
#      Python package; no static internal library, nothing of them in the
#      exported targets or the .pc);
#   2. consumer/ configured with find_package(mbx 0.1) against that prefix
#      only, its C and C++ hosts built and run;
#   3. the C host built again with only `pkg-config --cflags --libs mbx`.
# usage: consumer_test.sh <build dir> <source dir> <work dir> <cc> <cxx> [extra compile+link flags]
# The extra flags are the sanitizers' in the ASan build: an instrumented
# libmbx needs instrumented executables (tests/install/CMakeLists.txt).
set -euo pipefail
build=$1 src=$2 work=$3 cc=$4 cxx=$5 flags=${6:-}
rm -rf "$work"
mkdir -p "$work/out"
prefix=$work/prefix
fail() { echo "consumer_test: $*" >&2; exit 1; }

cmake --install "$build" --prefix "$prefix" >"$work/install.log"

# 1. The installed tree.
libdir=$(dirname "$(find "$prefix" -name 'libmbx.so.0' | head -1)")
[[ -n "$libdir" && -d "$libdir" ]] || fail "no libmbx.so.0 installed"
[[ -f "$prefix/include/mbx/mbx.h" && -f "$prefix/include/mbx/mbx_files.h" ]] || fail "headers missing"
[[ -L "$libdir/libmbx.so" && -L "$libdir/libmbx.so.0" ]] || fail "libmbx.so / libmbx.so.0 links missing"
soname=$(readelf -d "$libdir/libmbx.so" | sed -n 's/.*Library soname: \[\(.*\)\]/\1/p')
[[ "$soname" == "libmbx.so.0" ]] || fail "libmbx soname is '$soname', expected libmbx.so.0"
[[ -x "$prefix/bin/mbx" ]] || fail "CLI missing"
"$prefix/bin/mbx" --version | grep -q '^mbx 0\.1\.' || fail "installed CLI does not run"
# The CLI must use the installed libmbx, not the build tree's.
cli_libmbx=$(ldd "$prefix/bin/mbx" | sed -n 's/.*libmbx\.so\.0 => \(.*\) (0x.*/\1/p')
[[ -n "$cli_libmbx" && "$(realpath "$cli_libmbx")" == "$(realpath "$libdir/libmbx.so.0")" ]] \
    || fail "installed CLI loads '$cli_libmbx', not the installed libmbx"
[[ -f "$libdir/cmake/mbx/mbxConfig.cmake" && -f "$libdir/cmake/mbx/mbxConfigVersion.cmake" ]] || fail "CMake package missing"
[[ -f "$libdir/pkgconfig/mbx.pc" ]] || fail "mbx.pc missing"
[[ -f "$prefix/lib/python3/dist-packages/mbx/__init__.py" ]] || fail "Python package missing"
if find "$prefix" -name '*.a' | grep -q .; then fail "static libraries installed: $(find "$prefix" -name '*.a')"; fi
for internal in mbx_core mbx_sim mbx_export mbx_calibration mbx_contact mbx_pmxml_vrml mbx_memory_host \
                Eigen3 pugixml assimp SUNDIALS Ceres; do
    if grep -q "$internal" "$libdir"/cmake/mbx/*.cmake "$libdir/pkgconfig/mbx.pc"; then
        fail "the installed package names the internal dependency $internal"
    fi
done
# Only the C API leaves the libraries.
if nm -D --defined-only "$libdir/libmbx.so.0" | awk '$2 ~ /[TDBRW]/ {print $3}' | grep -v '^mbx_' | grep -q .; then
    fail "libmbx exports non-mbx_ symbols"
fi

# 2. find_package(mbx 0.1), from the scratch prefix only.
cmake -S "$src/tests/install/consumer" -B "$work/consumer" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_C_COMPILER="$cc" -DCMAKE_CXX_COMPILER="$cxx" \
    -DCMAKE_C_FLAGS="$flags" -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="$flags" \
    -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF >"$work/consumer.log" \
    || { cat "$work/consumer.log"; fail "consumer configure failed"; }
found=$(sed -n 's/^mbx_DIR:PATH=//p' "$work/consumer/CMakeCache.txt")
[[ "$found" == "$libdir/cmake/mbx" ]] || fail "find_package(mbx) found '$found', not the scratch prefix"
cmake --build "$work/consumer" >"$work/consumer_build.log" 2>&1 \
    || { cat "$work/consumer_build.log"; fail "consumer build failed"; }
"$work/consumer/c_host" "$src/samples" "$work/out"
"$work/consumer/cpp_host" "$src/samples" "$work/out"
# A version the package does not provide is refused.
cat >"$work/too_new.cmake" <<CMAKE
set(CMAKE_PREFIX_PATH "$prefix")
find_package(mbx 0.2 QUIET)
if(mbx_FOUND)
  message(FATAL_ERROR "find_package(mbx 0.2) accepted 0.1")
endif()
CMAKE
cmake -P "$work/too_new.cmake" || fail "version check"

# 3. pkg-config only.
export PKG_CONFIG_PATH="$libdir/pkgconfig"
pc_libdir=$(pkg-config --variable=libdir mbx)
[[ "$(realpath "$pc_libdir")" == "$(realpath "$libdir")" ]] || fail "mbx.pc libdir '$pc_libdir' is not $libdir"
# shellcheck disable=SC2046,SC2086
"$cc" $flags -I"$src/tests/install/consumer" -o "$work/c_host_pkgconfig" "$src/tests/install/consumer/c_host.c" \
    $(pkg-config --cflags --libs mbx) -lmbx_files -lm -Wl,-rpath,"$pc_libdir"
mkdir -p "$work/out_pkgconfig"
"$work/c_host_pkgconfig" "$src/samples" "$work/out_pkgconfig"
# 4. The installed Python package finds the installed libraries by itself
# (its _paths.py), with no MBX_LIBRARY. Not in the sanitizer build: an
# uninstrumented python3 needs the runtimes preloaded (tests/python does that).
if [[ -z "$flags" ]] && [[ -x /usr/bin/python3 ]] && /usr/bin/python3 -c 'import numpy' 2>/dev/null; then
    env -u MBX_LIBRARY -u MBX_FILES_LIBRARY PYTHONPATH="$prefix/lib/python3/dist-packages" PYTHONDONTWRITEBYTECODE=1 \
        /usr/bin/python3 - "$src/samples" "$libdir" <<'PY' || fail "installed Python package"
import os, sys
import mbx, mbx._lib
samples, libdir = sys.argv[1], sys.argv[2]
assert os.path.realpath(mbx._lib.lib._name) == os.path.realpath(os.path.join(libdir, "libmbx.so.0")), mbx._lib.lib._name
arm = mbx.translate(os.path.join(samples, "five_axis_arm", "five_axis_arm.xml"))
assert arm.summary.rigid_body_count == 5 and arm.summary.dof == 5
print("consumer_test: installed Python package loads", mbx._lib.lib._name)
PY
fi
echo "consumer_test: installed SDK used through find_package and pkg-config"
