#!/usr/bin/env bash
# Installs the Debian/Ubuntu packages that libpbf's build, tests and samples need, but only
# those that are missing (checked with dpkg -s). Uses sudo when not run as root.
# Prints nothing when everything is already installed.
#
#   scripts/install-deps.sh            the build, the tests, the samples, tools/bake (CLI11,
#                                      nlohmann-json), the headless renderer (EGL, GL, Mesa), the install check and the C# package
#                                      checks (nuget, unzip, python3, python3-clang: the C#
#                                      bindings' generator)
#   scripts/install-deps.sh windows    also the Windows cross build and its tests
#                                      (MinGW-w64 posix-thread compilers, Wine)
set -euo pipefail

packages=(cmake g++ make pkg-config libeigen3-dev catch2 libpng-dev
          mono-mcs mono-runtime nunit-console libnunit-cil-dev
          libcli11-dev nlohmann-json3-dev nuget unzip python3 python3-clang
          libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri)  # the renderer's smoke test (Mesa llvmpipe)
if [ "${1:-}" = windows ]; then
  packages+=(g++-mingw-w64-x86-64-posix gcc-mingw-w64-x86-64-posix wine wine64)
fi

missing=()
for p in "${packages[@]}"; do
  # dpkg -s also succeeds for a removed package whose config files remain: check its status.
  if ! dpkg -s "$p" 2>/dev/null | grep -q '^Status: install ok installed'; then
    missing+=("$p")
  fi
done
[ "${#missing[@]}" -eq 0 ] && exit 0

if ! command -v apt-get >/dev/null 2>&1; then
  echo "install-deps.sh: missing ${missing[*]}, and apt-get is not available: install them by hand" >&2
  exit 1
fi
sudo=()
if [ "$(id -u)" -ne 0 ]; then
  if ! command -v sudo >/dev/null 2>&1; then
    echo "install-deps.sh: missing ${missing[*]}; run as root or install sudo" >&2
    exit 1
  fi
  sudo=(sudo)
fi

echo "install-deps.sh: installing ${missing[*]}"
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
if ! { "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q &&
       "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q "${missing[@]}"; } >"$log" 2>&1; then
  cat "$log" >&2
  echo "install-deps.sh: apt-get failed" >&2
  exit 1
fi
