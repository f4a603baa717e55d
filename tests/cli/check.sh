#!/usr/bin/env bash
# peri check: validates the deck, builds the discretization and prints the summary with
# the memory estimate, and runs nothing (no output directory).
# The LAMMPS examples/peri decks must give LAMMPS's own published counts: 3487 nodes and
# 335,966 directed bonds (docs/verification.md case 7).
# Usage: bash tests/cli/check.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

# check_deck DECK: "peri check DECK" from an empty working directory succeeds, prints the
# summary and writes nothing.
check_deck() {
  local deck=$1 work
  [[ -f "$deck" ]] || fail "run from the repository root ($deck not found)"
  work=$(mktemp -d "$TMP/run.XXXXXX")
  run_peri_in "$work" check "$(pwd)/$deck"
  expect_status 0
  expect_stdout_contains "$(pwd)/$deck"
  expect_stdout_matches "^  nodes +[0-9]+$"
  expect_stdout_matches "^  bonds +[0-9]+ directed"
  expect_stdout_matches "^  memory +[0-9]+(\.[0-9]+)? MB estimated"
  expect_stdout_matches "^  time step +[0-9.e+-]+ s \(stable estimate [0-9.e+-]+ s\), [0-9]+ steps"
  # check runs nothing: no progress, no "finished" line, no files
  if grep -qE "finished|broken bonds +[0-9]+ of" "$RUN_STDOUT"; then fail "check ran the solver"; fi
  [[ -z "$(ls -A "$work")" ]] || fail "check wrote into the working directory: $(ls -A "$work")"
}

for model in pmb lps; do
  deck=examples/lammps_peri_$model.yaml
  check_deck "$deck"
  expect_stdout_contains "nodes        3487"
  expect_stdout_contains "335966 directed"
  expect_stdout_matches "^  model +$model, 3D$"
  # before the run no bond is broken (the LAMMPS form starts with an unbounded s0)
  expect_stdout_contains "335966 directed (96.3 per node), 0 broken"
  # the deck's own 1e-7 s time step and 1000 steps
  expect_stdout_matches "^  time step +1e-07 s .*, 1000 steps"
  pass "check $deck: 3487 nodes, 335966 directed bonds, 1000 steps of 1e-7 s"
done

deck=examples/quickstart.yaml
check_deck "$deck"
expect_stdout_contains "nodes        36000"
expect_stdout_matches "^  model +pmb, 2D, plane stress$"
expect_stdout_matches "^  memory +[0-9.]+ MB estimated \([0-9.]+ bytes per directed bond, node blocks at most [0-9.]+ more\)"
# the memory estimate is positive and plausible for 36,000 nodes and ~1.3 M bonds
mb=$(sed -nE 's/^  memory +([0-9.]+) MB.*/\1/p' "$RUN_STDOUT")
awk -v mb="$mb" 'BEGIN { exit !(mb > 1 && mb < 1000) }' || fail "memory estimate $mb MB is not plausible"
pass "check $deck: summary with a memory line ($mb MB)"

# --quiet does not silence check: printing the summary is what check is for
run_peri check "$deck" --quiet
expect_status 0
expect_stdout_contains "nodes        36000"
pass "check --quiet still prints the summary"

# check ignores --output: nothing is written there
run_peri check "$deck" --output "$TMP/out"
expect_status 0
expect_no_path "$TMP/out"
pass "check --output DIR writes nothing"

echo "PASS: $CLI_NAME"
