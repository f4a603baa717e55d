#!/usr/bin/env bash
# Checkpoint and restart (docs/restart.md). For each deck, a run without interruption
# writes a checkpoint every k steps; a copy of its output directory is cut back to what an
# interrupted run would have left a few steps after one checkpoint (later frames and
# checkpoints gone, extra history rows after the checkpoint), and `peri run --restart`
# continues from that checkpoint. The continued run must give the same bytes as the run
# without interruption: history.csv, the .pvd, every VTU frame and the final checkpoint
# (whose displacements are also compared with h5dump). Decks: a 2D PMB plate with a
# pre-crack whose crack keeps growing after the checkpoint, its LPS twin, the PMB plate with
# the compression-dependent critical stretch (per-node s0 carried over), the PMB plate with
# sublayer plasticity (the plastic stretches of every bond carried over), a heat deck with
# a growing crack, a two-way thermomechanical quench, and a 1D quasi-static bar restarted
# before it breaks through in a dynamic phase, a punch under load control (explicit) and a plane
# under load slid with friction (adr), and a projectile striking a target through short-range
# forces. Then a truncated or damaged checkpoint, one
# of another discretization, one of another model and one beyond the deck's end are refused
# with exit status 2 before anything is written (a missing file and one that is not HDF5:
# tests/unit/test_checkpoint.c).
# Usage: bash tests/cli/restart.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

# A build without HDF5 refuses checkpoints with a clear message (exit 2), and that is all.
run_peri check "$DECKS/restart_heat.yaml"
if [[ $RUN_STATUS -ne 0 ]] && grep -q "built without HDF5" "$RUN_STDERR"; then
  expect_status 2
  run_peri run "$DECKS/plate_pmb.yaml" --quiet --output "$TMP/none" --restart "$TMP/none.h5"
  expect_status 2
  expect_stderr_contains "built without HDF5"
  expect_no_path "$TMP/none"
  pass "built without HDF5: checkpoint keys and --restart are refused with exit status 2"
  echo "PASS: $CLI_NAME"
  exit 0
fi
expect_status 0
command -v h5dump >/dev/null || fail "h5dump is needed (Debian package hdf5-tools, see scripts/install-deps)"

# h5_attr FILE PATH: an integer attribute of the checkpoint, e.g. /state/frames.
h5_attr() {
  h5dump -a "$2" "$1" | sed -nE 's/^ *\(0\): *(-?[0-9]+).*/\1/p' | head -n 1
}

# h5_data FILE DATASET: the values of a dataset as text (h5dump prints all 17 digits).
h5_data() {
  h5dump -m %.17g -d "$2" "$1" | sed -n '/DATA {/,/}/p'
}

# csv_value FILE ROW NAME: column NAME of data row ROW (0-based) of a history.csv.
csv_value() {
  local col
  col=$(csv_column "$1" "$3")
  [[ -n "$col" ]] || fail "$1 has no column $3"
  sed -n "$(($2 + 2))p" "$1" | cut -d, -f"$col"
}

# restart_case NAME DECK K LAST COLUMN [--set ...]: the run without interruption, checkpoints
# at K and LAST (the last step); the restart from K; COLUMN of history.csv must grow after K
# (the state keeps changing after the restart, e.g. bonds keep breaking).
restart_case() {
  local name=$1 deck=$2 k=$3 last=$4 column=$5
  shift 5
  local full="$TMP/$name/full" part="$TMP/$name/part"
  local ck fin
  ck=$(printf 'checkpoint_%06d.h5' "$k")
  fin=$(printf 'checkpoint_%06d.h5' "$last")
  run_peri run "$deck" --quiet --output "$full" "$@"
  expect_status 0
  expect_nonempty_file "$full/$ck"
  expect_nonempty_file "$full/$fin"
  [[ -z "$(find "$full" -name '*.tmp')" ]] || fail "$name: a temporary checkpoint was left in $full"

  # what an interrupted run leaves: the frames and rows written up to step K (from the
  # checkpoint's record), five rows more, and no later frames or checkpoints
  local frames rows
  frames=$(h5_attr "$full/$ck" /state/frames)
  rows=$(h5_attr "$full/$ck" /state/history_rows)
  [[ "$frames" =~ ^[0-9]+$ && "$rows" =~ ^[0-9]+$ ]] || fail "$name: cannot read /state/frames and history_rows of $ck"
  [[ "$(csv_value "$full/history.csv" $((rows - 1)) step)" == "$k" ]] ||
    fail "$name: the checkpoint at step $k records $rows history rows, but row $rows is not step $k"
  mkdir -p "$part"
  cp "$full"/*.pvd "$full/$ck" "$part/"
  head -n $((rows + 6)) "$full/history.csv" >"$part/history.csv"
  local f index
  for f in "$full"/*.vtu; do
    index=$(basename "$f" .vtu)
    index=$((10#${index##*_}))
    if ((index < frames)); then cp "$f" "$part/"; fi
  done

  run_peri run "$deck" --quiet --output "$part" --restart "$part/$ck" "$@"
  expect_status 0
  cmp -s "$full/history.csv" "$part/history.csv" ||
    fail "$name: history.csv after the restart differs from the run without interruption: $(cmp "$full/history.csv" "$part/history.csv")"
  for f in "$full"/*.pvd "$full"/*.vtu "$full/$fin"; do
    [[ -f "$part/$(basename "$f")" ]] || fail "$name: the restarted run did not write $(basename "$f")"
    cmp -s "$f" "$part/$(basename "$f")" || fail "$name: $(basename "$f") differs after the restart"
  done
  [[ "$(h5_data "$full/$fin" /nodes/u)" == "$(h5_data "$part/$fin" /nodes/u)" ]] ||
    fail "$name: final displacements differ"
  [[ -n "$(h5_data "$part/$fin" /nodes/u)" ]] || fail "$name: h5dump printed no displacements"
  local before after
  before=$(csv_value "$full/history.csv" $((rows - 1)) "$column")
  after=$(tail -n 1 "$full/history.csv" | cut -d, -f"$(csv_column "$full/history.csv" "$column")")
  awk -v a="$before" -v b="$after" 'BEGIN { exit !(b > a) }' ||
    fail "$name: $column does not grow after step $k ($before, then $after): the restart tests nothing"
  pass "$name: restarted at step $k, history.csv, .pvd, $(ls "$full"/*.vtu | wc -l) frames and the final checkpoint are bitwise equal ($column $before -> $after)"
}

every=(--set output.checkpoint_every=50 --set 'output.checkpoint_file=checkpoint_{step}.h5')
restart_case pmb "$DECKS/plate_pmb.yaml" 100 200 broken_bond_fraction "${every[@]}"
restart_case lps "$DECKS/plate_lps.yaml" 150 200 broken_bond_fraction "${every[@]}"
restart_case compression_s0 "$DECKS/plate_pmb.yaml" 100 200 broken_bond_fraction "${every[@]}" \
  --set 'materials.glass={model: pmb, density: 2440, youngs_modulus: 72.0e9, critical_stretch: {s00: 0.00016, alpha: 0.25}}'
# sublayer plasticity (docs/plasticity.md): the plastic state of every bond is carried over
restart_case plastic "$DECKS/plate_pmb.yaml" 100 200 mean_yield_index "${every[@]}" \
  --set 'materials.glass={model: pmb, density: 2440, youngs_modulus: 72.0e9, fracture_energy: 3.8, plasticity: {weights: [0.9, 0.1], yield_stretches: [5.0e-5, 2.0e-4]}}'
# the deviatoric yield rule (docs/plasticity.md section 8): each node's plastic deviatoric
# stretches of its bonds carried over, the 3D block restarted while it yields through
restart_case deviatoric "$DECKS/plastic_block3d.yaml" 50 400 mean_yield_index "${every[@]}"
# the tensor yield rule (section 10): each node's plastic tensors carried over
restart_case tensor "$DECKS/plastic_block3d.yaml" 50 400 mean_yield_index "${every[@]}" \
  --set materials.steel.plasticity.yield_rule=deviatoric_tensor
restart_case heat "$DECKS/restart_heat.yaml" 20 60 broken_bond_fraction
restart_case thermal_shock "$DECKS/restart_thermal_shock.yaml" 240 512 broken_bond_fraction
# the bar breaks through at load step 21 in a dynamic phase (solver.dynamic_switch), whose
# history rows carry step 21 too; the restart from load step 14 runs through it
restart_case quasi_static "$DECKS/qs_bar.yaml" 14 40 broken_bond_fraction \
  --set output.checkpoint_every=7 --set 'output.checkpoint_file=checkpoint_{step}.h5' \
  --set 'solver.dynamic_switch={when_broken_exceeds: 10, damping: 1.0e5, history_every: 5}'
# rigid tools (docs/contact.md): the punch's load-controlled offset, its rate and the contact
# force its next step reads (explicit), and the load search's compliance and the distance slid
# by a plane under load with friction (adr), carried over
restart_case tools_explicit "$DECKS/tool_load_control.yaml" 200 548 tool_punch_normal_force \
  --set output.checkpoint_every=100 --set 'output.checkpoint_file=checkpoint_{step}.h5'
restart_case tools_quasi_static "$DECKS/tool_load_sliding.yaml" 2 4 tool_slider_sliding_distance \
  --set output.checkpoint_every=1 --set 'output.checkpoint_file=checkpoint_{step}.h5'
# short-range forces between two bodies (docs/contact.md): a projectile restarted while it
# strikes the target (the pair list is rebuilt from the positions)
restart_case short_range "$DECKS/projectile_penetration.yaml" 270 833 momentum_target_x \
  --set output.checkpoint_every=270 --set 'output.checkpoint_file=checkpoint_{step}.h5'
sed '/^tools:/,/^solver:/{/^solver:/!d}' "$DECKS/tool_load_control.yaml" >"$TMP/no_tools.yaml"
run_peri run "$TMP/no_tools.yaml" --quiet --output "$TMP/e7" --restart "$TMP/tools_explicit/full/checkpoint_000200.h5"
expect_status 2
expect_stderr_contains "it has the state of rigid tools, but the deck has no tools"
expect_no_path "$TMP/e7"
pass "a checkpoint with tools for the deck without them: exit 2"

# Refused checkpoints: exit 2, a message naming the file, and no output written.
ck="$TMP/pmb/full/checkpoint_000100.h5"
head -c 4000 "$ck" >"$TMP/truncated.h5"
run_peri run "$DECKS/plate_pmb.yaml" --quiet --output "$TMP/e1" --restart "$TMP/truncated.h5"
expect_status 2
expect_stderr_contains "checkpoint '$TMP/truncated.h5'"
expect_no_path "$TMP/e1"
pass "a truncated checkpoint: exit 2"

# one flipped byte in the middle of the file, among the node arrays: their checksums catch it
cp "$ck" "$TMP/flipped.h5"
printf '\x5a' | dd of="$TMP/flipped.h5" bs=1 seek=$(($(stat -c %s "$ck") / 2)) conv=notrunc status=none
cmp -s "$ck" "$TMP/flipped.h5" && fail "the byte flip did not change the file"
run_peri run "$DECKS/plate_pmb.yaml" --quiet --output "$TMP/e2" --restart "$TMP/flipped.h5"
expect_status 2
expect_stderr_contains "damaged"
expect_no_path "$TMP/e2"
pass "a checkpoint with a flipped byte: exit 2, 'damaged'"

run_peri run "$DECKS/plate_pmb.yaml" --quiet --output "$TMP/e4" --restart "$ck" --set discretization.spacing=1.2e-3
expect_status 2
expect_stderr_contains "has 1440 nodes, deck builds 1000"
expect_no_path "$TMP/e4"
pass "a checkpoint of another discretization: exit 2, 'has 1440 nodes, deck builds 1000'"

run_peri run "$DECKS/plate_lps.yaml" --quiet --output "$TMP/e5" --restart "$ck"
expect_status 2
expect_stderr_contains "model pmb, the deck uses lps"
expect_no_path "$TMP/e5"
pass "a checkpoint of another model: exit 2"

run_peri run "$DECKS/plate_pmb.yaml" --quiet --output "$TMP/e6" --restart "$ck" --set solver.steps=60
expect_status 2
expect_stderr_contains "at step 100, beyond the deck's last step 60"
expect_no_path "$TMP/e6"
pass "a checkpoint beyond the deck's last step: exit 2"

run_peri check "$DECKS/plate_pmb.yaml" --restart "$ck"
expect_status 2
expect_stderr_contains "only for peri run"
pass "check --restart: exit 2"

echo "PASS: $CLI_NAME"
