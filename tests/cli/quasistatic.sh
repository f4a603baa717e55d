#!/usr/bin/env bash
# Quasi-static solvers from the command line (docs/solvers.md): a run with fracture writes
# the reaction-displacement history and its plot and the stress fields; a solve that does not
# converge exits 1 with a message and keeps its output; --set overrides carry positions and
# suggestions; peri sweep tabulates quantities; solver keys are checked against the type.
# Usage: bash tests/cli/quasistatic.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"
deck="$DECKS/qs_bar.yaml"

# --- a run to complete failure: history with reaction and imposed displacement, a plot
out="$TMP/bar"
run_peri run "$deck" --output "$out"
expect_status 0
expect_stdout_contains "solver       nlcg (quasi-static), 40 load steps"
expect_stdout_matches "^  finished +40 load steps"
expect_stdout_matches "^  max von Mises steel: "
expect_nonempty_file "$out/history.csv"
expect_nonempty_file "$out/reaction_pulled_x_vs_displacement_pulled_x.png"
r=$(csv_column "$out/history.csv" reaction_pulled_x)
u=$(csv_column "$out/history.csv" displacement_pulled_x)
[[ -n "$r" && -n "$u" ]] || fail "history.csv lacks reaction_pulled_x or displacement_pulled_x: $(head -n 1 "$out/history.csv")"
# 41 rows (t = 0 and 40 load steps); the peak is E A s0 = 2 MN within 2%, the end is ~0
[[ $(($(wc -l <"$out/history.csv") - 1)) -eq 41 ]] || fail "history.csv: expected 41 rows"
peak=$(awk -F, -v c="$r" 'NR > 1 && $c > m { m = $c } END { print m }' "$out/history.csv")
last=$(tail -n 1 "$out/history.csv" | cut -d, -f"$r")
awk -v p="$peak" -v l="$last" 'BEGIN { exit !(p > 1.96e6 && p < 2.04e6 && l < 1 && l > -1) }' ||
  fail "peak reaction $peak N (expected 2e6 within 2%), final $last N (expected 0)"
vtu=$(ls "$out"/qs_bar_*.vtu | tail -n 1)
for f in stress von_mises strain principal_stress; do
  grep -q "Name=\"$f\"" "$vtu" || fail "$vtu has no field $f"
done
grep -q 'Name="stress" NumberOfComponents="9"' "$vtu" || fail "$vtu: stress is not a 9-component tensor"
pass "run to failure: peak $peak N, final $last N, plot and stress fields written"

# --- not converged: exit 1, a message, the output so far kept
out="$TMP/stuck"
run_peri run "$deck" --quiet --output "$out" --set solver.max_iterations=3
expect_status 1
expect_stderr_contains "nlcg: not converged at load step 1"
expect_stderr_contains "raise solver.max_iterations"
expect_nonempty_file "$out/history.csv"
pass "a solve that does not converge exits 1 and keeps history.csv"

# --- overrides: positions and suggestions, exit 2 before any work
run_peri check "$deck" --set discretization.spcing=0.02
expect_status 2
expect_stderr_contains "--set:1:16: error: unknown key 'spcing' in discretization; did you mean 'spacing'?"
run_peri check "$deck" --set solver.type=nlcg --set materials.stel.density=1
expect_status 2
expect_stderr_contains "--set:2:11: error: unknown material 'stel'; did you mean 'steel'?"
run_peri check "$deck" --set solver.stiffness_factor=4
expect_status 2
expect_stderr_contains "key 'stiffness_factor': only for solver type adr"
run_peri check "$deck" --set solver.load_steps=0
expect_status 2
expect_stderr_contains "--set:1:19: error: key 'load_steps': must be >= 1"
run_peri check "$deck" --set discretization.m=abc
expect_status 2
expect_stderr_contains "key 'm': expected a number, got 'abc'"
run_peri check "$deck" --set "discretization.spacing=0.02" --set solver.type=adr
expect_status 0
expect_stdout_contains "spacing 0.02"
expect_stdout_contains "solver       adr (quasi-static)"
run_peri check "$deck" --set "solver.type=explicit" --set solver.steps=10 --set solver.load_steps=4
expect_status 2
expect_stderr_contains "key 'load_steps': only for solver type adr, dynamic_relaxation or nlcg"
pass "--set: positions, suggestions, type checks"

# --- sweep: one row per value, the quantities as columns
run_peri sweep "$deck" --set solver.load_steps=1 --set "boundary_conditions.1.x=1.0e-4*t" \
  --set-list discretization.spacing=0.02,0.01 --quantity "displacement_x@0.5" --quantity nodes
expect_status 0
expect_stdout_contains "| discretization.spacing | displacement_x@0.5 | nodes | seconds |"
# u = 1e-4 x at the nearest node (x = 0.49 and 0.495), within the 0.5% end effect
expect_stdout_matches "^\| 0.02 \| 4\.9[0-9]*e-05 \| 50 \|"
expect_stdout_matches "^\| 0.01 \| 4\.9[0-9]*e-05 \| 100 \|"
run_peri sweep "$deck" --set-list discretization.spacing=0.02 --quantity nonsense
expect_status 2
expect_stderr_contains "unknown quantity 'nonsense'"
pass "sweep tabulates one row per value"

echo "PASS: $CLI_NAME"
