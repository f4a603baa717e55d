#!/usr/bin/env bash
# --device (docs/gpu.md): cpu or gpu, a clear error for anything else and, in a build without
# the GPU back end or on a machine without a GPU, for gpu itself (exit 2, nothing written);
# where a GPU is used the summary names it. Also the summary's mass (density times volume
# summed over the nodes) and output.history_digits.
# Usage: bash tests/cli/device_option.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"
deck=examples/quickstart.yaml
short=(--set solver.end_time=2.0e-7 --set output.picture=false)

run_peri run "$deck" --device tpu --output "$TMP/tpu" "${short[@]}"
expect_status 2
expect_stderr_contains "option --device: expected cpu or gpu, got 'tpu'"
expect_no_path "$TMP/tpu"
run_peri run "$deck" --device
expect_status 2
expect_stderr_contains "option --device needs a value"
run_peri sweep "$deck" --device gpu --set-list solver.end_time=1e-7,2e-7 --quantity strain_energy
expect_status 2
expect_stderr_contains "option --device: only for peri run and peri check"
pass "--device: a wrong value, a missing one and sweep are refused (exit 2)"

run_peri run "$deck" --device gpu --output "$TMP/gpu" "${short[@]}"
if [[ "$RUN_STATUS" == 0 ]]; then # a build with the GPU back end on a machine with a GPU
  expect_stdout_matches "^  device       GPU: "
  expect_stdout_matches "^  gpu          [0-9]+ steps in "
  # the device line's estimate of the device's memory is what the run allocated, within 1%
  estimate=$(sed -n 's/^  device .*run there (\([0-9.e+-]*\) GB on the device.*/\1/p' "$RUN_STDOUT")
  allocated=$(sed -n 's/^  gpu .*; \([0-9.e+-]*\) GB on the device.*/\1/p' "$RUN_STDOUT")
  awk -v e="$estimate" -v a="$allocated" 'BEGIN { d = e - a; if (d < 0) d = -d; exit !(a > 0 && d <= 0.01 * a) }' ||
    fail "device memory: estimated '$estimate' GB, allocated '$allocated' GB"
  pass "--device gpu: the run took the GPU ($allocated GB allocated, $estimate GB estimated)"
else
  expect_status 2
  expect_stderr_matches "^peri: error: option --device gpu: "
  expect_no_path "$TMP/gpu"
  pass "--device gpu without a GPU: $(head -c 160 "$RUN_STDERR")"
fi
run_peri run "$deck" --device cpu --output "$TMP/cpu" "${short[@]}"
expect_status 0
if grep -q "^  device " "$RUN_STDOUT"; then fail "--device cpu printed a device line"; fi
pass "--device cpu: the CPU, no device line"

# the mass: 100 x 40 x 1 mm of glass at 2440 kg/m^3 = 9.76 g (36,000 nodes of (1/3 mm)^2 x 1 mm)
run_peri check "$deck"
expect_status 0
mass=$(sed -n 's/^  mass *\([0-9.e+-]*\) kg$/\1/p' "$RUN_STDOUT")
awk -v m="$mass" 'BEGIN { exit !(m != "" && (m - 0.00976 < 0 ? 0.00976 - m : m - 0.00976) <= 1e-4 * 0.00976) }' ||
  fail "mass '$mass' kg, expected 0.00976 kg within 1e-4"
pass "summary mass $mass kg (0.1 x 0.04 x 0.001 m x 2440 kg/m^3 = 0.00976 kg)"

# history_digits: 17 digits give every bit of a double (the time 2e-7 is not a short decimal
# after its steps: printed with 17 significant digits it has 17 of them), 0 and 18 are refused
run_peri run "$deck" --output "$TMP/h17" "${short[@]}" --set output.history_digits=17
expect_status 0
digits=$(tail -n 1 "$TMP/h17/history.csv" | cut -d, -f1 | sed 's/e.*//; s/[-.]//g; s/^0*//')
[[ ${#digits} -ge 15 ]] || fail "history_digits 17: the time printed as $(tail -n 1 "$TMP/h17/history.csv" | cut -d, -f1)"
for bad in 0 18; do
  run_peri run "$deck" --output "$TMP/h$bad" "${short[@]}" --set output.history_digits=$bad
  expect_status 2
  expect_stderr_contains "key 'history_digits': must be from 1 to 17"
done
pass "output.history_digits: 17 digits written, 0 and 18 refused"
