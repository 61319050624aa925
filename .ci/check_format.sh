#!/usr/bin/env bash
# The repository's .clang-format on every tracked C++ file: lists the files that differ and fails
# (CI), or with --fix rewrites them in place. Uses Debian 12's clang-format (14), the version the
# tree is formatted with: another version may format some constructs differently.
set -euo pipefail
cd "$(dirname "$0")/.."

mapfile -t files < <(git ls-files -- '*.cpp' '*.hpp' '*.h' '*.cc')
if [ "${1:-}" = "--fix" ]; then
  clang-format -i "${files[@]}"
  exit 0
fi
bad=()
for f in "${files[@]}"; do
  clang-format --dry-run --Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if ((${#bad[@]})); then
  echo "clang-format: ${#bad[@]} of ${#files[@]} files differ from .clang-format (fix: bash .ci/check_format.sh --fix):" >&2
  printf '  %s\n' "${bad[@]}" >&2
  exit 1
fi
echo "clang-format: ${#files[@]} files formatted"
