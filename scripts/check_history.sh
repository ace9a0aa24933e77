#!/usr/bin/env bash
# The product speaks of itself: code, README and docs say what the library is and why, never the
# issue, session or work period a change came from (that history belongs in CHANGELOG.md and the
# commit messages, which this check leaves alone). Fails, listing file:line and the text, where a
# tracked file's contents or name cite an issue number ("issue 13", "issue #7", "issues 13 and 16"),
# a session ("session 7", "this session's runs") or a work period ("work period 9"), or carry a
# work-period suffix ("h100_gpu_suite_s9.log", "h100_s5_diffuse.csv"), or a recorded run under
# docs/ is named by a stage of the work ("h100_bench_sizes_v5a.csv", "h100_gpu_suite_final.log"):
# name a log by what it measures and its commit.
#
#   bash scripts/check_history.sh     # from anywhere in the repository; about a second
#
# scripts/check_history.allow lists paths (one per line, '#' comments) whose findings are shown
# but tolerated for now; an empty list tolerates nothing.
set -uo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root" || exit 1
allow_file="scripts/check_history.allow"

# Case-insensitive: an issue, session or work-period number, or a session or work period pointed
# at ("this session's runs", "in the same work period").
period='(this|that|next|last|previous|same|earlier|a) (session|work[ -]period)([^[:alnum:]]|$)'
words="(^|[^[:alnum:]])(issues?[ _#-]*[0-9]|sessions?[ _#-]*[0-9]|work[ -]periods?[ _#-]*[0-9]|$period)"
# Case-sensitive: a work-period suffix in a file name (_s9.log, _s5_open.log, h100_s5_mesh.csv).
suffix='_s[0-9]+(_[[:alnum:]]+)*\.(log|csv|txt|json|png)|_s[0-9]+_'
# A stage of the work in the name of a recorded run under docs/ (_v5, _v5a_, _final.log).
stage='_(v[0-9]+[a-z]?|final)([._]|$)'

# Exempt: the history itself, this check (its patterns and examples), and the contents of
# recorded output (logs and CSVs are what a run printed; their names are still checked).
exempt=(':!CHANGELOG.md' ':!scripts/check_history.sh' ':!scripts/check_history.allow' ':!*.log' ':!*.csv')

allowed=()
if [ -f "$allow_file" ]; then
  while IFS= read -r line; do
    line="${line%%#*}"
    line="${line//[[:space:]]/}"
    [ -n "$line" ] && allowed+=("$line")
  done <"$allow_file"
fi

is_allowed() {  # is_allowed PATH: PATH equals or lies under an allow-listed path
  local a
  for a in "${allowed[@]+"${allowed[@]}"}"; do
    [ "$1" = "$a" ] || [[ "$1" == "$a"/* ]] && return 0
  done
  return 1
}

if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  hits="$( { git grep -n -I -i -E "$words" -- . "${exempt[@]}"
             git grep -n -I -E "$suffix" -- . "${exempt[@]}"; } | sort -u -t: -k1,1 -k2,2n)"
  names="$(git ls-files | grep -E -i 'issues?[ _#-]*[0-9]|session' ; git ls-files | grep -E '_s[0-9]+([._]|$)'
           git ls-files docs | grep -E "$stage")"
else  # a source tarball: every text file but build output
  excl=(--exclude=CHANGELOG.md --exclude=check_history.sh --exclude=check_history.allow
        --exclude='*.log' --exclude='*.csv' --exclude-dir=.git --exclude-dir='build*')
  hits="$( { grep -r -n -I -i -E "$words" "${excl[@]}" . ; grep -r -n -I -E "$suffix" "${excl[@]}" . ; } |
           sed 's|^\./||' | sort -u -t: -k1,1 -k2,2n)"
  names="$(find . -path ./.git -prune -o -path './build*' -prune -o -type f -print | sed 's|^\./||' |
           grep -E -i 'issues?[ _#-]*[0-9]|session'; find . -path ./.git -prune -o -type f -print |
           sed 's|^\./||' | grep -E '_s[0-9]+([._]|$)'; find docs -type f 2>/dev/null | grep -E "$stage")"
fi

failed=0 tolerated=0
report() {  # report PATH TEXT
  if is_allowed "$1"; then
    echo "  tolerated (allow-listed): $2"
    tolerated=$((tolerated + 1))
  else
    echo "  $2"
    failed=$((failed + 1))
  fi
}

while IFS= read -r hit; do
  [ -n "$hit" ] || continue
  report "${hit%%:*}" "$(printf '%s' "$hit" | cut -c1-200)"
done <<<"$hits"
while IFS= read -r name; do
  [ -n "$name" ] || continue
  report "$name" "$name: a file named by an issue or a work period"
done <<<"$(printf '%s\n' "$names" | sort -u)"

if [ "$failed" -gt 0 ]; then
  echo "check_history.sh: FAILED: $failed lines or names cite issues, sessions or work periods" \
       "($tolerated tolerated); move history to CHANGELOG.md or a commit message"
  exit 1
fi
echo "check_history.sh: ok: no issue numbers or work periods in code, README or docs ($tolerated tolerated)"
