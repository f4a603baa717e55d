#!/usr/bin/env bash
# A heat-conduction deck runs end to end: Bobaru & Duangpanya 2012 Example 3 (insulated crack) writes its
# series, history and temperature picture; the temperatures stay within the prescribed
# extremes -100 and +100 C (maximum principle of the heat equation). output.plot draws a
# history column of the heat run (the largest temperature against time) as a PNG, and a
# column that heat runs do not write is an error that lists the ones they do.
# Usage: bash tests/cli/heat_example.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

run_peri run examples/heat_example3.yaml --quiet --output "$TMP/out" \
  --set output.plot.x=time --set output.plot.y=max_temperature
expect_status 0
expect_nonempty_file "$TMP/out/heat_example3.pvd"
expect_nonempty_file "$TMP/out/temperature.png"
head -c 8 "$TMP/out/temperature.png" | od -An -tx1 | grep -q "89 50 4e 47" || fail "temperature.png is not a PNG"
history="$TMP/out/history.csv"
expect_nonempty_file "$history"
tmin=$(csv_column "$history" min_temperature)
tmax=$(csv_column "$history" max_temperature)
[[ -n "$tmin" && -n "$tmax" ]] || fail "history.csv lacks min_temperature/max_temperature"
awk -F, -v a="$tmin" -v b="$tmax" 'NR > 1 { if ($a < -100 - 1e-9 || $b > 100 + 1e-9) { print "line " NR ": " $a " " $b; bad = 1; exit } }
  END { exit bad }' "$history" || fail "temperature left [-100, 100] C"
pass "heat example 3 runs; temperatures obey the maximum principle"

expect_nonempty_file "$TMP/out/max_temperature_vs_time.png"
head -c 8 "$TMP/out/max_temperature_vs_time.png" | od -An -tx1 | grep -q "89 50 4e 47" ||
  fail "max_temperature_vs_time.png is not a PNG"
run_peri check examples/heat_example3.yaml --set output.plot.x=time --set output.plot.y=kinetic_energy
expect_status 2
expect_stderr_contains "history.csv has no column 'kinetic_energy' (columns: time, step, total_heat"
pass "output.plot of a heat run: the curve of max_temperature; an unknown column lists the heat columns"
echo "PASS: $CLI_NAME"
