/* Explicit dynamics of the PD-FEM coupling (docs/coupling.md, "Explicit dynamics"): a bar of
 * 450 m, E = rho = A = 1 (c = 1 m/s), dx = 1, 2-node bars in [0, 150) and (300, 450], bond-based
 * PD (alpha = 1, delta = 3 dx) in [150, 300]; lumped masses rho V_i, velocity-Verlet at 0.8
 * times the stable step. A right-moving Gaussian pulse u = a exp(-((x - 75 - ct)/w)^2) starts
 * in the left FEM part (w = 10 and 20: its tails are below 1e-6 a at the ends and interfaces).
 *  - The stable step of the coupled rows (Gershgorin) is dx / c, the CFL step of the bar
 *    element, to round-off: the 2-node bar with lumped masses has w_max = 2c/dx exactly.
 *  - Reflection at each interface: the out-of-balance force of a cubic field across an
 *    interface, sum F = -(1/24)(1 - 1/m^2) E A delta^2 u''' (002 eq. 2.108), is a point force
 *    that radiates both ways the displacement (1/(2 rho c A)) int F dt, at most
 *    (1/27)(delta/w)^2 a for m = 3 (max |g''| = 2a/w^2); the phase velocities of PD,
 *    c (1 - (k delta)^2/48), and of the lumped bar, c (1 - (k dx)^2/24), differ by 0.146 k^2,
 *    an impedance mismatch reflecting half of it, 0.15% at k = sqrt(2)/w. The sum, 0.48% at
 *    w = 10, bounds the largest |u| behind the pulse (left interface at t = 150 in [0, 140];
 *    right interface at t = 300 in [160, 290]; the pulse is then 85 m = 4.25 w away or more). At w = 20 it is a quarter. The transmitted
 *    pulse keeps its peak to 2% (the dispersion of w = 10 over 150 m lowers it by 0.5%).
 *  - Energy: the coupled stiffness is not symmetric, so 1/2 u.Ku + kinetic energy is not
 *    conserved while the pulse crosses an interface (the out-of-balance forces do work of
 *    order (delta/w)^2, returned at the symmetric exit); after both crossings, back in the FEM
 *    part, it is E0 to 1e-4 (velocity-Verlet conserves the energy of the linear elastic bar
 *    up to its O(dt^2) oscillation), and inside the PD part it stays within (1/4)(delta/w)^2 of E0.
 * A wrong mass (the FEM nodes' mass doubled: impedance ratio sqrt 2, a reflection of 17%) or
 * a wrong step fails these checks. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include "peri/coupling.h"
#include "peri/energies.h"
#include "peri/sim.h"
#include "peri/solver.h"
#include "support.h"

typedef struct record {
  double e0, worst_in_pd, end;
  double behind_left, behind_right, peak;
} record;

static double largest_u(const peri_sim *s, double lo, double hi) {
  double m = 0.0;
  for (int32_t i = 0; i < s->disc.p.n; ++i) {
    const double x = s->disc.p.x[3 * (size_t)i];
    if (x > lo && x < hi) m = fmax(m, fabs(s->disc.p.u[3 * (size_t)i]));
  }
  return m;
}

static int hook(peri_sim *s, void *ctx) {
  record *r = ctx;
  const double t = s->state.time, e = peri_kinetic_energy(s) + peri_strain_energy(s);
  if (t > 135.0 && t < 165.0) r->worst_in_pd = fmax(r->worst_in_pd, fabs(e / r->e0 - 1.0)); /* the pulse in PD */
  r->end = e;
  if (fabs(t - 150.0) < 0.5 * s->solver.dt) {
    r->behind_left = largest_u(s, 0.0, 140.0);
    r->peak = largest_u(s, 160.0, 290.0);
  }
  if (fabs(t - 300.0) < 0.5 * s->solver.dt) r->behind_right = largest_u(s, 160.0, 290.0);
  return 0;
}

/* Runs the pulse of width w to t = 300 (a multiple of the step 0.8). */
static record run_pulse(double w, double *dt_stable) {
  char deck[2048];
  snprintf(deck, sizeof deck,
           "dimension: 1\n"
           "materials: {bar: {model: pmb, density: 1, youngs_modulus: 1}}\n"
           "discretization: {spacing: 1, m: 3, cross_section: 1, placement: lattice,\n"
           "                 fill: [{shape: interval, min: [0], max: [450]}]}\n"
           "regions: {pd: {shape: interval, min: [149.75], max: [300.25]}}\n"
           "coupling: {pd_region: pd}\n"
           "boundary_conditions:\n"
           "  - {type: initial_displacement, region: all, x: \"1e-3*exp(-((x-75)/%g)^2)\"}\n"
           "  - {type: initial_velocity, region: all, x: \"2e-3*(x-75)/%g*exp(-((x-75)/%g)^2)\"}\n"
           "solver: {type: explicit, end_time: 300, safety_factor: 0.8}\n"
           "output: {picture: false}\n",
           w, w * w, w);
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0, "deck:\n%s", deck);
  cr_assert_not_null(s.coupling);
  *dt_stable = peri_stable_dt(&s);
  peri_apply_initial_conditions(&s);
  peri_coupling_force(&s);
  record r = {0};
  r.e0 = peri_kinetic_energy(&s) + peri_strain_energy(&s);
  s.state.forces_current = true;
  cr_assert_eq(peri_solve_explicit(&s, hook, &r), 0);
  cr_assert(fabs(s.state.time - 300.0) < 1e-9, "ran to t = %g", s.state.time);
  peri_sim_free(&s);
  return r;
}

Test(coupling_dynamics, pulse_crosses_the_interfaces) {
  const double a = 1e-3, delta = 3.0, dx = 1.0;
  double dt;
  const record r10 = run_pulse(10.0, &dt);
  cr_expect(fabs(dt - dx) <= 1e-12, "stable step %.15g, the bar's CFL step dx/c = 1", dt);
  const record r20 = run_pulse(20.0, &dt);
  for (int k = 0; k < 2; ++k) {
    const double w = k ? 20.0 : 10.0;
    const record *r = k ? &r20 : &r10;
    const double k_rms = sqrt(2.0) / w;
    const double bound = (pow(delta / w, 2) / 27.0 + 0.5 * (delta * delta / 48.0 - dx * dx / 24.0) * k_rms * k_rms) * a;
    printf("w = %g: behind the left interface %.4g, the right %.4g (bound %.4g); peak %.5g; energy in PD %.4g, "
           "after %.3g\n", w, r->behind_left / a, r->behind_right / a, bound / a, r->peak / a, r->worst_in_pd,
           r->end / r->e0 - 1.0);
    cr_expect(r->behind_left <= bound, "w = %g: reflection at the left interface %g > %g", w, r->behind_left, bound);
    cr_expect(r->behind_right <= bound, "w = %g: reflection at the right interface %g > %g", w, r->behind_right, bound);
    cr_expect(r->peak >= 0.98 * a, "w = %g: transmitted peak %g", w, r->peak);
    cr_expect(fabs(r->end / r->e0 - 1.0) <= 1e-4, "w = %g: energy after both crossings %g of E0", w, r->end / r->e0 - 1.0);
    cr_expect(r->worst_in_pd <= 0.25 * pow(delta / w, 2), "w = %g: energy in the PD part off by %g", w, r->worst_in_pd);
  }
}
