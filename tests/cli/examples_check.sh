#!/usr/bin/env bash
# Every example deck stays valid as the deck grows: `peri check` accepts each examples/*.yaml
# (exit 0), and each example has its line in examples/README.md (the docs' promise).
# Usage: bash tests/cli/examples_check.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

n=0
for deck in examples/*.yaml; do
  run_peri check "$deck" --threads 1
  expect_status 0
  n=$((n + 1))
done
[ "$n" -ge 30 ] || fail "only $n example decks found (run from the repository root)"
pass "peri check accepts all $n example decks"

for f in examples/*.yaml examples/*/run.sh; do
  name=${f#examples/}
  grep -qF "| \`$name\`" examples/README.md || fail "examples/README.md has no line for $name"
done
pass "every example has its line in examples/README.md"
