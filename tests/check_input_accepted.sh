#!/bin/sh
# Run `dpmpm --check` on an input that is valid and check that it is accepted the way a user
# should see it:
#   check_input_accepted.sh <mpiexec> <dpmpm> <nranks> <file.nml> <expected-warning | ->
# Passes when the check ends within 60 s with exit code 0, there is no input error and no
# Fortran runtime error, and stderr holds the expected warning exactly once (printed by
# rank 0 only); with "-", when stderr holds no input warning at all.
set -u
. "$(dirname "$0")/input_run.sh"
input_args "expected-warning | -" "$@"
input_run --check "$file"
echo "--- exit code $rc; stderr:"; cat "$err"
echo "---"

fail=0
if [ "$rc" -ne 0 ]; then
  echo "FAIL: exit code $rc for a valid input"; fail=1
fi
if grep -qF -- "dpmpm: input error" "$err"; then
  echo "FAIL: an input error for a valid input"; fail=1
fi
runtime_errors
if [ "$expected" = "-" ]; then
  if grep -qF -- "dpmpm: input warning" "$err"; then
    echo "FAIL: a warning where none was expected"; fail=1
  fi
else
  n=$(grep -cF -- "$expected" "$err")
  if [ "$n" -ne 1 ]; then
    echo "FAIL: stderr holds the expected warning $n times, not once: $expected"; fail=1
  fi
  if ! grep -F -- "$expected" "$err" | grep -qF "dpmpm: input warning"; then
    echo "FAIL: the expected text is not on an input warning line"; fail=1
  fi
fi
if [ "$fail" -eq 0 ]; then echo "PASS"; fi
exit $fail
