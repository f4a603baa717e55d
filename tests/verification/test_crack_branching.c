/* Dynamic crack branching in soda-lime glass (docs/verification.md case 8; Ha & Bobaru 2010):
 * the quickstart deck. The crack runs from the notch, branches into two branches on
 * either side of y = 0, and its tip never outruns the Rayleigh wave speed. */
#include <criterion/criterion.h>
#include <math.h>
#include "peri/damage.h"
#include "peri/damage_index.h"
#include "peri/setup.h"
#include "peri/solver.h"

typedef struct tip_track {
  double *phi;
  double last_t, last_x, max_speed, first_x;
} tip_track;

/* crack tip: the largest x of a node with damage >= 0.4 near the crack path */
static double tip_x(const peri_sim *s, double *phi) {
  peri_damage_index(s, phi);
  double x = -INFINITY;
  for (int32_t i = 0; i < s->disc.p.n_owned; ++i)
    if (phi[i] >= 0.4 && fabs(s->disc.p.x[3 * i + 1]) < 0.019) x = fmax(x, s->disc.p.x[3 * i]);
  return x;
}

static int sample(peri_sim *s, void *ctx) {
  tip_track *t = ctx;
  if (s->state.step % 40) return 0;
  double x = tip_x(s, t->phi);
  if (t->last_t > 0.0 && x > t->last_x) t->max_speed = fmax(t->max_speed, (x - t->last_x) / (s->state.time - t->last_t));
  t->last_t = s->state.time;
  t->last_x = x;
  return 0;
}

Test(fracture, glass_crack_branching, .timeout = 300) {
  peri_sim s;
  cr_assert_eq(peri_sim_from_deck(&s, "examples/quickstart.yaml"), 0);
  tip_track t = {.phi = malloc(sizeof(double) * s.disc.p.n)};
  peri_apply_initial_conditions(&s);
  t.first_x = tip_x(&s, t.phi);
  cr_assert_eq(peri_solve_explicit(&s, sample, &t), 0);

  /* Rayleigh speed c_R = c_s (0.862 + 1.14 nu)/(1 + nu) (Viktorov), c_s = sqrt(mu/rho),
   * nu = 1/3 for bond-based plane stress: 3099 m/s for E = 72 GPa, rho = 2440. */
  const double E = 72e9, rho = 2440.0, nu = 1.0 / 3.0;
  const double cs = sqrt(E / (2.0 * (1.0 + nu)) / rho);
  const double cR = cs * (0.862 + 1.14 * nu) / (1.0 + nu);
  cr_log_info("tip speed max %.0f m/s (c_R %.0f), crack ran %.1f mm", t.max_speed, cR, 1e3 * (t.last_x - t.first_x));
  cr_expect(t.max_speed > 0.0, "the crack must grow");
  cr_expect(t.max_speed < cR, "crack tip speed %.0f m/s exceeds the Rayleigh speed %.0f m/s", t.max_speed, cR);

  /* two branches: damaged nodes well above and well below the notch line, ahead of the
   * branching point, roughly symmetric (their extents within a factor 2) */
  peri_damage_index(&s, t.phi);
  double up = 0.0, down = 0.0;
  for (int32_t i = 0; i < s.disc.p.n_owned; ++i) {
    if (t.phi[i] < 0.4 || s.disc.p.x[3 * i] < 0.0) continue;
    double y = s.disc.p.x[3 * i + 1];
    if (fabs(y) > 0.019) continue; /* not the loaded edges */
    up = fmax(up, y);
    down = fmax(down, -y);
  }
  cr_log_info("branches reach y = +%.1f mm and -%.1f mm", 1e3 * up, 1e3 * down);
  cr_expect(up > 0.005 && down > 0.005, "branches reach y = %+.1f mm and %+.1f mm", 1e3 * up, -1e3 * down);
  cr_expect(up < 2.0 * down && down < 2.0 * up, "branches not roughly symmetric: %.1f vs %.1f mm", 1e3 * up,
            1e3 * down);
  cr_expect(t.last_x - t.first_x > 0.02, "the crack ran %.1f mm", 1e3 * (t.last_x - t.first_x));
  free(t.phi);
  peri_sim_free(&s);
}
