#!/usr/bin/env bash
# Formats every tracked C/C++ source file in place as .clang-format says (or the FILEs given);
# `make test` checks it (scripts/check-format.sh, the ctest test `format`).
# Usage: scripts/format.sh [FILE...]
exec "$(dirname "$0")/check-format.sh" --fix "$@"
