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
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
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

/* Switching during explicit dynamics (docs/coupling.md, "Switching during explicit dynamics"):
 * a bar of 300 m (E = rho = A = 1, c = 1 m/s, dx = 1, delta = 3 dx), 2-node bars except PD
 * nodes in [146, 154], both ends pulled apart by u = -+v0 (t - tau tanh(t / tau)) (velocity
 * v0 tanh^2(t / tau), v0 = 1e-3, tau = 20 s: a smooth front some 20 dx wide), critical stretch
 * s0 = 1.5 v0 / c, switch_radius 2, 0.2 times the stable step. Each end sends a tensile wave
 * of strain (v0 / c) tanh^2((t - |x - x_end| / c) / tau) inward; one wave (at most v0 / c)
 * never breaks a bond, the two superposed at the midpoint x = 150 reach s0 when
 * 2 tanh^2((t - 150) / tau) = 1.5, at t* = 150 + tau atanh(sqrt(0.75)) = 176.34 s. Checked:
 *  - the first bond breaks within 0.5 s of t*: the time step is 0.2 s, and a strain error of
 *    1% of s0 moves the break by 0.35 s at the front's slope there,
 *    4 (v0 / c) tanh sech^2 / tau = 0.043 (v0 / c) per s; the errors are smaller: the lumped
 *    bar's phase lag over 150 m, 150 (k dx)^2 / 24 with k = 1 / tau, is 0.016 s, a bond's
 *    stretch averages the strain over |xi| <= delta ((delta / tau)^2 / 24 = 0.1%), and the
 *    interfaces' out-of-balance radiates at most (1/27)(delta / tau)^2 = 0.08% of the wave;
 *  - the first bonds to break are about the midpoint (within 2 delta of x = 150);
 *  - the switching rule at the end: every node within 2 delta of a node that lost a bond is PD,
 *    and the PD zone grew beyond [146, 154];
 *  - the time step holds through any switch: it is the smaller of the all-FEM and all-PD
 *    steps (each node's row is its FEM or its PD row); in 1D the bar element's dx / c (the PD
 *    rows' Gershgorin step is 1.6 times longer at m = 3).
 * Without switching during the run these fail. */
static const char switching_bar[] =
    "dimension: 1\n"
    "materials:\n"
    "  bar: {model: pmb, density: 1, youngs_modulus: 1, critical_stretch: 1.5e-3}\n"
    "discretization: {spacing: 1, m: 3, cross_section: 1, placement: lattice,\n"
    "                 fill: [{shape: interval, min: [0], max: [300]}]}\n"
    "regions:\n"
    "  pd: {shape: interval, min: [145.5], max: [154.5]}\n"
    "  left_end: {shape: interval, min: [-0.5], max: [0.5]}\n"
    "  right_end: {shape: interval, min: [299.5], max: [300.5]}\n"
    "coupling: %s\n"
    "boundary_conditions:\n"
    "  - {type: displacement, region: left_end, x: \"-1e-3*(t-20*tanh(t/20))\"}\n"
    "  - {type: displacement, region: right_end, x: \"1e-3*(t-20*tanh(t/20))\"}\n"
    "solver: {type: explicit, end_time: 220, safety_factor: 0.2, breaking: %s}\n"
    "output: {frames: 0}\n";

typedef struct first_break {
  double time;
  double lo, hi; /* the span of the nodes that lost a bond at that step */
} first_break;

static int on_break(peri_sim *s, void *ctx) {
  first_break *fb = ctx;
  if (fb->time > 0.0) return 0;
  const peri_bonds *b = &s->disc.bonds;
  for (int32_t i = 0; i < s->disc.p.n; ++i)
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k)
      if (b->broken[k]) {
        fb->time = s->state.time;
        fb->lo = fmin(fb->lo, s->disc.p.x[3 * (size_t)i]);
        fb->hi = fmax(fb->hi, s->disc.p.x[3 * (size_t)i]);
      }
  return 0;
}

/* The time step of the bar with the given coupling mapping and breaking. */
static double bar_step(const char *coupling, const char *breaking) {
  char deck[2048];
  snprintf(deck, sizeof deck, switching_bar, coupling, breaking);
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0);
  const double dt = s.solver.dt;
  peri_sim_free(&s);
  return dt;
}

Test(coupling_dynamics, switching_during_a_dynamic_crack_run) {
  char deck[2048];
  snprintf(deck, sizeof deck, switching_bar, "{pd_region: pd, switch_radius: 2}", "true");
  static peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0);
  s.out.quiet = true;
  const int32_t pd_at_start = s.coupling->n_pd;
  cr_assert_eq(pd_at_start, 9, "PD nodes 146..154 at the start, got %d", pd_at_start);

  /* the step: the smaller of the all-FEM rows' (the bar element's dx / c, times the safety
   * factor) and the all-PD rows' */
  const double fem = s.solver.safety_factor * 1.0, pd = bar_step("{pd_region: all}", "false");
  cr_assert_float_eq(s.solver.dt, fmin(fem, pd), 1e-12 * pd, "step %g, all FEM %g, all PD %g", s.solver.dt, fem, pd);

  first_break fb = {0.0, INFINITY, -INFINITY};
  peri_apply_initial_conditions(&s);
  cr_assert_eq(peri_solve_explicit(&s, on_break, &fb), 0);
  const double t_star = 150.0 + 20.0 * atanh(sqrt(0.75));
  cr_expect(fb.time > 0.0, "no bond broke");
  cr_expect_leq(fabs(fb.time - t_star), 0.5, "first break at t = %g s, the waves' superposition reaches s0 at %g s",
                fb.time, t_star);
  cr_expect(fb.lo >= 150.0 - 6.0 && fb.hi <= 150.0 + 6.0, "the first broken bonds span [%g, %g], not about x = 150",
            fb.lo, fb.hi);

  /* the switching rule (brute force) */
  const peri_bonds *b = &s.disc.bonds;
  const double *x = s.disc.p.x;
  const int32_t *type = s.coupling->node_type;
  int32_t pd_count = 0;
  for (int32_t i = 0; i < s.disc.p.n; ++i) {
    pd_count += type[i] != 0;
    bool lost = false;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) lost = lost || b->broken[k];
    if (!lost) continue;
    cr_expect_eq(type[i], 1, "node at x = %g lost a bond and is FEM", x[3 * (size_t)i]);
    for (int32_t j = 0; j < s.disc.p.n; ++j)
      if (fabs(x[3 * (size_t)j] - x[3 * (size_t)i]) <= 2.0 * 3.0 + 1e-9)
        cr_expect_eq(type[j], 1, "node at x = %g lies within 2 delta of x = %g, which lost a bond, and is FEM",
                     x[3 * (size_t)j], x[3 * (size_t)i]);
  }
  cr_expect_eq(pd_count, s.coupling->n_pd);
  cr_expect_gt(pd_count, pd_at_start, "no node switched");
  peri_sim_free(&s);
}
