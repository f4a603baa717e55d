#!/usr/bin/env bash
# The peer-parity keys (docs/models.md 3.5, 4.1, 5.1): materials.*.force_state,
# solver.breaking_order and discretization.surface_correction are refused with exit status 2
# where they do not apply, and accepted where they do.
# Usage: bash tests/cli/parity_keys.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"
D="$DECKS"

run_peri check "$D/valid_small.yaml" --set materials.glass.force_state=peer
expect_status 2
expect_stderr_contains "key 'force_state': only the lps model has a force state"
pass "force_state on a pmb material: exit 2"

run_peri check "$D/valid_small.yaml" --set solver.breaking_order=sideways
expect_status 2
expect_stderr_contains "breaking_order"
pass "an unknown breaking_order: exit 2"

run_peri check "$D/qs_bar.yaml" --set solver.breaking_order=after_force
expect_status 2
expect_stderr_contains "after_force is for the explicit solver only"
pass "breaking_order: after_force with a quasi-static solver: exit 2"

run_peri check "$D/valid_small.yaml" --set discretization.surface_correction=sideways
expect_status 2
expect_stderr_contains "surface_correction"
pass "an unknown surface_correction: exit 2"

run_peri check "$D/plate_lps.yaml" --set discretization.surface_correction=volume
expect_status 2
expect_stderr_contains "volume is for pmb"
pass "surface_correction: volume with lps: exit 2"

run_peri run "$D/valid_small.yaml" --quiet --output "$TMP/after" --set solver.breaking_order=after_force \
  --set discretization.surface_correction=energy
expect_status 0
expect_file "$TMP/after/history.csv"
pass "breaking_order: after_force and surface_correction: energy run"
