# What check_bad_input.sh and check_input_accepted.sh share, read by both with `.`:
#   input_args <what the fifth argument is> "$@"
#     the five arguments <mpiexec> <dpmpm> <nranks> <file.nml> <fifth> into mpiexec, exe,
#     nranks, file and expected (else the usage, exit code 2); out and err, two files
#     removed at the exit.
#   input_run <dpmpm arguments...>
#     dpmpm on nranks ranks, stopped after 60 s: stdout in $out, stderr in $err, the exit
#     code in rc. One rank runs the binary itself, as a plain `dpmpm file.nml` does (MPI as
#     a singleton): Open MPI's mpiexec holds a single process that ends with an error code
#     for 2 s before it returns (0.36 s against 2.4 s a bad-input case).
#   runtime_errors
#     a FAIL line (and fail=1) for each sign of a Fortran runtime error in the output.
input_args() {
  usage=$1
  shift
  if [ $# -ne 5 ]; then
    echo "usage: $0 <mpiexec> <dpmpm> <nranks> <file.nml> <$usage>" >&2
    exit 2
  fi
  mpiexec=$1 exe=$2 nranks=$3 file=$4 expected=$5
  out=$(mktemp) err=$(mktemp)
  trap 'rm -f "$out" "$err"' EXIT
}

input_run() {
  if [ "$nranks" -eq 1 ]; then
    timeout 60 "$exe" "$@" >"$out" 2>"$err"
  else
    timeout 60 "$mpiexec" --oversubscribe -n "$nranks" "$exe" "$@" >"$out" 2>"$err"
  fi
  rc=$?
}

runtime_errors() {
  for bad in "Backtrace" "Error termination" "At line"; do
    if grep -qF -- "$bad" "$out" "$err"; then
      echo "FAIL: Fortran runtime error in the output ($bad)"; fail=1
    fi
  done
}
