/* Explicit dynamics: wave speed in a bar (docs/verification.md Elasticity 3) and energy
 * conservation of a freely vibrating body (Elasticity 5). */
#include <criterion/criterion.h>
#include <math.h>
#include "peri/energies.h"
#include "peri/setup.h"
#include "peri/solver.h"
#include "support.h"

/* A 1D steel bar, 2 m long, dx = 1 mm, m = 3; a Gaussian displacement bump of width
 * 20 mm (>> delta, so dispersion is negligible) at x = 0.5 m splits into two pulses that
 * travel at c0 = sqrt(E/rho). */
static const char *bar_deck =
    "dimension: 1\n"
    "materials:\n"
    "  steel: {model: %s, density: 7850, youngs_modulus: 200e9%s}\n"
    "discretization:\n"
    "  spacing: 1e-3\n"
    "  m: 3\n"
    "  fill: [{shape: interval, min: [0], max: [2]}]\n"
    "boundary_conditions:\n"
    "  - {type: initial_displacement, region: all, x: \"1e-6*exp(-((x-0.5)/0.02)^2)\"}\n"
    "solver: {type: explicit, end_time: %g, breaking: false}\n"
    "output: {picture: false}\n";

static double pulse_peak(const peri_sim *s, double from) {
  /* position of the maximum of u for x > from, refined by a parabola through 3 nodes */
  int32_t best = -1;
  for (int32_t i = 0; i < s->disc.p.n_owned; ++i)
    if (s->disc.p.x[3 * i] > from && (best < 0 || s->disc.p.u[3 * i] > s->disc.p.u[3 * best])) best = i;
  double dx = 1e-3, xm = s->disc.p.x[3 * best];
  double um = 0, up = 0, u0 = s->disc.p.u[3 * best];
  for (int32_t i = 0; i < s->disc.p.n_owned; ++i) {
    if (fabs(s->disc.p.x[3 * i] - (xm - dx)) < 1e-9) um = s->disc.p.u[3 * i];
    if (fabs(s->disc.p.x[3 * i] - (xm + dx)) < 1e-9) up = s->disc.p.u[3 * i];
  }
  return xm + 0.5 * dx * (um - up) / (um - 2 * u0 + up);
}

static void check_wave_speed(const char *model, const char *extra) {
  const double c0 = sqrt(200e9 / 7850.0), t_end = 150e-6;
  char deck[2048];
  snprintf(deck, sizeof deck, bar_deck, model, extra, t_end);
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0);
  peri_apply_initial_conditions(&s);
  cr_assert_eq(peri_solve_explicit(&s, NULL, NULL), 0);
  double travelled = pulse_peak(&s, 0.5) - 0.5;
  double speed = travelled / s.state.time;
  cr_expect(fabs(speed / c0 - 1.0) < 0.02, "%s: wave speed %g, c0 = %g (%.2f%%)", model, speed, c0,
            100 * (speed / c0 - 1));
  peri_sim_free(&s);
}

Test(dynamics, wave_speed_pmb_1d) { check_wave_speed("pmb", ""); }
Test(dynamics, wave_speed_lps_1d) { check_wave_speed("lps", ", poisson_ratio: 0.3"); }
Test(dynamics, wave_speed_osb_mo_1d) { check_wave_speed("osb_mo", ", poisson_ratio: 0.3"); }

/* A free 2D plate (or 3D block) with a smooth initial velocity field vibrates without
 * damage; velocity-Verlet is symplectic, so kinetic + strain energy stays within 0.1%
 * over 10^4 steps at the (safety-factored) stable time step. Its energy error oscillates
 * with relative amplitude ~ (omega dt)^2/8 for the excited mode omega ~ c pi / L, with
 * dt ~ 0.8 dx / c: the body must span L >= 40 dx for that to be below 1e-3. */
static const char *vibration_deck =
    "dimension: %d\n"
    "%s"
    "materials:\n"
    "  m: {model: %s, density: 2000, youngs_modulus: 10e9, poisson_ratio: %s}\n"
    "discretization:\n"
    "  spacing: 1e-3\n"
    "  m: 3\n"
    "  fill: [{shape: box, min: [0, 0, 0], max: [%s]}]\n"
    "boundary_conditions:\n"
    "  - {type: initial_velocity, region: all, %s}\n"
    "solver: {type: explicit, steps: 10000, breaking: false, safety_factor: %s}\n"
    "output: {picture: false}\n";

static double total_energy(peri_sim *s) { return peri_kinetic_energy(s) + peri_strain_energy(s); }

typedef struct drift { double e0, worst; } drift;

static int track(peri_sim *s, void *ctx) {
  drift *d = ctx;
  if (s->state.step % 100 == 0) {
    double e = total_energy(s);
    d->worst = fmax(d->worst, fabs(e / d->e0 - 1.0));
  }
  return 0;
}

static void check_energy(int dim, const char *model, const char *nu, const char *size, const char *velocity,
                         const char *safety) {
  char deck[2048];
  snprintf(deck, sizeof deck, vibration_deck, dim, dim == 2 ? "plane: stress\n" : "", model, nu, size, velocity,
           safety);
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0);
  peri_apply_initial_conditions(&s);
  s.mat.model->force(&s);
  drift d = {total_energy(&s), 0.0};
  cr_assert_eq(peri_solve_explicit(&s, track, &d), 0);
  cr_expect(d.worst < 1e-3, "%dD %s: energy drift %.3g over %ld steps", dim, model, d.worst, s.state.step);
  cr_expect(peri_strain_energy(&s) > 1e-3 * d.e0, "the body must actually deform");
  peri_sim_free(&s);
}

static const char *plate_velocity = "x: \"0.1*sin(pi*y/0.04)\", y: \"0.1*cos(pi*x/0.04)\"";
Test(dynamics, energy_conservation_pmb_2d) {
  check_energy(2, "pmb", "0.3333333333333333", "0.04, 0.04", plate_velocity, "0.8");
}
Test(dynamics, energy_conservation_lps_2d) { check_energy(2, "lps", "0.25", "0.04, 0.04", plate_velocity, "0.8"); }
/* 3D: a 40 x 4 x 4 bar in its first longitudinal mode keeps the node count small. Its
 * thin cross-section puts lateral (Poisson) modes near the highest grid frequency, whose
 * (omega dt)^2 energy oscillation is 0.15% at safety 0.8; at safety 0.5 it is 2.56x smaller. */
Test(dynamics, energy_conservation_lps_3d) {
  check_energy(3, "lps", "0.3", "0.04, 0.004, 0.004", "x: \"0.1*cos(pi*x/0.04)\"", "0.5");
}
