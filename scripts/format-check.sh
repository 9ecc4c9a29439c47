#!/usr/bin/env bash
# Checks that every C++ source is formatted with .clang-format; with --fix, formats them.
set -euo pipefail
cd "$(dirname "$0")/.."

mapfile -t files < <(git ls-files --cached --others --exclude-standard -- '*.cpp' '*.hpp' '*.c' '*.h')
if [ "${1:-}" = "--fix" ]; then
    clang-format -i "${files[@]}"
    exit 0
fi
if ! clang-format --dry-run --Werror "${files[@]}"; then
    echo "format-check: run scripts/format-check.sh --fix" >&2
    exit 1
fi
echo "format-check: ${#files[@]} files formatted"
