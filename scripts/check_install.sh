#!/usr/bin/env bash
# Installs a built libpbf into a temporary prefix and uses it the way another project would:
#
#   bash scripts/check_install.sh [BUILD_DIR=build]
#
#   1. cmake --install BUILD_DIR --prefix <tmp>: the library with its soname links, the header,
#      the CMake package (pbfConfig.cmake, pbfConfigVersion.cmake, pbfTargets.cmake), pbf.pc,
#      LICENSE; the exported target must carry no link dependency (static CUDA runtime, OpenMP).
#   2. tests/consumer with find_package(pbf 2 CONFIG REQUIRED) and pbf::pbf; built and run.
#   3. tests/consumer/consumer.c with `pkg-config --cflags --libs pbf`; built and run.
#   4. add_subdirectory: a parent project that adds libpbf's source tree gets the library but no
#      tests, samples or install rules (configure only).
#
# BUILD_DIR must hold a built libpbf (scripts/build.sh). The last line is the summary:
# "check_install.sh: ok: ..." or "check_install.sh: FAILED: ..."; exits non-zero on failure.
set -uo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root" || exit 1
build="${1:-build}"
cc="${CC:-cc}"
work="$(mktemp -d "${TMPDIR:-/tmp}/pbf-install.XXXXXX")"
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"
log="$work/log"

fail() {
  echo "check_install.sh: FAILED: $1"
  exit 1
}
run_logged() {  # runs a command, showing its output only if it fails
  if ! "$@" >"$log" 2>&1; then
    tail -n 40 "$log"
    return 1
  fi
}

[ -f "$build/CMakeCache.txt" ] || fail "$build is not a configured build (run scripts/build.sh first)"
command -v pkg-config >/dev/null 2>&1 || fail "pkg-config is not installed (scripts/install-deps.sh installs it)"

# ---- 1. install ---------------------------------------------------------------------------------
echo "== install $build into a temporary prefix"
run_logged cmake --install "$build" --prefix "$prefix" || fail "cmake --install $build"
pc="$(find "$prefix" -name pbf.pc -path '*/pkgconfig/*' | head -n 1)"
config="$(find "$prefix" -name pbfConfig.cmake | head -n 1)"
[ -n "$pc" ] || fail "no pkgconfig/pbf.pc installed"
[ -n "$config" ] || fail "no pbfConfig.cmake installed"
libdir="$(dirname "$(dirname "$pc")")"
cmakedir="$(dirname "$config")"
version="$(sed -n 's/^Version: *//p' "$pc")"
major="${version%%.*}"
missing=()
for f in "$prefix/include/pbf_c_api.h" "$libdir/libpbf.so" "$libdir/libpbf.so.$major" "$libdir/libpbf.so.$version" \
         "$cmakedir/pbfConfigVersion.cmake" "$cmakedir/pbfTargets.cmake"; do
  [ -e "$f" ] || missing+=("${f#"$prefix"/}")
done
[ -n "$(find "$prefix" -name LICENSE | head -n 1)" ] || missing+=("LICENSE")
[ "${#missing[@]}" -eq 0 ] || fail "not installed: ${missing[*]}"
[ -L "$libdir/libpbf.so" ] && [ -L "$libdir/libpbf.so.$major" ] || fail "libpbf.so and libpbf.so.$major are not symlinks"
soname="$(objdump -p "$libdir/libpbf.so.$version" 2>/dev/null | awk '/SONAME/ {print $2}')"
[ "$soname" = "libpbf.so.$major" ] || fail "soname is '$soname', expected libpbf.so.$major"
# The exported target must not hand its private dependencies to consumers.
leaks="$(grep -h -E -i 'cudart|CUDA::|OpenMP|Eigen|pbf_objects|INTERFACE_LINK_LIBRARIES' "$cmakedir"/pbfTargets*.cmake || true)"
[ -z "$leaks" ] || fail "pbfTargets.cmake exposes link dependencies: $leaks"
grep -q '^License: MIT' "$pc" || fail "pbf.pc states no licence"
# SameMajorVersion: any 2.x request is served by 2.y.z, 1.x and 3.x are not.
printf 'include("%s/pbfConfigVersion.cmake")\nmessage("${PACKAGE_VERSION_COMPATIBLE}")\n' "$cmakedir" >"$work/version.cmake"
for want in "$major.0:TRUE" "$((major - 1)).0:FALSE" "$((major + 1)).0:FALSE"; do
  got="$(cmake -DPACKAGE_FIND_VERSION="${want%%:*}" -DPACKAGE_FIND_VERSION_MAJOR="${want%%.*}" \
    -DPACKAGE_FIND_VERSION_MINOR=0 -DPACKAGE_FIND_VERSION_PATCH=0 -DPACKAGE_FIND_VERSION_COUNT=2 \
    -DCMAKE_SIZEOF_VOID_P=8 -P "$work/version.cmake" 2>&1)"
  [ "$got" = "${want#*:}" ] || fail "pbfConfigVersion.cmake: find_package(pbf ${want%%:*}) compatible='$got', expected ${want#*:}"
done
echo "installed libpbf $version (soname $soname) into $prefix: ${libdir#"$prefix"/}, include, ${cmakedir#"$prefix"/}"

# ---- 2. find_package ----------------------------------------------------------------------------
echo "== consumer with find_package(pbf 2 CONFIG REQUIRED)"
run_logged cmake -S tests/consumer -B "$work/consumer-cmake" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release ||
  fail "configuring tests/consumer with find_package(pbf)"
run_logged cmake --build "$work/consumer-cmake" || fail "building tests/consumer with find_package(pbf)"
out_cmake="$("$work/consumer-cmake/pbf_consumer" 2>&1)" || fail "find_package consumer: $out_cmake"
echo "$out_cmake"

# ---- 3. pkg-config ------------------------------------------------------------------------------
echo "== consumer with pkg-config --cflags --libs pbf"
export PKG_CONFIG_PATH="$(dirname "$pc")"
flags="$(pkg-config --cflags --libs pbf)" || fail "pkg-config --cflags --libs pbf"
pkg-config --atleast-version=2 pbf || fail "pkg-config: pbf is older than 2"
echo "pkg-config --cflags --libs pbf: $flags"
# shellcheck disable=SC2086  # the flags are words
run_logged "$cc" -std=c99 -Wall -Wextra -pedantic -Werror tests/consumer/consumer.c $flags \
  -Wl,-rpath,"$(pkg-config --variable=libdir pbf)" -o "$work/consumer-pc" ||
  fail "building tests/consumer/consumer.c with pkg-config"
out_pc="$("$work/consumer-pc" 2>&1)" || fail "pkg-config consumer: $out_pc"
echo "$out_pc"

# ---- 4. add_subdirectory --------------------------------------------------------------------------
echo "== parent project with add_subdirectory(libpbf) (configure only)"
mkdir -p "$work/parent"
cat >"$work/parent/CMakeLists.txt" <<CMAKE
cmake_minimum_required(VERSION 3.25)
project(pbf_parent LANGUAGES C CXX)
add_subdirectory("$root" libpbf)
add_executable(parent_app "$root/tests/consumer/consumer.c")
target_link_libraries(parent_app PRIVATE pbf::pbf)
CMAKE
run_logged cmake -S "$work/parent" -B "$work/parent/build" -DPBF_WITH_CUDA=OFF || fail "configuring a parent project"
extra="$(cmake --build "$work/parent/build" --target help | grep -E -o 'pbf_(api|unit|gpu|reliability|validation)_tests|dam_break|pbf_bench' | sort -u | tr '\n' ' ')"
[ -z "$extra" ] || fail "add_subdirectory also builds: $extra"
grep -q '^PBF_INSTALL:BOOL=OFF' "$work/parent/build/CMakeCache.txt" || fail "add_subdirectory: PBF_INSTALL is not OFF"
echo "add_subdirectory: library only (tests, samples and install rules off)"

echo "check_install.sh: ok: libpbf $version installed; find_package consumer OK; pkg-config consumer OK; add_subdirectory builds the library only"
