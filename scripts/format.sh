#!/usr/bin/env bash
# Layout of the Fortran sources (src, app, tests): statement indentation by findent
# (two spaces, case labels two to the left of their block, continuation lines as
# written) and spacing by fprettify (.fprettify.rc; its own indentation is off, so
# continuation lines keep their hand alignment). Both tools come from PyPI, pinned in
# scripts/common.sh.
# Usage: scripts/format.sh           lay out every tracked Fortran file in place
#        scripts/format.sh --check   list the files whose layout differs; exit 1 if any
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$DPMPM_ROOT"
for tool in findent fprettify; do
  command -v "$tool" >/dev/null || { echo "format: $tool missing (pip install $DPMPM_PY_TOOLS)"; exit 2; }
done

# Lay out one file: $1 the source, $2 where the result goes.
layout() {
  findent -ifree -i2 -c2 -k- < "$1" > "$2.tmp"
  fprettify -c "$DPMPM_ROOT/.fprettify.rc" --disable-indent --silent --stdout "$2.tmp" > "$2"
  rm -f "$2.tmp"
}

files=$(git ls-files 'src/*.f90' 'app/*.f90' 'tests/*.f90')
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
changed=0
for f in $files; do
  layout "$f" "$work/out.f90"
  if ! cmp -s "$f" "$work/out.f90"; then
    changed=$((changed + 1))
    if [ "${1:-}" = --check ]; then
      echo "format: $f differs from its layout:"
      diff -u "$f" "$work/out.f90" | sed -n '3,14p' || true
    else
      cp "$work/out.f90" "$f"
      echo "format: $f"
    fi
  fi
done
if [ "${1:-}" = --check ]; then
  echo "format: $changed of $(echo "$files" | wc -w) files differ (scripts/format.sh lays them out)"
  [ "$changed" -eq 0 ]
fi
