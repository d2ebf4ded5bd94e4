#!/bin/sh
# Run dpmpm on a bad input file and check that it fails the way a user should see it:
#   check_bad_input.sh <mpiexec> <dpmpm> <nranks> <file.nml> <expected-substring>
# Passes when the run ends within 60 s with a non-zero exit code, stderr contains the
# expected text, every input error line appears once (printed by rank 0 only), and there
# is no Fortran runtime error (traceback, "Error termination", "At line").
set -u
. "$(dirname "$0")/input_run.sh"
input_args expected-substring "$@"
input_run "$file"
echo "--- exit code $rc; stdout:"; cat "$out"
echo "--- stderr:"; cat "$err"
echo "---"

fail=0
if [ "$rc" -eq 124 ] || [ "$rc" -eq 137 ]; then
  echo "FAIL: the run did not finish within 60 s"; fail=1
elif [ "$rc" -eq 0 ]; then
  echo "FAIL: exit code 0 for a bad input"; fail=1
fi
if ! grep -qF -- "$expected" "$err"; then
  echo "FAIL: stderr does not contain: $expected"; fail=1
fi
runtime_errors
dups=$(grep -F 'dpmpm: input error' "$err" | sort | uniq -d)
if [ -n "$dups" ]; then
  echo "FAIL: input errors printed more than once:"; echo "$dups"; fail=1
fi
if [ "$fail" -eq 0 ]; then echo "PASS"; fi
exit $fail
