#!/usr/bin/env bash
# format_lint ROOT CLANG_FORMAT: fails, listing the files, when a tracked C++
# source of ROOT differs from what .clang-format makes of it (the planted lint
# trees are left as written). Reads the files git tracks, or every C++ file
# under ROOT when it is not a git checkout (a source archive).
set -uo pipefail
root="$1"
clang_format="$2"
cd "$root" || exit 2
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.h' '*.cc' | grep -v '^tests/lint/planted')
else
  mapfile -t files < <(find sim_core hal firmware host_tools tests -name '*.cpp' -o -name '*.hpp' -o -name '*.h' -o -name '*.cc' |
    grep -v '^tests/lint/planted')
fi
# One clang-format process for every file; its diagnostics name each file.
mapfile -t bad < <("$clang_format" --dry-run -Werror "${files[@]}" 2>&1 | sed -n 's/^\([^:]*\):[0-9]*:[0-9]*: error:.*/\1/p' | sort -u)
if [ "${#bad[@]}" -gt 0 ]; then
  printf 'format_lint: not as .clang-format writes it (run clang-format -i):\n'
  printf '  %s\n' "${bad[@]}"
  exit 1
fi
echo "format_lint: ${#files[@]} files as .clang-format writes them"
