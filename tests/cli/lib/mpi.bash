# Helpers for the MPI command-line tests (tests/cli/mpi_*.sh). Sourced after assert.bash:
#
#   mpi_init                  # SKIP (exit 0) when peri was built without MPI
#   run_peri_mpi N ARGS...    # mpirun -np N peri ARGS..., like run_peri; fails the test when
#                             # it runs longer than MPI_TIMEOUT seconds (ranks that hang)
#   compare_histories A B "$MPI_TOL"  # (lib/assert.bash) every value equal to a relative MPI_TOL
#   compare_scaled A B TOL    # every value within TOL of the largest of its kind (solver tolerances)
#
# The runs may start as root (containers) and on more ranks than cores (--oversubscribe);
# each rank uses one OpenMP thread. These settings stay here, out of users' way.

MPI_TOL=1e-12
# a run that has not ended after this many seconds hangs (ranks waiting in different
# collectives): the test fails instead of waiting for ctest's limit
MPI_TIMEOUT=${MPI_TIMEOUT:-300}

mpi_init() {
  if ! "$PERI" --help 2>/dev/null | grep -q 'this build has MPI'; then
    echo "SKIP: $CLI_NAME: peri was built without MPI (install libopenmpi-dev: scripts/install-deps)"
    exit 0
  fi
  command -v mpirun >/dev/null 2>&1 || fail "peri is built with MPI but mpirun is missing (scripts/install-deps)"
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  export OMP_NUM_THREADS=1
  # every collective call is checked for agreement between the ranks (docs/parallel.md): a
  # branch taken differently on two ranks stops the run with a message instead of a hang
  export PERI_CHECK_COLLECTIVES=${PERI_CHECK_COLLECTIVES:-1}
}

run_peri_mpi() {
  local np=$1
  shift
  RUN_CMD="mpirun -np $np peri $*"
  # waiting ranks yield the core: other tests (ctest -j) and ranks share few cores
  timeout -k 10 "$MPI_TIMEOUT" mpirun --oversubscribe --mca mpi_yield_when_idle 1 -np "$np" "$PERI" "$@" \
    >"$RUN_STDOUT" 2>"$RUN_STDERR" </dev/null
  RUN_STATUS=$?
  if [[ $RUN_STATUS -eq 124 || $RUN_STATUS -eq 137 ]]; then
    fail "no end after $MPI_TIMEOUT s on $np ranks: the ranks hang (PERI_CHECK_COLLECTIVES=1 shows where they part)"
  fi
  return 0
}


# broken_line: the "broken bonds N of M" line of the last run's summary.
broken_line() { grep -E '^  broken bonds ' "$RUN_STDOUT" | head -n 1; }

# without_column FILE NAME: FILE (a CSV) without its column NAME, on stdout
without_column() {
  local k
  k=$(head -n 1 "$1" | tr -d '\r' | tr ',' '\n' | grep -nxF -- "$2" | cut -d: -f1)
  if [[ -z "$k" ]]; then cat "$1"; else cut -d, -f"$k" --complement "$1"; fi
}

# histories_within_tolerance A B: compare_histories A B "$MPI_TOL"; with MPI_TOL above
# 1e-12 (the solver-tolerance comparisons of implicit runs) without energy_balance: in an
# elastic quasi-static run it is U - W, a difference of two equal energies (~1e-12 of U),
# whose round-off has no relative precision; its terms are compared in their own columns.
histories_within_tolerance() {
  if [[ "$MPI_TOL" == 1e-12 ]]; then
    compare_histories "$1" "$2" "$MPI_TOL"
  else
    without_column "$1" energy_balance >"$TMP/.ref_wo.csv"
    without_column "$2" energy_balance >"$TMP/.cmp_wo.csv"
    compare_histories "$TMP/.ref_wo.csv" "$TMP/.cmp_wo.csv" "$MPI_TOL"
  fi
}

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
    diff_report=$(histories_within_tolerance "$MPI_REF" "$out/history.csv") ||
      fail "$name: history.csv on 1 and $np ranks differ: $diff_report"
    [[ "$(broken_line)" == "$MPI_BROKEN" ]] ||
      fail "$name: '$MPI_BROKEN' on 1 rank, '$(broken_line)' on $np"
    expect_stdout_contains "MPI ranks    $np"
  done
}

# compare_scaled A B TOL: same header and rows; |a - b| <= TOL * max(|a|, |b|, S), where S is
# the largest magnitude in A of the columns of the same kind (the name before its first "_":
# reaction, displacement, strain, ...). Prints the first difference and returns 1.
compare_scaled() {
  awk -F, -v tol="$3" -v fa="$1" -v fb="$2" '
    function abs(v) { return v < 0 ? -v : v }
    function kind(name) { sub(/_.*/, "", name); return name }
    NR == FNR {
      if (FNR == 1) { header = $0; ncol = split($0, names, ","); next }
      rows_a = FNR
      for (c = 1; c <= NF; c++) {
        a[FNR, c] = $c
        k = kind(names[c]); if (abs($c) > scale[k]) scale[k] = abs($c)
      }
      next
    }
    FNR == 1 { if ($0 != header) { printf "headers differ\n"; bad = 1; exit } next }
    {
      rows_b = FNR
      if (NF != ncol) { printf "row %d: %d columns, header %d\n", FNR, NF, ncol; bad = 1; exit }
      for (c = 1; c <= NF; c++) {
        x = a[FNR, c] + 0; y = $c + 0
        s = abs(x) > abs(y) ? abs(x) : abs(y)
        if (scale[kind(names[c])] > s) s = scale[kind(names[c])]
        if (abs(x - y) > tol * s) {
          printf "row %d, column %s: %s vs %s (difference %.3g of the largest %s value)\n",
                 FNR, names[c], a[FNR, c], $c, abs(x - y) / s, kind(names[c])
          bad = 1; exit
        }
      }
    }
    END {
      if (bad) exit 1
      if (rows_a != rows_b) { printf "%s has %d rows, %s has %d\n", fa, rows_a, fb, rows_b; exit 1 }
    }' "$1" "$2"
}
