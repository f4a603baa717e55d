#!/usr/bin/env bash
# A short fuzzing run of one target (the ctest tests fuzz.deck_smoke, fuzz.run_smoke and
# fuzz.checkpoint_smoke; README.md has the long runs):
#   bash tests/fuzz/smoke.sh TARGET_BINARY CORPUS_NAME SECONDS [libFuzzer options...]
# starts from the seeds in tests/fuzz/corpus/CORPUS_NAME, writes new inputs to a temporary
# corpus, and fails when the target crashes, leaks, times out or trips a sanitizer; the
# input that did it is kept as TARGET-*.crash (fuzz_deck-crash-...) in the working directory.
# libFuzzer's random seed is fixed (PERI_FUZZ_SEED, 0 for a new one each run), so that a
# smoke run repeats on the same build and machine; the long runs of README.md explore.
set -u
if [[ $# -lt 3 ]]; then
  echo "usage: bash $0 TARGET_BINARY CORPUS_NAME SECONDS [libFuzzer options...]" >&2
  exit 2
fi
target=$1 name=$2 seconds=$3
label=$(basename "$target")
shift 3
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
[[ -x "$target" ]] || { echo "FAIL: $target is not an executable program" >&2; exit 1; }
work=$(mktemp -d "${TMPDIR:-/tmp}/peri-fuzz-smoke.XXXXXX") || exit 1
trap 'rm -rf -- "$work"' EXIT
mkdir -p "$work/corpus" "$work/artifacts"
# the targets write their deck or checkpoint file under TMPDIR: removed with the rest
export TMPDIR="$work"

# one thread: the bond loops would otherwise take every core for tiny problems
export OMP_NUM_THREADS=1 OMP_WAIT_POLICY=passive
export LSAN_OPTIONS="suppressions=$here/lsan.supp:print_suppressions=0"
seeds=("$here/corpus/$name")
[[ -d "$here/regressions/$name" ]] && seeds+=("$here/regressions/$name")
seed=${PERI_FUZZ_SEED:-20261129}
dict=()
[[ -f "$here/$name.dict" ]] && dict=("-dict=$here/$name.dict")

"$target" -seed="$seed" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -print_final_stats=1 \
  -artifact_prefix="$work/artifacts/" "${dict[@]}" "$@" "$work/corpus" "${seeds[@]}" >"$work/log" 2>&1
status=$?
grep -E '^(#[0-9]+[[:space:]]+(INITED|DONE)|stat::number_of_executed_units|Done [0-9]+ runs)' "$work/log"
if [[ $status -ne 0 ]]; then
  echo "FAIL: $label: the target stopped with status $status (libFuzzer seed $seed)" >&2
  tail -n 60 "$work/log" >&2
  for a in "$work"/artifacts/*; do
    [[ -f "$a" ]] || continue
    keep="$label-$(basename "$a").crash"
    cp -- "$a" "$keep"
    echo "the input is kept as $(pwd)/$keep (run: $target $keep)" >&2
  done
  exit 1
fi
echo "ok: $label: no crash, leak, timeout or sanitizer report in $seconds s"
