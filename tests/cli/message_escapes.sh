#!/usr/bin/env bash
# Control characters in deck text (YAML escapes such as "\e", "\a", "\r" in a quoted key or
# value) are quoted back in error messages as escapes (\x1b, \x07, \r), never raw: a raw
# ESC would drive the terminal instead of being seen. Covers the unknown-key, the
# unknown-choice and the unknown-region messages (three paths with suggestions).
# Usage: bash tests/cli/message_escapes.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

# no byte below 0x20 (other than the line ends) and no DEL on stderr
expect_no_control_bytes() {
  if LC_ALL=C grep -q $'[\x01-\x09\x0b-\x1f\x7f]' "$RUN_STDERR"; then
    fail "stderr holds a raw control character: $(od -c "$RUN_STDERR" | head -n 5)"
  fi
}

deck="$TMP/key.yaml"
sed 's/^    fracture_energy: 3.8$/    fracture_energy: 3.8\n    "dens\\e[31mity": 1/' \
  "$DECKS/valid_small.yaml" >"$deck"
run_peri check "$deck"
expect_status 2
expect_no_control_bytes
expect_stderr_contains "unknown key 'dens\\x1b[31mity' in materials.glass"
pass "ESC in a key is written as \\x1b"

deck="$TMP/choice.yaml"
sed 's/model: pmb/model: "pm\\ab"/' "$DECKS/valid_small.yaml" >"$deck"
run_peri check "$deck"
expect_status 2
expect_no_control_bytes
expect_stderr_contains "key 'model': unknown value 'pm\\x07b'; did you mean 'pmb'?"
pass "BEL in a value is written as \\x07"

deck="$TMP/region.yaml"
sed 's/region: top, y/region: "to\\rp", y/' "$DECKS/valid_small.yaml" >"$deck"
run_peri check "$deck"
expect_status 2
expect_no_control_bytes
expect_stderr_contains "unknown region 'to\\rp'; did you mean 'top'?"
pass "CR in a region name is written as \\r"
