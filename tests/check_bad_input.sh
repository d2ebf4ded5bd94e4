#!/bin/sh
# Run dpmpm on a bad input file and check that it fails the way a user should see it:
#   check_bad_input.sh <mpiexec> <dpmpm> <nranks> <file.nml> <expected-substring>
# Passes when the run ends within 60 s with a non-zero exit code, stderr contains the
# expected text, every input error line appears once (printed by rank 0 only), and there
# is no Fortran runtime error (traceback, "Error termination", "At line").
set -u
if [ $# -ne 5 ]; then
  echo "usage: $0 <mpiexec> <dpmpm> <nranks> <file.nml> <expected-substring>" >&2
  exit 2
fi
mpiexec=$1 exe=$2 nranks=$3 file=$4 expected=$5
out=$(mktemp) err=$(mktemp)
trap 'rm -f "$out" "$err"' EXIT

# One rank runs the binary itself, as a plain `dpmpm file.nml` does (MPI as a singleton):
# Open MPI's mpiexec holds a single process that ends with an error code for 2 s before it
# returns (0.36 s against 2.4 s a case, half the input tests' time).
if [ "$nranks" -eq 1 ]; then
  timeout 60 "$exe" "$file" >"$out" 2>"$err"
else
  timeout 60 "$mpiexec" --oversubscribe -n "$nranks" "$exe" "$file" >"$out" 2>"$err"
fi
rc=$?
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
for bad in "Backtrace" "Error termination" "At line"; do
  if grep -qF -- "$bad" "$out" "$err"; then
    echo "FAIL: Fortran runtime error in the output ($bad)"; fail=1
  fi
done
dups=$(grep -F 'dpmpm: input error' "$err" | sort | uniq -d)
if [ -n "$dups" ]; then
  echo "FAIL: input errors printed more than once:"; echo "$dups"; fail=1
fi
if [ "$fail" -eq 0 ]; then echo "PASS"; fi
exit $fail
