#!/usr/bin/env bash
# Deck errors: each fixture tests/cli/decks/err_*.yaml differs from valid_small.yaml by one
# mistake. peri must exit 2, name the file:line:col of the mistake, say what is wrong (with
# a suggestion for a likely typo), print no summary and create no output directory: every
# input error is reported before any work.
# Usage: bash tests/cli/deck_errors.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

# deck_fails COMMAND DECK: runs "peri COMMAND DECK" from an empty working directory with
# --output into it, and checks status 2, no stdout, a "file:" prefixed error and that no
# output directory appeared (neither --output nor the default output/NAME).
deck_fails() {
  local command=$1 deck=$2 work
  work=$(mktemp -d "$TMP/run.XXXXXX")
  if [[ "$command" == run ]]; then
    run_peri_in "$work" run "$deck" --quiet --output "$work/out"
  else
    run_peri_in "$work" check "$deck"
  fi
  expect_status 2
  expect_stdout_empty
  expect_stderr_contains "$deck:"
  expect_stderr_contains ": error: "
  expect_no_path "$work/out"
  expect_no_path "$work/output"
  [[ -z "$(ls -A "$work")" ]] || fail "the working directory is not empty after the error: $(ls -A "$work")"
}

# expect_error_at DECK PATTERN MESSAGE: the error names DECK at the line and column where
# the fixed string PATTERN starts in DECK, followed by MESSAGE.
expect_error_at() {
  locate "$2" "$1"
  expect_stderr_contains "$1:$LOC_LINE:$LOC_COL: error: $3"
}

# both commands fail the same way; `run` is checked for "no work" and `check` for the
# message too (check validates the deck exactly as run does)
check_both() {
  local deck=$1 pattern=$2 message=$3
  for command in check run; do
    deck_fails "$command" "$deck"
    expect_error_at "$deck" "$pattern" "$message"
  done
}

D="$DECKS"

# control: the fixtures' common deck is valid and runs
run_peri check "$D/valid_small.yaml"
expect_status 0
expect_stderr_empty
run_peri run "$D/valid_small.yaml" --quiet --output "$TMP/valid"
expect_status 0
expect_file "$TMP/valid/history.csv"
pass "control: valid_small.yaml checks and runs"

# (a) a misspelt key: position of the key, the section and a suggestion
check_both "$D/err_unknown_key.yaml" "densty:" \
  "unknown key 'densty' in materials.glass; did you mean 'density'?"
pass "(a) unknown key 'densty': file:line:col of the key and did you mean 'density'"

# (b) wrong types: position of the value, what was expected and what was found
check_both "$D/err_type_list.yaml" "[1, 2]" "key 'density': expected a number, got a list"
check_both "$D/err_type_string.yaml" "abc" "key 'density': expected a number, got 'abc'"
pass "(b) density: [1, 2] and density: abc: expected a number"

# (c) a missing required key: names the key and the section; the position is that of the
# material's mapping (its line, or the line of its name)
deck="$D/err_missing_key.yaml"
for command in check run; do
  deck_fails "$command" "$deck"
  expect_stderr_contains "missing key 'density' in materials.glass"
  locate "glass:" "$deck"
  lines="$LOC_LINE|$((LOC_LINE + 1))"
  expect_stderr_matches "$deck:($lines):[0-9]+: error: missing key 'density'"
done
pass "(c) no density: missing key 'density' in materials.glass"

# (d) an expression with an unknown variable, at the position of the value
check_both "$D/err_expression.yaml" '"2*q"' "key 'y': bad expression '2*q': unknown variable 'q'"
pass "(d) y: \"2*q\": unknown variable 'q'"

# (e) an unknown choice with a suggestion and the list of choices
check_both "$D/err_model.yaml" "pbm" "key 'model': unknown value 'pbm'; did you mean 'pmb'?"
expect_stderr_contains "(choices: pmb, lps, osb_mo)"
pass "(e) model: pbm: did you mean 'pmb'"

# (f) YAML syntax errors: file:line:col of the offending character
check_both "$D/err_yaml_colon.yaml" ": 3" "mapping values are not allowed in this context"
# the list opened at "[0.020" is closed by the '}' after "0.010"
deck="$D/err_yaml_bracket.yaml"
for command in check run; do
  deck_fails "$command" "$deck"
  locate "0.010}" "$deck"
  expect_stderr_contains "$deck:$LOC_LINE:$((LOC_COL + 5)): error: did not find expected ',' or ']'"
  locate "[0.020" "$deck"
  expect_stderr_contains "started at line $LOC_LINE, column $LOC_COL"
done
# a tab in the indentation (made here so that no editor can turn it into spaces)
deck="$TMP/err_yaml_tab.yaml"
sed 's/^    density: 2440$/\tdensity: 2440/' "$D/valid_small.yaml" >"$deck"
grep -q "$(printf '^\t')density" "$deck" || fail "could not make the tab fixture"
check_both "$deck" "$(printf '\t')density" "tab character; YAML indentation must use spaces"
pass "(f) YAML syntax errors (':' in a value, '}' closing a list, a tab): file:line:col"

# (g) an unknown top-level section with a suggestion
check_both "$D/err_section.yaml" "solvr:" "unknown key 'solvr' in the deck; did you mean 'solver'?"
pass "(g) solvr: did you mean 'solver'"

# (h) unknown regions in a boundary condition, at the position of the name
check_both "$D/err_region_typo.yaml" "topp" "unknown region 'topp'; did you mean 'top'?"
check_both "$D/err_region_unknown.yaml" "middle" "unknown region 'middle'"
pass "(h) unknown region 'topp' (did you mean 'top') and 'middle'"

# (h2) a condition without 'region' no longer applies to the whole body: an error at the
# condition naming the fix ('region: all'); with 'region: all' written the deck is valid
deck="$TMP/err_region_missing.yaml"
sed 's/^  - {type: velocity, region: bottom, y: 0}$/  - {type: body_force, y: "-9.81*2440"}/' "$D/valid_small.yaml" >"$deck"
grep -q 'type: body_force, y:' "$deck" || fail "valid_small.yaml changed: the fixture edit did not apply"
check_both "$deck" "{type: body_force" "boundary condition 'body_force' has no 'region': name one, or write 'region: all'"
sed -i 's/{type: body_force, y:/{type: body_force, region: all, y:/' "$deck"
run_peri check "$deck"
expect_status 0
pass "(h2) a condition without 'region' is refused; 'region: all' is accepted"

# (i) an unknown output field, at the position of the name, with a suggestion and the list
# of the fields a frame can hold
deck="$TMP/err_field.yaml"
sed 's/^  every: 10$/  every: 10\n  fields: [damage, dammage]/' "$D/valid_small.yaml" >"$deck"
grep -q "dammage" "$deck" || fail "could not make the output field fixture"
check_both "$deck" "dammage" "unknown output field 'dammage'; did you mean 'damage'?"
expect_stderr_contains "(fields: displacement, velocity, force, damage, dilatation, material, volume, strain_energy_density, block, stress, strain, von_mises, principal_stress, temperature, heat_flux, node_type, d2u, horizon, yield_index, plastic_stretch, spacing, interface, body)"
pass "(i) unknown output field 'dammage': did you mean 'damage', and the list of fields"

# the same deck given through a relative path is named as given
rel="tests/cli/decks/err_unknown_key.yaml"
if [[ -f "$rel" ]]; then
  run_peri check "$rel"
  expect_status 2
  locate "densty:" "$rel"
  expect_stderr_contains "$rel:$LOC_LINE:$LOC_COL: error: unknown key 'densty'"
  pass "a relative deck path is reported as given"
fi

echo "PASS: $CLI_NAME"
