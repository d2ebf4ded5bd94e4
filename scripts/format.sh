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

# Lay out every file: findent one by one (it reads a stream), then fprettify once over the
# whole copy, since starting its interpreter per file cost most of the time (164 files:
# 34 s of CPU one by one).
files=$(git ls-files 'src/*.f90' 'app/*.f90' 'tests/*.f90')
# The fypp templates (src/solver/*.fypp) get fprettify's spacing; their indentation is
# kept as written, since findent does not read fypp's directive lines.
templates=$(git ls-files 'src/*.fypp')
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for f in $files; do
  mkdir -p "$work/$(dirname "$f")"
  findent -ifree -i2 -c2 -k- < "$f" > "$work/$f"
done
for f in $templates; do
  mkdir -p "$work/$(dirname "$f")"
  cp "$f" "$work/$f"
done
(cd "$work" && fprettify -c "$DPMPM_ROOT/.fprettify.rc" --disable-indent --silent $files $templates)
changed=0
for f in $files $templates; do
  if ! cmp -s "$f" "$work/$f"; then
    changed=$((changed + 1))
    if [ "${1:-}" = --check ]; then
      echo "format: $f differs from its layout:"
      diff -u "$f" "$work/$f" | sed -n '3,14p' || true
    else
      cp "$work/$f" "$f"
      echo "format: $f"
    fi
  fi
done
if [ "${1:-}" = --check ]; then
  echo "format: $changed of $(echo $files $templates | wc -w) files differ (scripts/format.sh lays them out)"
  [ "$changed" -eq 0 ]
fi
