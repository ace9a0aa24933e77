#!/usr/bin/env bash
# Checks that every artefact states the same version (a ctest test, label `packaging`):
#
#   bash scripts/check_versions.sh
#
#   include/pbf_c_api.h                PBF_VERSION_MAJOR/MINOR/PATCH        (required)
#   CMakeLists.txt                     project(libpbf VERSION x.y.z)        (required)
#   bindings/csharp/**/*.cs            PBF_VERSION_MAJOR/MINOR/PATCH = n    (C# files defining them)
#   bindings/csharp/unity/package.json "version"                            (if present)
#   bindings/csharp/Pbf.csproj         <Version>                            (if present)
#   bindings/csharp/nuget/Pbf.nuspec   <version>                            (if present)
#
# The header is the reference. Exits 1 listing every file that disagrees with it, or that is
# required and missing or unreadable; prints the agreed version otherwise.
set -uo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root" || exit 1
problems=()
declare -a found=()

# The first x.y.z that the command prints, or nothing.
semver() { grep -m1 -oE '[0-9]+\.[0-9]+\.[0-9]+' || true; }

# MAJOR.MINOR.PATCH from three "NAME = n" / "#define NAME n" lines of a C or C# file.
three_defines() {
  local file="$1" part value out=""
  for part in MAJOR MINOR PATCH; do
    # Only a definition counts ("#define NAME n" in C, "NAME = n" in C#), not a mention in a comment.
    value="$(grep -m1 -E "^[[:space:]]*#[[:space:]]*define[[:space:]]+PBF_VERSION_${part}[[:space:]]+[0-9]+|PBF_VERSION_${part}[[:space:]]*=[[:space:]]*[0-9]+" "$file" |
      grep -oE '[0-9]+' | tail -n 1)"
    [ -z "$value" ] && return 0
    out="${out:+$out.}$value"
  done
  echo "$out"
}

record() {  # file, version (empty: unreadable), required (1/0)
  local file="$1" version="$2" required="$3"
  if [ ! -e "$file" ]; then
    [ "$required" = 1 ] && problems+=("$file: missing")
    return
  fi
  if [ -z "$version" ]; then
    problems+=("$file: no version found in it")
    return
  fi
  found+=("$file=$version")
}

header=include/pbf_c_api.h
header_version=""
[ -e "$header" ] && header_version="$(three_defines "$header")"
record "$header" "$header_version" 1

cmake_version=""
[ -e CMakeLists.txt ] &&
  cmake_version="$(tr '\n' ' ' <CMakeLists.txt | grep -oE 'project\([[:space:]]*libpbf[^)]*\)' | grep -oE 'VERSION[[:space:]]+[0-9]+\.[0-9]+\.[0-9]+' | semver)"
record CMakeLists.txt "$cmake_version" 1

# The C# mirror of the header's constants (Native.cs), wherever the bindings keep it.
while IFS= read -r f; do
  record "$f" "$(three_defines "$f")" 0
done < <(grep -rl --include='*.cs' --exclude-dir=build --exclude-dir=obj --exclude-dir=bin \
           -E 'PBF_VERSION_MAJOR[[:space:]]*=' bindings/csharp 2>/dev/null | sort)

f=bindings/csharp/unity/package.json
[ -e "$f" ] && record "$f" "$(grep -m1 -E '^[[:space:]]*"version"[[:space:]]*:' "$f" | semver)" 0

f=bindings/csharp/Pbf.csproj
if [ -e "$f" ] && grep -q '<Version>' "$f"; then
  record "$f" "$(grep -m1 -oE '<Version>[^<]*</Version>' "$f" | semver)" 0
fi

f=bindings/csharp/nuget/Pbf.nuspec
[ -e "$f" ] && record "$f" "$(grep -m1 -oE '<version>[^<]*</version>' "$f" | semver)" 0

for entry in "${found[@]}"; do
  file="${entry%%=*}" version="${entry#*=}"
  if [ -n "$header_version" ] && [ "$version" != "$header_version" ]; then
    problems+=("$file: $version (the header says $header_version)")
  fi
done

if [ "${#problems[@]}" -ne 0 ]; then
  echo "check_versions.sh: versions disagree:"
  printf '  %s\n' "${problems[@]}"
  echo "checked: ${found[*]}"
  exit 1
fi
echo "check_versions.sh: all at $header_version (${found[*]%%=*})"
