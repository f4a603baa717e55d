/* A horizon per node (docs/variable_horizon.md): the families against a brute-force search of
 * the rule "bonded within max(delta_i, delta_j) with the partial-volume ramp", their symmetry
 * and the reverse bonds, the default coupling region, and a short run of the per-node models
 * with the partial stress (under the sanitizers: every array the coupling reads). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include "peri/horizon_field.h"
#include "peri/setup.h"
#include "peri/solver.h"
#include "support.h"

static const char *const plate_deck =
    "dimension: 2\n"
    "plane: stress\n"
    "materials:\n  m: {model: %s, density: 2700, youngs_modulus: 70e9, poisson_ratio: 0.3, critical_stretch: 0.01}\n"
    "discretization:\n  spacing: 1.0e-3\n  thickness: 1.0e-3\n  horizon: \"x < 0.01 ? 0.0021 : 0.00345\"\n"
    "  fill: [{shape: rectangle, min: [0.0, 0.0], max: [0.02, 0.012]}]\n"
    "boundary_conditions:\n  - {type: initial_velocity, region: all, x: \"0.5 * exp(-((x - 0.006) / 0.002)^2)\"}\n"
    "solver: {type: explicit, steps: 20}\n"
    "output: {picture: false}\n";

static void build(peri_sim *s, const char *model) {
  char deck[2048];
  snprintf(deck, sizeof deck, plate_deck, model);
  cr_assert_eq(sim_from_string(s, deck), 0);
  cr_assert_not_null(s->disc.horizon_field);
}

Test(horizon_field, families_follow_the_larger_horizon) {
  peri_sim s;
  build(&s, "pmb");
  const peri_particles *p = &s.disc.p;
  const peri_bonds *b = &s.disc.bonds;
  const peri_horizon_field *h = s.disc.horizon_field;
  cr_assert_float_eq(h->min, 0.0021, 1e-15);
  cr_assert_float_eq(h->max, 0.00345, 1e-15);
  for (int32_t i = 0; i < p->n_owned; ++i) {
    int64_t expected = 0;
    for (int32_t j = 0; j < p->n; ++j) {
      if (j == i) continue;
      const double r = peri_bond_length(p->x, i, j), d = fmax(h->delta[i], h->delta[j]);
      /* linear rule: beta = 1/2 + (d - r)/dx > 0 (the horizons are chosen so that no lattice
       * distance lies at d + dx/2, where rounding would decide) */
      const bool bonded = r < d + 0.5e-3 - 1e-12;
      expected += bonded;
      const int64_t k = peri_bonds_find(b, i, j);
      cr_assert_eq(k >= 0, bonded, "pair %d %d at %g (horizons %g %g)", i, j, r, h->delta[i], h->delta[j]);
      if (k >= 0) {
        cr_assert_eq(b->neighbor[h->reverse[k]], i, "reverse of %d -> %d", i, j);
        cr_assert_eq(h->reverse[h->reverse[k]], k);
      }
    }
    cr_assert_eq(b->offset[i + 1] - b->offset[i], expected, "family size of node %d", i);
    /* the default coupling region: some bonded node has another horizon */
    bool differs = false;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) differs |= h->delta[b->neighbor[k]] != h->delta[i];
    cr_assert_eq(h->coupled[i] != 0, differs, "coupled flag of node %d", i);
  }
  cr_assert_gt(h->n_coupled, 0);
  peri_sim_free(&s);
}

/* 20 explicit steps of a velocity pulse with breaking on, PMB and LPS: finite forces and
 * energies (the 2D run is too short to show the growth docs/variable_horizon.md reports). */
static void short_run(const char *model) {
  peri_sim s;
  build(&s, model);
  peri_apply_initial_conditions(&s);
  cr_assert_eq(peri_solve_explicit(&s, NULL, NULL), 0);
  double *W = calloc((size_t)s.disc.p.n, sizeof(double));
  s.mat.model->energy(&s, W);
  for (int32_t i = 0; i < s.disc.p.n_owned; ++i) {
    cr_assert(isfinite(W[i]) && W[i] >= 0.0, "W[%d] = %g", i, W[i]);
    for (int a = 0; a < 3; ++a) cr_assert(isfinite(s.disc.p.f[3 * i + a]));
  }
  free(W);
  peri_sim_free(&s);
}

Test(horizon_field, pmb_run) { short_run("pmb"); }
Test(horizon_field, lps_run) { short_run("lps"); }
