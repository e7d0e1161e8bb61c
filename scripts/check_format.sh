#!/usr/bin/env bash
# Fails when a C++ file of the repository differs from what clang-format makes of it (.clang-format:
# Google style, 120 columns). Fix with: scripts/check_format.sh --fix
#   usage: scripts/check_format.sh [--fix]
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
cd "$repo"
command -v clang-format >/dev/null || "$repo/scripts/setup.sh" --no-build  # installs clang-format with the rest
mapfile -t files < <(git ls-files '*.cc' '*.h')
if [ "${1:-}" = "--fix" ]; then
  clang-format -i "${files[@]}"
  echo "formatted ${#files[@]} files"
  exit 0
fi
bad=()
for file in "${files[@]}"; do
  clang-format --dry-run --Werror "$file" >/dev/null 2>&1 || bad+=("$file")
done
if [ ${#bad[@]} -gt 0 ]; then
  printf 'not formatted: %s\n' "${bad[@]}"
  echo "format: ${#bad[@]} of ${#files[@]} files differ from clang-format (run scripts/check_format.sh --fix)"
  exit 1
fi
echo "format: all ${#files[@]} C++ files as clang-format makes them"
