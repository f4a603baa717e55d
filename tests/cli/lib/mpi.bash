# Helpers for the MPI command-line tests (tests/cli/mpi_*.sh). Sourced after assert.bash:
#
#   mpi_init                  # SKIP (exit 0) when peri was built without MPI
#   run_peri_mpi N ARGS...    # mpirun -np N peri ARGS..., like run_peri
#   compare_histories A B     # every value equal to a relative MPI_TOL
#
# The runs may start as root (containers) and on more ranks than cores (--oversubscribe);
# each rank uses one OpenMP thread. These settings stay here, out of users' way.

MPI_TOL=1e-12

mpi_init() {
  if ! "$PERI" --help 2>/dev/null | grep -q 'this build has MPI'; then
    echo "SKIP: $CLI_NAME: peri was built without MPI (install libopenmpi-dev: scripts/install-deps)"
    exit 0
  fi
  command -v mpirun >/dev/null 2>&1 || fail "peri is built with MPI but mpirun is missing (scripts/install-deps)"
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  export OMP_NUM_THREADS=1
}

run_peri_mpi() {
  local np=$1
  shift
  RUN_CMD="mpirun -np $np peri $*"
  # waiting ranks yield the core: other tests (ctest -j) and ranks share few cores
  mpirun --oversubscribe --mca mpi_yield_when_idle 1 -np "$np" "$PERI" "$@" >"$RUN_STDOUT" 2>"$RUN_STDERR" </dev/null
  RUN_STATUS=$?
  return 0
}

# compare_histories A B: same header, same rows, every value equal to a relative MPI_TOL
# (|a - b| <= MPI_TOL * max(|a|, |b|); equal text is equal). Prints the first difference.
compare_histories() {
  awk -F, -v tol="$MPI_TOL" -v fa="$1" -v fb="$2" '
    function abs(v) { return v < 0 ? -v : v }
    NR == FNR { row[FNR] = $0; rows_a = FNR; next }
    {
      rows_b = FNR
      if (!(FNR in row)) { printf "%s has more lines than %s\n", fb, fa; bad = 1; exit }
      if (FNR == 1) {
        if ($0 != row[1]) { printf "headers differ:\n  %s\n  %s\n", row[1], $0; bad = 1; exit }
        ncol = split($0, names, ",")
        next
      }
      n = split(row[FNR], a, ",")
      if (n != NF || n != ncol) { printf "row %d: %d and %d columns (header: %d)\n", FNR, n, NF, ncol; bad = 1; exit }
      for (c = 1; c <= n; c++) {
        if (a[c] == $c) continue
        x = a[c] + 0; y = $c + 0
        scale = abs(x) > abs(y) ? abs(x) : abs(y)
        if (abs(x - y) > tol * scale) {
          printf "row %d, column %s: %s vs %s (relative difference %.3g > %g)\n",
                 FNR, names[c], a[c], $c, abs(x - y) / scale, tol
          bad = 1; exit
        }
      }
    }
    END {
      if (bad) exit 1
      if (rows_a != rows_b) { printf "%s has %d lines, %s has %d\n", fa, rows_a, fb, rows_b; exit 1 }
    }' "$1" "$2"
}

# broken_line: the "broken bonds N of M" line of the last run's summary.
broken_line() { grep -E '^  broken bonds ' "$RUN_STDOUT" | head -n 1; }

# mpi_same_on_ranks NAME DECK [ARGS...]: runs DECK on 1, 2, 3 and 4 ranks (or the counts in
# MPI_RANKS, 1 first); history.csv must
# agree to MPI_TOL and the count of broken bonds must be the same. Sets MPI_REF (the
# history of the 1-rank run) and MPI_BROKEN (its broken-bond line).
mpi_same_on_ranks() {
  local name=$1 deck=$2
  shift 2
  local np out diff_report
  MPI_REF=""
  MPI_BROKEN=""
  for np in ${MPI_RANKS:-1 2 3 4}; do
    out="$TMP/$name-np$np"
    run_peri_mpi "$np" run "$deck" --output "$out" "$@"
    expect_status 0
    expect_nonempty_file "$out/history.csv"
    if [[ $np -eq 1 ]]; then
      MPI_REF="$out/history.csv"
      MPI_BROKEN=$(broken_line)
      continue
    fi
    diff_report=$(compare_histories "$MPI_REF" "$out/history.csv") ||
      fail "$name: history.csv on 1 and $np ranks differ: $diff_report"
    [[ "$(broken_line)" == "$MPI_BROKEN" ]] ||
      fail "$name: '$MPI_BROKEN' on 1 rank, '$(broken_line)' on $np"
    expect_stdout_contains "MPI ranks    $np"
  done
}
