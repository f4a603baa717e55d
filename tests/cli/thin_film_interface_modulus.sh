#!/usr/bin/env bash
# The interface bonds' own modulus (interfaces[].youngs_modulus, docs/thin_films.md section 7):
# a 1D PMB bar of two materials in series, a (E = 200 GPa) | b (E = 100 GPa), whose bonds
# across the interface take E_I = 20 GPa, pulled by U = 1 mm through fictitious layers.
# The theory is the bar's discrete equilibrium, solved here with numpy from the PMB definition
# (docs/model_reference.md 2: pair force c_ij beta V_j (u_j - u_i)/|xi| in 1D, exactly linear,
# c = 2E/(A delta^2), the partial-volume ramp min(1, 1/2 + (delta - |xi|)/dx), c_ij = c_I for
# a pair across the interface and (c_a + c_b)/2 otherwise):
# - the implicit (Newton, tangent) and nlcg solves give every node's displacement within
#   1e-4 U of it and the right layer's reaction (the bar's effective stiffness E_eff = F L/(A U))
#   within 1e-4 (nlcg: 1e-3), and strain_energy = F U/2 (Clapeyron) within the same;
# - the same bar with the mean rule at the interface (no youngs_modulus) is 10% stiffer, so a
#   code that ignored the key fails by 100x the tolerance, and its run matches that solution;
# - bad keys exit 2 at the key: a negative modulus, the same material twice, the LPS model;
#   peri sweep's film quantities on a deck without output.wrinkles exit 2 before any run.
# Usage: bash tests/cli/thin_film_interface_modulus.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"
bar="$DECKS/interface_series_bar.yaml"

PY=""
for candidate in /usr/bin/python3 python3; do
  if command -v "$candidate" >/dev/null && "$candidate" -c 'import numpy' 2>/dev/null; then
    PY=$candidate
    break
  fi
done
if [[ -z "$PY" ]]; then
  echo "SKIP: $CLI_NAME: no python3 with numpy (Debian python3-numpy: scripts/install-deps)"
  exit 0
fi

# compare DIR E_I(0: mean rule) TOLERANCE: prints "OK E_eff ..." or "FAIL ..."
compare() {
  "$PY" - "$CLI_DIR/lib" "$@" <<'PYEOF'
import sys, csv
sys.path.insert(0, sys.argv[1])
import numpy as np
from check_outputs import read_frame, read_pvd
out, E_I, tol = sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
dx, delta, A, U, L = 0.01, 0.03, 0.01, 1e-3, 1.0
x = -0.025 + dx * np.arange(106)               # cell centres of the fill [-0.03, 1.03]
E = np.where(x < 0.5, 200e9, 100e9)
c = 2 * E / (A * delta**2)                      # 1D PMB micromodulus
n = len(x)
K = np.zeros((n, n))
for i in range(n):
    for j in range(n):
        r = abs(x[j] - x[i])
        if i == j or r > delta + dx / 2 + 1e-12:
            continue
        beta = min(1.0, 0.5 + (delta - r) / dx)
        across = (x[i] < 0.5) != (x[j] < 0.5)
        cij = 2 * E_I / (A * delta**2) if (across and E_I > 0) else 0.5 * (c[i] + c[j])
        k = cij * beta * A * dx / r             # force density on i per (u_j - u_i)
        K[i, j] += k
        K[i, i] -= k
held = (x < 0) | (x > 1)
u = np.where(x > 1, U, 0.0)
free = ~held
u[free] = np.linalg.solve(K[np.ix_(free, free)], -K[np.ix_(free, held)] @ u[held])
F = -np.sum((K @ u)[x > 1] * A * dx)            # reaction of the right layer: -sum f V
frames = read_pvd(out, "interface_series_bar")
a, _ = read_frame(out, frames[-1][1])
xs = a["reference_position"][:, 0]
us = a["displacement"][:, 0]
order = np.argsort(xs)
body = free
err = np.max(np.abs(us[order] - u[body])) / U
rows = list(csv.DictReader(open(out + "/history.csv")))
Fp = float(rows[-1]["reaction_right_layer_x"])
E_eff = F * L / (A * U)
W = float(rows[-1]["strain_energy"])             # Clapeyron: the stored energy F U / 2
ok = err < tol and abs(Fp / F - 1) < tol and abs(W / (0.5 * F * U) - 1) < tol
print("%s E_eff %.6g Pa (run %.6g), displacement error %.2e U, reaction %.6g N (theory %.6g N), "
      "strain energy %.6g J (F U/2 %.6g J)" % ("OK" if ok else "FAIL", E_eff, Fp * L / (A * U), err, Fp, F, W, 0.5 * F * U))
PYEOF
}

run_peri run "$bar" --quiet --output "$TMP/implicit"
expect_status 0
line=$(compare "$TMP/implicit" 20e9 1e-4)
[[ "$line" == OK* ]] || fail "implicit: $line"
pass "E_I = 20 GPa, implicit: $line"

run_peri run "$bar" --quiet --output "$TMP/nlcg" --set solver.type=nlcg --set solver.tolerance=1e-10
expect_status 0
line=$(compare "$TMP/nlcg" 20e9 1e-3)
[[ "$line" == OK* ]] || fail "nlcg: $line"
pass "E_I = 20 GPa, nlcg: $line"

# the mean rule: the run without the key matches its own solution, which differs by ~10%
run_peri run "$bar" --quiet --output "$TMP/mean" --set "interfaces=[]"
expect_status 0
line=$(compare "$TMP/mean" 0 1e-4)
[[ "$line" == OK* ]] || fail "mean rule: $line"
wrong=$(compare "$TMP/mean" 20e9 1e-2)
[[ "$wrong" == FAIL* ]] || fail "the solution with E_I = 20 GPa does not tell the mean rule apart: $wrong"
pass "mean rule (no youngs_modulus): $line"

run_peri check "$bar" --set "interfaces.0.youngs_modulus=-1e9"
expect_status 2
expect_stderr_contains "youngs_modulus must be a positive number"
run_peri check "$bar" --set "interfaces=[{materials: [a, a], youngs_modulus: 1e9}]"
expect_status 2
expect_stderr_contains "needs two different materials"
run_peri check "$bar" --set "materials.a={model: lps, density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.25}" --set "materials.b={model: lps, density: 7850, youngs_modulus: 100e9, poisson_ratio: 0.25}"
expect_status 2
expect_stderr_contains "youngs_modulus is for the bond-based model pmb"
pass "bad youngs_modulus keys: exit 2 at the key"

# peri sweep's film quantities need a film region (output.wrinkles): exit 2 before any run
run_peri sweep "$bar" --set-list "interfaces.0.youngs_modulus=1e9,2e9" --quantity film_regime
expect_status 2
expect_stderr_contains "need a quasi-static solver and output.wrinkles"
[[ ! -s "$RUN_STDOUT" ]] || fail "the sweep printed rows before the error: $(cat "$RUN_STDOUT")"
pass "peri sweep --quantity film_regime without output.wrinkles: exit 2 before any run"
