#!/usr/bin/env bash
# Checks that every tracked C/C++ source file is formatted as .clang-format says (the ctest test
# `format`, run by `make test`). Lists the files that differ and exits with 1 if there are any.
# With --fix (what scripts/format.sh runs) formats them in place instead.
# Usage: scripts/check-format.sh [--fix] [FILE...]    (default: every tracked *.cpp, *.hpp, *.h, *.c)
# CLANG_FORMAT names the program (default: clang-format; the config is for Debian 12's version 14).
set -euo pipefail
clang_format=${CLANG_FORMAT:-clang-format}
fix=false
if [ "${1:-}" = --fix ]; then
  fix=true
  shift
fi

if [ $# -gt 0 ]; then
  files=("$@")
else
  cd "$(dirname "$0")/.."
  mapfile -t files < <(git ls-files -- '*.cpp' '*.hpp' '*.h' '*.c')
fi
existing=()
for f in "${files[@]}"; do
  [ -f "$f" ] && existing+=("$f")  # (a file deleted in the work tree is skipped)
done
if [ ${#existing[@]} -eq 0 ]; then
  echo "check-format: no files"
  exit 0
fi

version=$("$clang_format" --version)
case "$version" in
  *"version 14."*) ;;
  *) echo "check-format: warning: .clang-format is tuned for clang-format 14, this is: $version" >&2 ;;
esac

if $fix; then
  printf '%s\0' "${existing[@]}" | xargs -0 -n 64 "$clang_format" --style=file -i
  echo "check-format: formatted ${#existing[@]} files"
  exit 0
fi

# One run over all files; each difference is reported as "FILE:LINE:COLUMN: error: ...".
report=$(printf '%s\0' "${existing[@]}" |
  xargs -0 -n 64 "$clang_format" --style=file --dry-run --Werror --ferror-limit=1 2>&1) && status=0 || status=$?
mapfile -t differ < <(sed -n 's/^\(.*\):[0-9]*:[0-9]*: error: code should be clang-formatted.*/\1/p' <<<"$report" | sort -u)
if [ "$status" -ne 0 ] && [ ${#differ[@]} -eq 0 ]; then
  echo "check-format: $clang_format failed:" >&2
  echo "$report" >&2
  exit 2
fi

if [ ${#differ[@]} -eq 0 ]; then
  echo "check-format: ${#existing[@]} files formatted as .clang-format says"
  exit 0
fi
echo "check-format: ${#differ[@]} of ${#existing[@]} files differ from .clang-format:"
printf '  %s\n' "${differ[@]}"
echo "check-format: fix with scripts/format.sh (every file) or $clang_format -i FILE"
exit 1
