#!/usr/bin/env bash
# The outputs for ParaView and for scripts (docs/output.md), on a coarse, short fragmenting
# cylinder (3D, LPS, bonds breaking from the first steps):
# - output.format both: the Exodus II file opens with Python's netCDF4 and holds the node
#   variables of output.fields by component, one SPHERE element of volume dx^3 per node, the
#   node count of `peri check`, one time step per frame at the times of the .pvd and of the
#   frames' TimeValue, the frames' reference positions as coordinates and their displacement
#   and damage (same numbers, in node_id order), and the history.csv row of each frame's time
#   as global variables;
# - every VTU frame holds node_id (1..N), reference_position (= Points - displacement to
#   round-off) and the FieldData TimeValue (= the .pvd time);
# - history_units.csv repeats the header of history.csv with a unit for every column, of a
#   run with reaction columns too;
# - the 3D run draws its picture: a slice normal to z (the default) of the width the deck
#   asks for, and a projection along x of the tube (twice as tall as wide) taller than it;
# - on 2 ranks, the Exodus file (gathered to rank 0) holds the numbers of the run on one, and
#   the VTU pieces the same node ids and reference positions;
# - a run restarted from a checkpoint continues the Exodus file: the same file as the run
#   without interruption;
# - bad keys: an unknown format and a 3D view on a 2D picture are input errors (exit 2).
# A build without the Exodus library refuses format: exodus with exit status 2 and a message
# naming the library; then only that and the VTU checks run.
# Usage: bash tests/cli/output_formats.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

PY=""
for candidate in /usr/bin/python3 python3; do
  if command -v "$candidate" >/dev/null && "$candidate" -c 'import numpy, netCDF4' 2>/dev/null; then
    PY=$candidate
    break
  fi
done
if [[ -z "$PY" ]]; then
  echo "SKIP: $CLI_NAME: no python3 with numpy and netCDF4 (Debian python3-numpy, python3-netcdf4: scripts/install-deps)"
  exit 0
fi
check() { "$PY" "$CLI_DIR/lib/check_outputs.py" "$@" || fail "check_outputs.py $*"; }

deck=examples/fragmenting_cylinder.yaml
dx=4e-3
small=(--set discretization.spacing=$dx --set solver.end_time=12e-6 --set output.frames=4 --quiet)
nodes=$("$PERI" check "$deck" --set discretization.spacing=$dx | sed -nE 's/^  nodes +([0-9]+).*/\1/p')
[[ -n "$nodes" ]] || fail "cannot read the node count from peri check"

# bad keys first
run_peri check "$deck" --set output.format=exodsu
expect_status 2
expect_stderr_contains "did you mean 'exodus'"
run_peri check "$DECKS/plate_pmb.yaml" --set "output.picture={field: damage, view: projection}"
expect_status 2
expect_stderr_contains "only 3D pictures have a view"
run_peri check "$deck" --set output.picture.view=projection --set output.picture.at=0.05
expect_status 2
expect_stderr_contains "'at' places a slice"
pass "an unknown format, a view of a 2D picture and 'at' with a projection are refused with exit status 2"

run_peri check "$deck" --set output.format=exodus
if [[ $RUN_STATUS -ne 0 ]] && grep -q "built without the Exodus II library" "$RUN_STDERR"; then
  expect_status 2
  run_peri run "$deck" "${small[@]}" --output "$TMP/vtu"
  expect_status 0
  check vtu "$TMP/vtu" fragmenting_cylinder "$nodes"
  pass "built without Exodus II: format exodus is refused with exit status 2; VTU frames checked"
  echo "PASS: $CLI_NAME"
  exit 0
fi
expect_status 0

# --- one process, both formats
out="$TMP/both"
run_peri run "$deck" "${small[@]}" --set output.format=both --set output.picture.width=600 --output "$out"
expect_status 0
check vtu "$out" fragmenting_cylinder "$nodes"
check exodus "$out" fragmenting_cylinder "$nodes" "$dx"
check units "$out"
pass "Exodus file, VTU frames and units of the fragmenting cylinder ($nodes nodes)"

# --- the 3D pictures: PNG width and height from the IHDR chunk
png_size() {
  [[ "$(head -c 16 "$1" | tail -c 4)" == "IHDR" ]] || fail "$1 is not a PNG"
  echo "$((16#$(head -c 20 "$1" | tail -c 4 | od -An -tx1 | tr -d ' \n'))) $((16#$(head -c 24 "$1" | tail -c 4 | od -An -tx1 | tr -d ' \n')))"
}
read -r w_z h_z < <(png_size "$out/damage.png")
[[ $w_z -eq 600 ]] || fail "the slice picture is $w_z px wide, the deck asks for 600"
run_peri run "$deck" "${small[@]}" --set output.picture.width=600 --set output.picture.view=projection \
  --set output.picture.normal=x --output "$TMP/side"
expect_status 0
read -r w_x h_x < <(png_size "$TMP/side/damage.png")
[[ $w_x -eq 600 ]] || fail "the projection is $w_x px wide, the deck asks for 600"
# the tube seen along x is 0.1 m tall and 0.05 m wide, its cross-section 0.05 m square: the
# plot area of the side view is about twice as tall (the labels and colour bar add the same)
(( h_x > h_z + 300 )) || fail "the side view ($w_x x $h_x) is not taller than the slice ($w_z x $h_z) by about a plot width"
pass "3D pictures: a z slice of $w_z x $h_z px and an x projection of $w_x x $h_x px"

# --- a run with reaction columns: their units
run_peri run "$DECKS/plate_pmb.yaml" --quiet --set solver.steps=20 --output "$TMP/plate"
expect_status 0
check units "$TMP/plate"
check vtu "$TMP/plate" plate_pmb "$("$PERI" check "$DECKS/plate_pmb.yaml" | sed -nE 's/^  nodes +([0-9]+).*/\1/p')"
pass "history_units.csv of a 2D run with reactions"

# --- two ranks: the Exodus file gathered on rank 0 is that of one process
if "$PERI" --help 2>/dev/null | grep -q 'this build has MPI'; then
  source "$CLI_DIR/lib/mpi.bash"
  mpi_init
  run_peri_mpi 2 run "$deck" "${small[@]}" --set output.format=both --set output.picture=false --output "$TMP/mpi"
  expect_status 0
  check same_exodus "$out/fragmenting_cylinder.e" "$TMP/mpi/fragmenting_cylinder.e" "$MPI_TOL"
  check vtu "$TMP/mpi" fragmenting_cylinder "$nodes"
  ls "$TMP"/mpi/*_0.vtu "$TMP"/mpi/*_1.vtu >/dev/null 2>&1 || fail "the 2-rank run wrote no piece per rank"
  pass "2 ranks: the same Exodus file as one process, VTU pieces with node_id and reference_position"
fi

# --- restart: the continued Exodus file is that of the run without interruption
if "$PERI" check "$DECKS/restart_heat.yaml" >/dev/null 2>&1; then
  ck=(--set output.checkpoint_every=10 --set 'output.checkpoint_file=ck_{step}.h5' --set output.format=exodus
      --set output.picture=false)
  run_peri run "$deck" "${small[@]}" "${ck[@]}" --output "$TMP/full"
  expect_status 0
  cp -r "$TMP/full" "$TMP/part"
  # what a run killed after step 10 would have left: a longer file than the checkpoint's frames
  run_peri run "$deck" "${small[@]}" "${ck[@]}" --output "$TMP/part" --restart "$TMP/part/ck_000010.h5"
  expect_status 0
  check same_exodus "$TMP/full/fragmenting_cylinder.e" "$TMP/part/fragmenting_cylinder.e" 0
  expect_no_path "$TMP/part/fragmenting_cylinder.e.restart"
  pass "restart from step 10: the same Exodus file as the run without interruption"
fi
echo "PASS: $CLI_NAME"
