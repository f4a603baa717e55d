/* Thermal strain in the mechanics (docs/model_reference.md 9): a body at the free-expansion displacement
 * u = eps x, eps = alpha dT ((1 + nu) alpha dT in plane strain), carries no force in PMB,
 * LPS and osb_mo, 1D, 2D and 3D; a 1D bar held at u = 0 carries the stress -E alpha dT. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include "peri/heat.h"
#include "peri/model.h"
#include "peri/setup.h"
#include "peri/thermal.h"
#include "support.h"

static const char *deck =
    "dimension: %d\n"
    "%s"
    "materials:\n"
    "  m: {model: %s, density: 7850, youngs_modulus: 200e9, %s conductivity: 50, specific_heat: 450,"
    " thermal_expansion: 1.2e-5}\n"
    "discretization: {spacing: 0.001, m: 3, fill: [{shape: box, min: [0, 0, 0], max: [%s]}]}\n"
    "thermal: {initial_temperature: 120, reference_temperature: 20, coupling: one_way}\n"
    "solver: {type: explicit, steps: 1}\n"
    "output: {picture: false}\n";

static void build(peri_sim *s, int dim, const char *plane, const char *model, const char *nu, const char *extent) {
  char text[4096];
  snprintf(text, sizeof text, deck, dim, plane, model, nu, extent);
  cr_assert_eq(sim_from_string(s, text), 0, "deck:\n%s", text);
}

static double max_force(const peri_sim *s) {
  double m = 0.0;
  for (int32_t i = 0; i < s->disc.p.n_owned; ++i)
    for (int d = 0; d < 3; ++d) m = fmax(m, fabs(s->disc.p.f[3 * i + d]));
  return m;
}

static void check_free(int dim, const char *plane, const char *model, const char *nu, const char *extent) {
  peri_sim s;
  build(&s, dim, plane, model, nu, extent);
  const double dT = 100.0, alpha = 1.2e-5;
  const bool strain = s.disc.geom.dim == 2 && s.disc.geom.plane == PERI_PLANE_STRAIN;
  const double eps = (strain ? 1.0 + s.mat.materials[0].nu : 1.0) * alpha * dT;
  /* held at u = 0 the body pushes out: the reference force scale */
  s.mat.model->force(&s);
  const double held = max_force(&s);
  cr_expect(held > 0.0);
  for (int32_t i = 0; i < s.disc.p.n_owned; ++i)
    for (int d = 0; d < dim; ++d) s.disc.p.u[3 * i + d] = eps * s.disc.p.x[3 * i + d];
  s.mat.model->force(&s);
  const double free_force = max_force(&s);
  cr_expect(free_force <= 1e-9 * held, "%s %dD%s: force %g at free expansion (held: %g)", model, dim, plane,
            free_force, held);
  peri_sim_free(&s);
}

Test(thermal_mech, free_expansion_no_force) {
  check_free(1, "", "pmb", "", "0.03");
  check_free(1, "", "lps", "poisson_ratio: 0.3,", "0.03");
  check_free(2, "plane: stress\n", "pmb", "", "0.02, 0.015");
  check_free(2, "plane: strain\n", "pmb", "", "0.02, 0.015");
  check_free(2, "plane: stress\n", "lps", "poisson_ratio: 0.3,", "0.02, 0.015");
  check_free(2, "plane: strain\n", "lps", "poisson_ratio: 0.3,", "0.02, 0.015");
  check_free(3, "", "pmb", "", "0.008, 0.007, 0.006");
  check_free(3, "", "lps", "poisson_ratio: 0.3,", "0.008, 0.007, 0.006");
  /* osb_mo (docs/models.md 3.6: theta^m without n alpha_T dT, the 2D a2 erratum-corrected) */
  check_free(1, "", "osb_mo", "poisson_ratio: 0.3,", "0.03");
  check_free(2, "plane: stress\n", "osb_mo", "poisson_ratio: 0.3,", "0.02, 0.015");
  check_free(2, "plane: strain\n", "osb_mo", "poisson_ratio: 0.3,", "0.02, 0.015");
  check_free(3, "", "osb_mo", "poisson_ratio: 0.3,", "0.008, 0.007, 0.006");
}

/* 1D bar held at u = 0: the force the right part exerts on the left part, sum over the
 * left nodes of f_i V_i, is sigma A with sigma = -E alpha dT (exact on the lattice: the
 * linear partial volumes integrate sum k beta exactly in 1D). */
static void check_constrained_bar(const char *model, const char *nu) {
  peri_sim s;
  build(&s, 1, "", model, nu, "0.05");
  s.mat.model->force(&s);
  double sum = 0.0;
  for (int32_t i = 0; i < s.disc.p.n_owned; ++i)
    if (s.disc.p.x[3 * i] < 0.025) sum += s.disc.p.f[3 * i] * s.disc.p.volume[i];
  const double sigma = sum / s.disc.geom.cross_section, expected = -200e9 * 1.2e-5 * 100.0;
  cr_expect(fabs(sigma / expected - 1.0) < 1e-9, "%s: stress %.10g, expected -E alpha dT = %.10g", model, sigma,
            expected);
  peri_sim_free(&s);
}

Test(thermal_mech, constrained_bar_stress) {
  check_constrained_bar("pmb", "");
  check_constrained_bar("lps", "poisson_ratio: 0.3,");
  check_constrained_bar("osb_mo", "poisson_ratio: 0.3,");
}

/* Without a thermal section nothing changes: no thermal strain array, no thermal state. */
Test(thermal_mech, no_thermal_section_no_thermal_state) {
  const char *mech =
      "dimension: 2\nmaterials:\n  m: {model: pmb, density: 7850, youngs_modulus: 200e9}\n"
      "discretization: {spacing: 0.001, m: 3, fill: [{shape: box, min: [0, 0], max: [0.01, 0.01]}]}\n"
      "solver: {type: explicit, steps: 1}\noutput: {picture: false}\n";
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, mech), 0);
  cr_expect(s.thermal == NULL && s.state.thermal_strain == NULL);
  peri_sim_free(&s);
}

/* Two-way coupling: a broken mechanical bond stops conducting; one-way: it keeps
 * conducting (only pre-cracks and growing cracks cut heat flow). */
Test(thermal_mech, broken_bonds_and_coupling) {
  const char *coupled =
      "dimension: 2\nmaterials:\n  m: {model: pmb, density: 1000, youngs_modulus: 1e9, conductivity: 100,"
      " specific_heat: 1000}\n"
      "discretization: {spacing: 0.001, m: 3, fill: [{shape: box, min: [0, 0], max: [0.02, 0.01]}]}\n"
      "thermal: {initial_temperature: \"x < 0.01 ? 100 : 0\", coupling: %s}\n"
      "solver: {type: explicit, steps: 1}\noutput: {picture: false}\n";
  for (int mode = 0; mode < 2; ++mode) {
    char text[2048];
    snprintf(text, sizeof text, coupled, mode == 0 ? "two_way" : "one_way");
    peri_sim s;
    cr_assert_eq(sim_from_string(&s, text), 0);
    /* the mechanics breaks every bond across x = 0.01 */
    for (int32_t i = 0; i < s.disc.p.n_owned; ++i)
      for (int64_t k = s.disc.bonds.offset[i]; k < s.disc.bonds.offset[i + 1]; ++k) {
        int32_t j = s.disc.bonds.neighbor[k];
        if ((s.disc.p.x[3 * i] < 0.01) != (s.disc.p.x[3 * j] < 0.01)) s.disc.bonds.broken[k] = 1;
      }
    for (int k = 0; k < 20; ++k) cr_assert_eq(peri_thermal_step(&s, s.thermal->dt), 0);
    double cold = 0.0;
    for (int32_t i = 0; i < s.disc.p.n_owned; ++i)
      if (s.disc.p.x[3 * i] > 0.01) cold = fmax(cold, s.thermal->T[i]);
    if (mode == 0) cr_expect(cold == 0.0, "two_way: heat crossed broken bonds (max T %g)", cold);
    else cr_expect(cold > 1.0, "one_way: heat should cross (max T %g)", cold);
    peri_sim_free(&s);
  }
}
