# Shared helpers for the command-line tests in tests/cli/*.sh. Sourced, not run: it lives
# outside the tests/cli/*.sh glob so that ctest does not register it as a test.
#
#   source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
#   cli_init "$@"            # PERI=<path to peri>, TMP=<private temp dir, removed on exit>
#   run_peri run DECK ...    # runs "$PERI" DECK..., keeps status, stdout and stderr
#   expect_status 2
#   expect_stderr_contains "did you mean 'density'"
#
# Every expect_* prints a "FAIL: <script>: <what>" line, the command and its output, and
# exits 1 at the first failure. pass prints an "ok" line for the log.

CLI_NAME=$(basename "${0:-cli}")
CLI_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
DECKS="$CLI_DIR/decks"
PERI=""
TMP=""
RUN_CMD=""
RUN_STATUS=""
RUN_STDOUT=""
RUN_STDERR=""

cli_cleanup() {
  if [[ -n "$TMP" && -d "$TMP" ]]; then rm -rf -- "$TMP"; fi
}

# cli_init PERI: checks the program and makes the temporary directory.
cli_init() {
  if [[ $# -lt 1 || -z "$1" ]]; then
    echo "usage: bash $CLI_NAME PATH_TO_PERI" >&2
    exit 2
  fi
  PERI=$1
  if [[ "$PERI" != /* ]]; then PERI="$(pwd)/$PERI"; fi
  if [[ ! -x "$PERI" ]]; then
    echo "FAIL: $CLI_NAME: '$PERI' is not an executable program" >&2
    exit 1
  fi
  TMP=$(mktemp -d "${TMPDIR:-/tmp}/peri-cli.XXXXXX") || {
    echo "FAIL: $CLI_NAME: cannot create a temporary directory" >&2
    exit 1
  }
  trap cli_cleanup EXIT
  # Threads that wait sleep instead of spinning: when ctest runs tests in parallel, or
  # a test asks for more threads than there are cores, spinning OpenMP threads take the
  # cores from the ones with work and a run can take many times longer. The results do
  # not depend on it. A value set by the caller is kept.
  export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}"
  RUN_STDOUT="$TMP/.stdout"
  RUN_STDERR="$TMP/.stderr"
}

# Shows the last command and what it printed (head of each stream).
show_last_run() {
  [[ -n "$RUN_CMD" ]] || return 0
  echo "  command: $RUN_CMD" >&2
  echo "  status:  $RUN_STATUS" >&2
  if [[ -s "$RUN_STDOUT" ]]; then
    echo "  stdout:" >&2
    head -n 20 "$RUN_STDOUT" | sed 's/^/    | /' >&2
  fi
  if [[ -s "$RUN_STDERR" ]]; then
    echo "  stderr:" >&2
    head -n 20 "$RUN_STDERR" | sed 's/^/    | /' >&2
  fi
}

fail() {
  echo "FAIL: $CLI_NAME: $*" >&2
  show_last_run
  exit 1
}

pass() { echo "ok: $*"; }

# run_peri ARGS...: runs the program under test, never stops the script on its status.
run_peri() {
  RUN_CMD="peri $*"
  "$PERI" "$@" >"$RUN_STDOUT" 2>"$RUN_STDERR" </dev/null
  RUN_STATUS=$?
  return 0
}

# run_peri_in DIR ARGS...: the same with DIR as the working directory, so that a default
# output directory (output/NAME, relative to the working directory) would land in DIR.
run_peri_in() {
  local dir=$1
  shift
  RUN_CMD="(cd $dir && peri $*)"
  (cd "$dir" && "$PERI" "$@") >"$RUN_STDOUT" 2>"$RUN_STDERR" </dev/null
  RUN_STATUS=$?
  return 0
}

expect_status() {
  [[ "$RUN_STATUS" == "$1" ]] || fail "expected exit status $1, got $RUN_STATUS"
}

expect_stdout_contains() {
  grep -qF -- "$1" "$RUN_STDOUT" || fail "stdout does not contain: $1"
}

expect_stderr_contains() {
  grep -qF -- "$1" "$RUN_STDERR" || fail "stderr does not contain: $1"
}

expect_stdout_matches() {
  grep -qE -- "$1" "$RUN_STDOUT" || fail "stdout does not match the regex: $1"
}

expect_stderr_matches() {
  grep -qE -- "$1" "$RUN_STDERR" || fail "stderr does not match the regex: $1"
}

expect_stderr_empty() {
  [[ ! -s "$RUN_STDERR" ]] || fail "expected nothing on stderr"
}

expect_stdout_empty() {
  [[ ! -s "$RUN_STDOUT" ]] || fail "expected nothing on stdout"
}

expect_file() {
  [[ -f "$1" ]] || fail "expected the file $1"
}

expect_nonempty_file() {
  [[ -s "$1" ]] || fail "expected a non-empty file $1"
}

expect_no_path() {
  [[ ! -e "$1" ]] || fail "expected no $1 (it exists: the program did work before the error)"
}

# locate PATTERN FILE: sets LOC_LINE and LOC_COL to the 1-based line and column where the
# fixed string PATTERN first occurs in FILE outside comment lines (fails the test when it
# does not: the fixture is broken). Used to compute the file:line:col an error must name.
LOC_LINE=""
LOC_COL=""
locate() {
  local found text prefix
  found=$(grep -nF -- "$1" "$2" | grep -vE '^[0-9]+:[[:space:]]*#' | head -n 1)
  [[ -n "$found" ]] || fail "fixture $2 has no line containing '$1'"
  LOC_LINE=${found%%:*}
  text=${found#*:}
  prefix=${text%%"$1"*}
  LOC_COL=$((${#prefix} + 1))
}

# csv_column FILE NAME: the 1-based index of column NAME in the header of FILE (empty when
# there is none).
csv_column() {
  head -n 1 "$1" | tr -d '\r' | tr ',' '\n' | grep -nxF -- "$2" | cut -d: -f1
}

# compare_histories A B [TOL]: same header, same number of rows, every value equal to a
# relative TOL (default 1e-12; |a - b| <= TOL * max(|a|, |b|); equal text is equal). Prints
# the first difference and returns 1 on a mismatch.
compare_histories() {
  awk -F, -v tol="${3:-1e-12}" -v fa="$1" -v fb="$2" '
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

# Ends the test as skipped (status 0, a SKIP line) when peri was built without HDF5: the
# deck with output.checkpoint_every is then refused, and checkpoints cannot be tested.
skip_without_checkpoints() {
  if ! "$PERI" check "$DECKS/restart_heat.yaml" >/dev/null 2>&1; then
    echo "SKIP: $CLI_NAME: peri was built without HDF5 (checkpoints need it: scripts/install-deps)"
    exit 0
  fi
}
