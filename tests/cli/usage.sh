#!/usr/bin/env bash
# Command line handling: help, version, and exit status 2 with a message for every misuse.
# Usage: bash tests/cli/usage.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

deck=examples/quickstart.yaml
[[ -f "$deck" ]] || fail "run from the repository root ($deck not found)"

# --help: the usage on stdout, status 0, both commands named
for flag in --help -h; do
  run_peri "$flag"
  expect_status 0
  expect_stdout_contains "usage: peri run DECK"
  expect_stdout_contains "peri check DECK"
  expect_stdout_matches "^ +run +"
  expect_stdout_matches "^ +check +"
  expect_stdout_contains "--threads N"
  expect_stdout_contains "--output DIR"
  expect_stderr_empty
done
pass "--help and -h print the usage (run, check) and exit 0"

# --version: "peri X.Y.Z" on stdout, status 0
run_peri --version
expect_status 0
expect_stderr_empty
[[ $(wc -l <"$RUN_STDOUT") -eq 1 ]] || fail "--version: expected one line"
grep -qE '^peri [0-9]+\.[0-9]+\.[0-9]+$' "$RUN_STDOUT" || fail "--version: expected 'peri X.Y.Z'"
version=$(cat "$RUN_STDOUT")
pass "--version prints '$version'"

# the summary printed by check names the same version
run_peri check "$deck"
expect_status 0
expect_stdout_contains "$version: $deck"
pass "check's summary names the version ($version)"

# no arguments: usage on stderr, status 2, nothing on stdout
run_peri
expect_status 2
expect_stdout_empty
expect_stderr_contains "usage: peri run DECK"
pass "no arguments: status 2 and the usage on stderr"

# unknown command
run_peri frobnicate "$deck"
expect_status 2
expect_stderr_contains "unknown command 'frobnicate'"
expect_stderr_contains "run, check"
pass "unknown command: status 2 with a message"

# a command without a deck
for command in run check; do
  run_peri "$command"
  expect_status 2
  expect_stderr_contains "no deck given"
done
pass "run / check without a deck: status 2"

# unknown option, before and after the deck
run_peri run --bogus "$deck"
expect_status 2
expect_stderr_contains "unknown option '--bogus'"
run_peri check "$deck" --frob
expect_status 2
expect_stderr_contains "unknown option '--frob'"
pass "unknown option: status 2 with a message"

# --threads needs a positive integer; every bad value is refused before any work
for value in 0 -1 two 1.5 "" 4294967297; do
  run_peri_in "$TMP" run "$(pwd)/$deck" --threads "$value" --output "$TMP/out"
  expect_status 2
  expect_stderr_contains "option --threads: expected an integer from 1 to 4096, got '$value'"
  expect_no_path "$TMP/out"
  expect_no_path "$TMP/output"
done
pass "--threads 0, -1, two, 1.5, '' and 2^32+1: status 2, no output"

# an empty output path is bad input; --help after the command prints the usage
run_peri_in "$TMP" run "$(pwd)/$deck" --output ""
expect_status 2
expect_stderr_contains "option --output: expected a directory"
run_peri run --help
expect_status 0
pass "--output '' is bad input; run --help prints the usage"

# options that need a value
for option in --threads --output; do
  run_peri run "$deck" "$option"
  expect_status 2
  expect_stderr_contains "option $option needs a value"
done
pass "--threads / --output without a value: status 2"

# two decks
run_peri check "$deck" "$deck"
expect_status 2
expect_stderr_contains "unexpected argument"
pass "two decks: status 2"

# a deck that does not exist, for both commands
for command in run check; do
  run_peri_in "$TMP" "$command" "$TMP/no_such_deck.yaml" --output "$TMP/out"
  expect_status 2
  expect_stderr_contains "cannot open"
  expect_stderr_contains "no_such_deck.yaml"
  expect_no_path "$TMP/out"
  expect_no_path "$TMP/output"
done
pass "missing deck file: status 2 with 'cannot open'"

# a directory given as the deck
run_peri check "$TMP"
expect_status 2
expect_stderr_matches "cannot (open|read) deck"
pass "a directory as the deck: status 2"

echo "PASS: $CLI_NAME"
