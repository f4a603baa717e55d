#!/usr/bin/env bash
# The switch of a quasi-static run to explicit dynamics (solver.dynamic_switch, docs/solvers.md
# section 4) from the command line, on the notched beam example coarsened to dx = 2.5 mm: the
# run reports its dynamic phases, history.csv has the phase and dynamic_time columns, the rows
# of a phase hold the load of their load step and carry kinetic energy, the static rows do
# not; bad dynamic_switch keys are errors at their position (exit 2).
# Usage: bash tests/cli/notched_beam_dynamic.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/beam.bash"
cli_init "$@"

deck=$BEAM_DECK
coarse=("${BEAM_COARSE[@]}"
  --set solver.load_steps=12 --set "boundary_conditions.2.y=-0.6e-3*t"
  --set solver.dynamic_switch.when_broken_exceeds=40 --set solver.dynamic_switch.history_every=50)

# --- a run through the peak load: dynamic phases, reported and in history.csv
out="$TMP/beam"
run_peri run "$deck" "${coarse[@]}" --output "$out"
expect_status 0
expect_stdout_matches "^  dynamics     above 40 bonds broken in a load step: explicit, time step [0-9.e+-]+ s, damping 20000 1/s"
expect_stdout_matches "^  dynamic      load step [0-9]+ \(t = [0-9.]+\): [0-9]+ steps \([0-9.e+-]+ s\), [0-9]+ bonds broken, arrested"
expect_stdout_matches "^  dynamic      [0-9]+ phases?, [0-9]+ explicit steps"
h="$out/history.csv"
expect_nonempty_file "$h"
for name in phase dynamic_time kinetic_energy time displacement_load_y; do
  [[ -n "$(csv_column "$h" "$name")" ]] || fail "history.csv has no column '$name': $(head -n 1 "$h")"
done
ph=$(csv_column "$h" phase)
dt=$(csv_column "$h" dynamic_time)
ke=$(csv_column "$h" kinetic_energy)
tc=$(csv_column "$h" time)
ud=$(csv_column "$h" displacement_load_y)
# every dynamic row: kinetic energy > 0, the time and the imposed displacement of the load
# step row that follows it (the load is held), dynamic_time not decreasing; static rows: no
# kinetic energy
report=$(awk -F, -v ph="$ph" -v dt="$dt" -v ke="$ke" -v tc="$tc" -v ud="$ud" '
  NR == 1 { next }
  {
    if ($dt + 0 < last_dt) { printf "row %d: dynamic_time decreases\n", NR; bad = 1; exit }
    last_dt = $dt + 0
    if ($ph == 1) {
      dyn++
      if (!($ke > 0)) { printf "row %d: a dynamic row without kinetic energy\n", NR; bad = 1; exit }
      if (pending && ($tc != pt || $ud != pu)) { printf "row %d: the load moved during the phase\n", NR; bad = 1; exit }
      pending = 1; pt = $tc; pu = $ud
    } else {
      if ($ke != 0) { printf "row %d: a static row with kinetic energy %s\n", NR, $ke; bad = 1; exit }
      if (pending && ($tc != pt || $ud != pu)) { printf "row %d: the phase did not hold the load of its step\n", NR; bad = 1; exit }
      pending = 0
    }
  }
  END { if (bad) exit 1; if (dyn < 1) { print "no row with phase 1"; exit 1 } print dyn }' "$h") ||
  fail "history.csv: $report"
pass "dynamic phases reported; $report history rows in dynamic phases hold the load of their step"

# --- bad keys: positions, suggestions, exit 2 before any work
locate "damping: 2.0e4" "$deck"
run_peri check "$deck" --set solver.breaking=false
expect_status 2
expect_stderr_contains "$deck:$LOC_LINE:$LOC_COL: error: solver.dynamic_switch: needs bonds that break"
run_peri check "$deck" --set solver.dynamic_switch.dampng=1
expect_status 2
expect_stderr_contains "unknown key 'dampng' in solver.dynamic_switch; did you mean 'damping'?"
run_peri check "$deck" --set solver.dynamic_switch.damping=-1
expect_status 2
expect_stderr_contains "--set:1:31: error: key 'damping': must be >= 0 (1/s)"
run_peri check "$deck" --set solver.dynamic_switch.arrest_kinetic_energy=2
expect_status 2
expect_stderr_contains "key 'arrest_kinetic_energy': must be in (0, 1)"
run_peri check "$deck" --set solver.dynamic_switch.max_dynamic_steps=0
expect_status 2
expect_stderr_contains "key 'max_dynamic_steps': must be >= 1"
run_peri check "$deck" --set solver.max_broken_per_step=0
expect_status 2
expect_stderr_contains "$deck:$LOC_LINE:$LOC_COL: error: solver.dynamic_switch: give 'when_broken_exceeds'"
run_peri check "$deck" --set "solver.dynamic_switch=[1, 2]"
expect_status 2
run_peri check "$deck" --set solver.dynamic_switch.time_step=1e-7
expect_status 0
expect_stdout_contains "explicit, time step 1e-07 s"
pass "dynamic_switch keys are checked with positions"

# the columns of the switch can be plotted, and only when the switch is on
run_peri check "$deck" --set output.plot.x=dynamic_time --set output.plot.y=phase
expect_status 0
run_peri check examples/plate_with_hole.yaml --set output.plot.x=dynamic_time --set output.plot.y=time
expect_status 2
expect_stderr_contains "history.csv has no column 'dynamic_time'"
pass "output.plot takes phase and dynamic_time with a dynamic switch"

echo "PASS: $CLI_NAME"
