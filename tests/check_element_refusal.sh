#!/bin/sh
# Run dpmpm_element on a bad input and check that it is refused as a user should see it:
#   check_element_refusal.sh <dpmpm_element> <file.nml> <expected-substring>...
# Passes when it exits with status 2 within 60 s, stderr holds every expected text, and
# there is no Fortran runtime error (traceback, "Error termination", "At line").
set -u
if [ $# -lt 3 ]; then
  echo "usage: $0 <dpmpm_element> <file.nml> <expected-substring>..." >&2
  exit 2
fi
exe=$1 file=$2
shift 2
out=$(mktemp) err=$(mktemp)
trap 'rm -f "$out" "$err"' EXIT
timeout 60 "$exe" "$file" >"$out" 2>"$err"
rc=$?
echo "--- exit code $rc; stdout:"; cat "$out"
echo "--- stderr:"; cat "$err"
echo "---"
fail=0
if [ "$rc" -ne 2 ]; then
  echo "FAIL: exit code $rc, a refused input exits with 2"; fail=1
fi
for expected in "$@"; do
  if ! grep -qF -- "$expected" "$err"; then
    echo "FAIL: stderr does not contain: $expected"; fail=1
  fi
done
for bad in "Backtrace" "Error termination" "At line"; do
  if grep -qF -- "$bad" "$out" "$err"; then
    echo "FAIL: Fortran runtime error in the output ($bad)"; fail=1
  fi
done
if [ "$fail" -eq 0 ]; then echo "PASS"; fi
exit $fail
