#!/usr/bin/env bash
# Checkpoints and restarts on MPI ranks (docs/restart.md, "MPI ranks"). A checkpoint holds
# every node and bond in the global order, whatever the number of ranks that wrote it, so:
#   - the 2D PMB fracture plate (bonds break before and after the checkpoint) written on 2
#     ranks gives the same checkpoint file, byte for byte, as on 1 rank;
#   - restarted from its mid checkpoint on 2 ranks it continues bit for bit: history.csv, the
#     .pvd, the frames and the final checkpoint equal those of the run without interruption;
#   - restarted on 1 and on 3 ranks it gives the uninterrupted history to a relative 1e-12
#     and the same number of broken bonds;
#   - the LPS plate (3 ranks -> 2), a heat deck with a growing crack (3 ranks -> 2; the
#     growing-crack position is split between the ranks) and a one-way coupled thermal
#     shock (2 ranks -> 3; conduction keeps its own cut flags) likewise to 1e-12;
#   - the quasi-static bar pulled to failure through a dynamic phase (2 ranks -> 3) likewise;
#   - a checkpoint of another deck is refused on 2 ranks with exit status 2, one message and
#     no output.
# Skipped when peri was built without MPI or without HDF5.
# Usage: bash tests/cli/mpi_restart.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init
skip_without_checkpoints
command -v h5dump >/dev/null || fail "h5dump is needed (Debian package hdf5-tools, see scripts/install-deps)"

every=(--set output.checkpoint_every=50 --set 'output.checkpoint_file=checkpoint_{step}.h5')

# h5_attr FILE PATH: an integer attribute of a checkpoint, e.g. /state/history_rows.
h5_attr() {
  h5dump -a "$2" "$1" | sed -nE 's/^ *\(0\): *(-?[0-9]+).*/\1/p' | head -n 1
}

# column_at FILE STEP NAME: column NAME of the last history.csv row of step STEP.
column_at() {
  local col
  col=$(csv_column "$1" "$3")
  [[ -n "$col" ]] || fail "$1 has no column $3"
  awk -F, -v c="$col" -v s="$2" -v sc="$(csv_column "$1" step)" 'NR > 1 && $sc == s { v = $c } END { print v }' "$1"
}

# interrupted FULL CHECKPOINT PART: what a run interrupted a few steps after CHECKPOINT
# leaves in PART: the .pvd, the frames written by then (.pvtu and pieces, or .vtu), the
# history rows written by then and three more, and the checkpoint.
interrupted() {
  local full=$1 ck=$2 part=$3 f index frames rows
  frames=$(h5_attr "$full/$ck" /state/frames)
  rows=$(h5_attr "$full/$ck" /state/history_rows)
  [[ "$frames" =~ ^[0-9]+$ && "$rows" =~ ^[0-9]+$ ]] || fail "cannot read /state/frames and history_rows of $full/$ck"
  mkdir -p "$part"
  cp "$full"/*.pvd "$full/$ck" "$part/"
  head -n $((rows + 4)) "$full/history.csv" >"$part/history.csv"
  for f in "$full"/*.vtu "$full"/*.pvtu; do
    [[ "$f" =~ _([0-9]{6})(_[0-9]+)?\.p?vtu$ ]] || continue # NAME_FRAME.vtu/.pvtu, NAME_FRAME_RANK.vtu
    index=$((10#${BASH_REMATCH[1]}))
    if ((index < frames)); then cp "$f" "$part/"; fi
  done
}

# restarted_same NAME FULL PART FROM NP: the history of the restart on NP ranks (in PART) of
# a checkpoint written on FROM ranks equals the uninterrupted one (in FULL) to MPI_TOL.
restarted_same() {
  local name=$1 full=$2 part=$3 from=$4 np=$5 diff_report
  diff_report=$(compare_histories "$full/history.csv" "$part/history.csv" "$MPI_TOL") ||
    fail "$name: checkpoint of $from ranks restarted on $np: history.csv differs from the run without interruption: $diff_report"
}

# --- PMB plate: written on 1 and 2 ranks, restarted on 2, 1 and 3
plate="$DECKS/plate_pmb.yaml"
run_peri run "$plate" --output "$TMP/pmb-np1" "${every[@]}" # one process: no mpirun start-up
expect_status 0
run_peri_mpi 2 run "$plate" --output "$TMP/pmb-np2" "${every[@]}"
expect_status 0
expect_stdout_contains "MPI ranks    2"
full_broken=$(broken_line)
full="$TMP/pmb-np2"
ck=checkpoint_000100.h5
for f in checkpoint_000050.h5 "$ck" checkpoint_000200.h5; do
  expect_nonempty_file "$full/$f"
  cmp -s "$TMP/pmb-np1/$f" "$full/$f" || fail "pmb: $f written on 2 ranks differs from the one of 1 rank"
done
[[ -z "$(find "$full" -name '*.tmp')" ]] || fail "pmb: a temporary checkpoint was left in $full"
before=$(column_at "$full/history.csv" 100 broken_bond_fraction)
after=$(column_at "$full/history.csv" 200 broken_bond_fraction)
awk -v a="$before" -v b="$after" 'BEGIN { exit !(a > 0 && b > a) }' ||
  fail "pmb: bonds must break before and after the checkpoint at step 100 ($before, then $after)"
pass "pmb plate: the checkpoints written on 2 ranks are those of 1 rank, byte for byte (broken bond fraction $before at step 100, $after at 200)"

interrupted "$full" "$ck" "$TMP/pmb-r2"
run_peri_mpi 2 run "$plate" --output "$TMP/pmb-r2" --restart "$TMP/pmb-r2/$ck" "${every[@]}"
expect_status 0
expect_stdout_contains "restart      from $TMP/pmb-r2/$ck at step 100"
for f in history.csv plate_pmb.pvd checkpoint_000200.h5 plate_pmb_000002.pvtu plate_pmb_000002_0.vtu \
  plate_pmb_000002_1.vtu; do
  expect_nonempty_file "$full/$f"
  [[ -f "$TMP/pmb-r2/$f" ]] || fail "pmb: the restart on 2 ranks did not write $f"
  cmp -s "$full/$f" "$TMP/pmb-r2/$f" ||
    fail "pmb: $f after the restart on 2 ranks differs from the run without interruption: $(cmp "$full/$f" "$TMP/pmb-r2/$f")"
done
pass "pmb plate: restarted at step 100 on 2 ranks, history.csv, the .pvd, the last frame and the final checkpoint are bitwise equal"

for np in 1 3; do
  interrupted "$full" "$ck" "$TMP/pmb-r$np"
  if ((np == 1)); then run_peri run "$plate" --output "$TMP/pmb-r1" --restart "$TMP/pmb-r1/$ck" "${every[@]}"
  else run_peri_mpi "$np" run "$plate" --output "$TMP/pmb-r$np" --restart "$TMP/pmb-r$np/$ck" "${every[@]}"; fi
  expect_status 0
  restarted_same pmb "$full" "$TMP/pmb-r$np" 2 "$np"
  [[ "$(broken_line)" == "$full_broken" ]] ||
    fail "pmb: '$full_broken' without interruption, '$(broken_line)' restarted on $np ranks"
done
pass "pmb plate: the 2-rank checkpoint restarted on 1 and 3 ranks gives the history (tolerance $MPI_TOL) and '$(sed "s/^ *//" <<<"$full_broken")'"

# --- LPS plate: written on 3 ranks, restarted on 2
run_peri_mpi 3 run "$DECKS/plate_lps.yaml" --output "$TMP/lps" "${every[@]}"
expect_status 0
interrupted "$TMP/lps" checkpoint_000150.h5 "$TMP/lps-r2"
run_peri_mpi 2 run "$DECKS/plate_lps.yaml" --output "$TMP/lps-r2" --restart "$TMP/lps-r2/checkpoint_000150.h5" \
  "${every[@]}"
expect_status 0
restarted_same lps "$TMP/lps" "$TMP/lps-r2" 3 2
before=$(column_at "$TMP/lps/history.csv" 150 broken_bond_fraction)
after=$(column_at "$TMP/lps/history.csv" 200 broken_bond_fraction)
awk -v a="$before" -v b="$after" 'BEGIN { exit !(b > a) }' || fail "lps: no bond breaks after step 150"
pass "lps plate: checkpoint of 3 ranks restarted on 2, the same history (broken bond fraction $before -> $after)"

# --- heat conduction with a growing crack: written on 3 ranks, restarted on 2
run_peri_mpi 3 run "$DECKS/restart_heat.yaml" --output "$TMP/heat"
expect_status 0
interrupted "$TMP/heat" checkpoint_000020.h5 "$TMP/heat-r2"
run_peri_mpi 2 run "$DECKS/restart_heat.yaml" --output "$TMP/heat-r2" --restart "$TMP/heat-r2/checkpoint_000020.h5"
expect_status 0
restarted_same heat "$TMP/heat" "$TMP/heat-r2" 3 2
before=$(column_at "$TMP/heat/history.csv" 20 broken_bond_fraction)
after=$(column_at "$TMP/heat/history.csv" 60 broken_bond_fraction)
awk -v a="$before" -v b="$after" 'BEGIN { exit !(b > a) }' || fail "heat: the growing crack cuts no bond after step 20"
pass "heat with a growing crack: checkpoint of 3 ranks restarted on 2, the same history (cut fraction $before -> $after)"

# --- one-way thermomechanics (conduction keeps its own cut flags): 2 ranks, restarted on 3
shock=(--set thermal.coupling=one_way)
run_peri_mpi 2 run "$DECKS/restart_thermal_shock.yaml" --output "$TMP/shock" "${shock[@]}"
expect_status 0
interrupted "$TMP/shock" checkpoint_000240.h5 "$TMP/shock-r3"
run_peri_mpi 3 run "$DECKS/restart_thermal_shock.yaml" --output "$TMP/shock-r3" "${shock[@]}" \
  --restart "$TMP/shock-r3/checkpoint_000240.h5"
expect_status 0
restarted_same shock "$TMP/shock" "$TMP/shock-r3" 2 3
pass "one-way thermal shock: checkpoint of 2 ranks restarted on 3, the same history"

# --- quasi-static: the bar pulled to failure by nlcg, breaking through in a dynamic phase
# (solver.dynamic_switch) after load step 21; written on 2 ranks at load step 14, restarted on 3
qs=(--set output.checkpoint_every=7 --set 'output.checkpoint_file=checkpoint_{step}.h5'
  --set 'solver.dynamic_switch={when_broken_exceeds: 10, damping: 1.0e5, history_every: 5}')
run_peri_mpi 2 run "$DECKS/qs_bar.yaml" --output "$TMP/qs" "${qs[@]}"
expect_status 0
interrupted "$TMP/qs" checkpoint_000014.h5 "$TMP/qs-r3"
run_peri_mpi 3 run "$DECKS/qs_bar.yaml" --output "$TMP/qs-r3" "${qs[@]}" --restart "$TMP/qs-r3/checkpoint_000014.h5"
expect_status 0
restarted_same quasi_static "$TMP/qs" "$TMP/qs-r3" 2 3
after=$(column_at "$TMP/qs/history.csv" 40 broken_bond_fraction)
awk -v b="$after" 'BEGIN { exit !(b > 0) }' || fail "quasi-static: the bar did not break after load step 14"
pass "quasi-static bar (nlcg, a dynamic phase): checkpoint of 2 ranks restarted on 3, the same history"

# --- a checkpoint of another deck: refused on 2 ranks before any output, one message
run_peri_mpi 2 run "$plate" --output "$TMP/refused" --restart "$TMP/lps/checkpoint_000150.h5"
expect_status 2
expect_stderr_contains "model lps, the deck uses pmb"
[[ $(grep -c 'error:' "$RUN_STDERR") -eq 1 ]] || fail "refused checkpoint: the message must be printed once"
expect_no_path "$TMP/refused"
pass "a checkpoint of another deck on 2 ranks: exit status 2, one message, nothing written"
echo "PASS: $CLI_NAME"
