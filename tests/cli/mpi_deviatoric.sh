#!/usr/bin/env bash
# The deviatoric yield rule on MPI ranks (docs/plasticity.md section 8, docs/parallel.md "Bond
# halo"): a node's force reads the other end's plastic term of each bond, which for a ghost
# its owner sends. The 3D LPS block of tests/cli/decks/plastic_block3d.yaml, pulled until it
# yields through (mean yield index 1), on 1, 2 and 3 ranks:
#   - history.csv agrees to a relative 1e-9, and on 2 ranks the displacements and the plastic
#     deviatoric stretches of every bond in the final checkpoint (global order, whatever the
#     ranks) differ by at most 1e-9 of their scale (the pulled end's displacement, the
#     nominal strain). Ranks change no order of summation (every family sum runs in the
#     global order), so round-off (1e-16 per operation over 400 steps) is far below the
#     bound, while a missing term from the other rank changes the flow at first order;
#   - restarted on 2 ranks from the checkpoint at step 50 (mean yield index 0.13, before the
#     block yields through) it gives history.csv and the final checkpoint bitwise.
# The tensor yield rule (section 10) on 1, 2 and 3 ranks and restarted on 3 from a checkpoint
# of 2, to the same 1e-9.
# Skipped when peri was built without MPI or without HDF5.
# Usage: bash tests/cli/mpi_deviatoric.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init
skip_without_checkpoints
command -v h5dump >/dev/null && command -v h5diff >/dev/null ||
  fail "h5dump and h5diff are needed (Debian package hdf5-tools, see scripts/install-deps)"

block="$DECKS/plastic_block3d.yaml"
every=(--set output.checkpoint_every=50 --set 'output.checkpoint_file=checkpoint_{step}.h5')
fin=checkpoint_000400.h5

run_peri run "$block" --output "$TMP/np1" "${every[@]}" # one process: no mpirun start-up
expect_status 0
for np in 2 3; do
  run_peri_mpi "$np" run "$block" --output "$TMP/np$np" "${every[@]}"
  expect_status 0
  expect_stdout_contains "MPI ranks    $np"
  report=$(compare_histories "$TMP/np1/history.csv" "$TMP/np$np/history.csv" 1e-9) ||
    fail "history.csv on 1 and $np ranks differs: $report"
done
psi_col=$(csv_column "$TMP/np1/history.csv" mean_yield_index)
psi=$(tail -n 1 "$TMP/np1/history.csv" | cut -d, -f"$psi_col")
awk -v p="$psi" 'BEGIN { exit !(p > 0.3) }' || fail "the block barely yields (mean yield index $psi): the comparison is weak"

# scales: the pulled end moves 2.5 m/s * t, over the block's 11 mm between the end zones
t_end=$(tail -n 1 "$TMP/np1/history.csv" | cut -d, -f"$(csv_column "$TMP/np1/history.csv" time)")
du=$(awk -v t="$t_end" 'BEGIN { printf "%.3e", 1e-9 * 2.5 * t }')
dp=$(awk -v t="$t_end" 'BEGIN { printf "%.3e", 1e-9 * 2.5 * t / 0.011 }')
h5diff -d "$du" "$TMP/np1/$fin" "$TMP/np2/$fin" /nodes/u /nodes/u >"$TMP/diff_u.txt" ||
  fail "displacements on 1 and 2 ranks differ by more than $du m: $(head -n 5 "$TMP/diff_u.txt")"
h5diff -d "$dp" "$TMP/np1/$fin" "$TMP/np2/$fin" /bonds/plastic_stretch /bonds/plastic_stretch >"$TMP/diff_p.txt" ||
  fail "plastic stretches on 1 and 2 ranks differ by more than $dp: $(head -n 5 "$TMP/diff_p.txt")"
h5dump -m %.3e -d /bonds/plastic_stretch "$TMP/np2/$fin" | grep -qE '[1-9]\.[0-9]+e-0[23]' ||
  fail "the final checkpoint holds no plastic stretch of the size of the strain"
pass "deviatoric block: 1, 2 and 3 ranks give the history (1e-9), 2 ranks the displacements (within $du m) and plastic stretches (within $dp); mean yield index $psi"

# --- restart on 2 ranks at step 50: what an interrupted run leaves, then the continuation
ck=checkpoint_000050.h5
full="$TMP/np2" part="$TMP/restart"
h5_attr() { h5dump -a "$2" "$1" | sed -nE 's/^ *\(0\): *(-?[0-9]+).*/\1/p' | head -n 1; }
frames=$(h5_attr "$full/$ck" /state/frames)
rows=$(h5_attr "$full/$ck" /state/history_rows)
[[ "$frames" =~ ^[0-9]+$ && "$rows" =~ ^[0-9]+$ ]] || fail "cannot read /state/frames and history_rows of $ck"
mkdir -p "$part"
cp "$full"/*.pvd "$full/$ck" "$part/"
head -n $((rows + 4)) "$full/history.csv" >"$part/history.csv"
for f in "$full"/*.pvtu "$full"/*.vtu; do
  [[ "$f" =~ _([0-9]{6})(_[0-9]+)?\.p?vtu$ ]] || continue # NAME_FRAME.pvtu, NAME_FRAME_RANK.vtu
  if ((10#${BASH_REMATCH[1]} < frames)); then cp "$f" "$part/"; fi
done
run_peri_mpi 2 run "$block" --output "$part" --restart "$part/$ck" "${every[@]}"
expect_status 0
expect_stdout_contains "restart      from $part/$ck at step 50"
for f in history.csv "$fin"; do
  cmp -s "$full/$f" "$part/$f" || fail "$f after the restart on 2 ranks differs from the run without interruption"
done
before=$(awk -F, -v c="$psi_col" -v r="$((rows + 1))" 'NR == r { print $c }' "$full/history.csv")
awk -v a="$before" 'BEGIN { exit !(a < 0.5) }' || fail "the block has yielded through by step 50 (mean yield index $before)"
pass "deviatoric block: restarted at step 50 on 2 ranks (mean yield index $before -> $psi), history.csv and the final checkpoint bitwise"

# --- the tensor yield rule (docs/plasticity.md section 10): a node's force reads its ghosts'
# plastic terms (6 numbers a node, exchanged as D and B are); the same block on 1, 2 and 3
# ranks, the plastic tensors of the final checkpoint (global node order) within 1e-9 of the
# nominal strain, and a restart at step 50 on 3 ranks from a checkpoint written on 2
tensor=(--set materials.steel.plasticity.yield_rule=deviatoric_tensor)
run_peri run "$block" "${tensor[@]}" --output "$TMP/t1" "${every[@]}"
expect_status 0
for np in 2 3; do
  run_peri_mpi "$np" run "$block" "${tensor[@]}" --output "$TMP/t$np" "${every[@]}"
  expect_status 0
  report=$(compare_histories "$TMP/t1/history.csv" "$TMP/t$np/history.csv" 1e-9) ||
    fail "tensor rule: history.csv on 1 and $np ranks differs: $report"
done
h5diff -d "$dp" "$TMP/t1/$fin" "$TMP/t2/$fin" /nodes/plastic_tensor /nodes/plastic_tensor >"$TMP/diff_t.txt" ||
  fail "tensor rule: plastic tensors on 1 and 2 ranks differ by more than $dp: $(head -n 5 "$TMP/diff_t.txt")"
h5dump -m %.3e -d /nodes/plastic_tensor "$TMP/t2/$fin" | grep -qE '[1-9]\.[0-9]+e-0[23]' ||
  fail "tensor rule: the final checkpoint holds no plastic tensor of the size of the strain"
part="$TMP/t_restart"
mkdir -p "$part"
cp "$TMP/t2"/*.pvd "$TMP/t2/$ck" "$part/"
rows=$(h5_attr "$TMP/t2/$ck" /state/history_rows)
head -n $((rows + 4)) "$TMP/t2/history.csv" >"$part/history.csv"
run_peri_mpi 3 run "$block" "${tensor[@]}" --output "$part" --restart "$part/$ck" "${every[@]}"
expect_status 0
report=$(compare_histories "$TMP/t1/history.csv" "$part/history.csv" 1e-9) ||
  fail "tensor rule: restarted on 3 ranks from 2, history.csv differs from one process: $report"
psi_t=$(tail -n 1 "$TMP/t1/history.csv" | cut -d, -f"$psi_col")
pass "tensor rule: 1, 2 and 3 ranks give the history (1e-9) and the plastic tensors (within $dp), a restart at step 50 from 2 ranks on 3 the history; mean yield index $psi_t"
echo "PASS: $CLI_NAME"
