/* Surface correction (docs/models.md 4.1), against classical elasticity:
 * (1) a 3D bar 1 x 0.1 x 0.1 m, dx = 20 mm (5 nodes across, every node within delta of a
 *     lateral surface), E = 200 GPa, pulled by 2 MN: without correction it is about 27%
 *     stiffer than E A (docs/solvers.md); with the energy correction its gauge elongation is
 *     F L/(E A) = 1 mm within 2% (LPS nu = 0.3; PMB);
 * (2) a free plate (2D plane stress LPS, nu = 0.3) under a uniform stretch imposed on every
 *     node, u = eps (x, -nu eps y): the PD stress sigma_xx up a column at mid-length is
 *     closer to E eps with the correction than without (it does not reach 2%: see below);
 * (3) surface_correction: position_aware (Mitchell, Silling and Littlewood 2015): the bar within
 *     2% of E A for PMB and LPS, the plate column within 2% up to the surface node, and a
 *     uniform stress state recovered within 0.5% at every node of a surface-to-middle line in
 *     1D, 2D and 3D, PMB and LPS;
 * (4) the surface node on top of a circular hole: its strain-based stress moves toward the
 *     handbook concentration with position_aware (docs/verification.md case 19). */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>
#include "peri/quasistatic.h"
#include "peri/setup.h"
#include "peri/stress.h"
#include "support.h"

static const char *bar3d =
    "dimension: 3\n"
    "materials:\n"
    "  steel: {model: %s, density: 7850, youngs_modulus: 200e9%s}\n"
    "discretization:\n"
    "  spacing: 0.02\n"
    "  m: 3\n"
    "  surface_correction: %s\n"
    "  fill: [{shape: box, min: [0, 0, 0], max: [1, 0.1, 0.1]}]\n"
    "regions:\n"
    "  held: {shape: box, min: [-1, -1, -1], max: [0.02, 1, 1]}\n"
    "  pulled: {shape: box, min: [0.98, -1, -1], max: [2, 1, 1]}\n"
    "boundary_conditions:\n"
    "  - {type: displacement, region: held, x: 0, y: 0, z: 0}\n"
    "  - {type: traction, region: pulled, x: 2.0e8, layer: 0.02}\n"
    "solver: {type: adr, tolerance: 1.0e-8}\n"
    "output: {picture: false}\n";

/* Mean x-displacement of the nodes within dx/2 of the plane x = x0. */
static double section_u(const peri_sim *s, double x0) {
  double sum = 0.0;
  int count = 0;
  for (int32_t i = 0; i < s->disc.p.n_owned; ++i)
    if (fabs(s->disc.p.x[3 * i] - x0) < 0.5 * s->disc.geom.spacing + 1e-12) sum += s->disc.p.u[3 * i], ++count;
  return count ? sum / count : NAN;
}

static double bar_strain_ratio(const char *model, const char *nu, const char *correction) {
  char deck[4096];
  snprintf(deck, sizeof deck, bar3d, model, nu, correction);
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0);
  peri_apply_initial_conditions(&s);
  cr_assert_eq(peri_solve_quasi_static(&s, NULL, NULL), 0, "adr did not converge");
  const double dx = 0.02, xa = 0.25 + 0.5 * dx, xb = 0.75 + 0.5 * dx;
  const double strain = (section_u(&s, xb) - section_u(&s, xa)) / (xb - xa), expected = 2.0e6 / (200e9 * 0.01);
  cr_log_info("3D bar, %s, correction %s: gauge strain / (F/(EA)) = %.5f", model, correction, strain / expected);
  peri_sim_free(&s);
  return strain / expected;
}

Test(surface_correction, bar_3d_lps_within_2_percent_of_EA, .timeout = 600) {
  const double plain = bar_strain_ratio("lps", ", poisson_ratio: 0.3", "none");
  const double corrected = bar_strain_ratio("lps", ", poisson_ratio: 0.3", "energy");
  cr_expect(fabs(plain - 1.0) > 0.1, "without correction the skin effect is expected (ratio %g)", plain);
  cr_expect(fabs(corrected - 1.0) < 0.02, "corrected 3D LPS bar: strain %g of F/(EA)", corrected);
}

/* PMB (nu = 1/4): the correction brings the bar closer to E A than without (not to 2%:
 * docs/verification.md). */
Test(surface_correction, bar_3d_pmb_closer_to_EA, .timeout = 600) {
  const double plain = bar_strain_ratio("pmb", "", "none");
  const double corrected = bar_strain_ratio("pmb", "", "energy");
  cr_expect(fabs(corrected - 1.0) < fabs(plain - 1.0), "PMB bar: %g of F/(EA) corrected, %g without", corrected, plain);
}

/* The plate: 40 x 20 mm, dx = 1 mm, m = 3, a uniform uniaxial stress state imposed on every
 * node (prescribed displacement), and the nodal PD stress (docs/models.md, stress recovery). */
static const char *plate =
    "dimension: 2\n"
    "plane: stress\n"
    "materials:\n"
    "  steel: {model: lps, density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.3}\n"
    "discretization:\n"
    "  spacing: 1.0e-3\n"
    "  m: 3\n"
    "  thickness: 1.0e-3\n"
    "  surface_correction: %s\n"
    "  fill: [{shape: rectangle, min: [0, 0], max: [0.04, 0.02]}]\n"
    "boundary_conditions:\n"
    "  - {type: displacement, region: all, x: \"1.0e-4*x\", y: \"-0.3e-4*y\"}\n"
    "solver: {type: adr, load_steps: 1, breaking: false}\n"
    "output: {picture: false}\n";

/* The largest |sigma_xx/(E eps) - 1| over the column of nodes at mid-length (free lateral
 * surfaces above and below, far from the ends' corners). */
static double plate_column(const char *correction) {
  char deck[4096];
  snprintf(deck, sizeof deck, plate, correction);
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0);
  peri_apply_initial_conditions(&s);
  cr_assert_eq(peri_solve_quasi_static(&s, NULL, NULL), 0);
  const int32_t n = s.disc.p.n_owned;
  double *sigma = malloc(sizeof(double) * 9 * (size_t)n);
  peri_stress(&s, sigma);
  const double expected = 200e9 * 1.0e-4;
  double worst = 0.0;
  for (int32_t i = 0; i < n; ++i)
    if (fabs(s.disc.p.x[3 * i] - 0.0205) < 1e-6) {
      const double ratio = sigma[9 * (size_t)i] / expected;
      worst = fmax(worst, fabs(ratio - 1.0));
      cr_log_info("plate, correction %s, x = 20.5 mm, y = %4.1f mm: sigma_xx/(E eps) = %.4f", correction,
                  1e3 * s.disc.p.x[3 * i + 1], ratio);
    }
  free(sigma);
  peri_sim_free(&s);
  return worst;
}

/* The corrected column is closer to uniform than the plain one at every depth's worst; the
 * 2% target is not reached (docs/verification.md: the collapsed stress of the second
 * row counts the corrected bonds of the surface row). */
Test(surface_correction, plate_column_closer_to_uniform, .timeout = 600) {
  const double plain = plate_column("none");
  const double corrected = plate_column("energy");
  cr_log_info("plate column: largest deviation %.4f without correction, %.4f with", plain, corrected);
  cr_expect(corrected < plain, "the correction should bring the column closer to E eps (%g, without %g)", corrected,
            plain);
}

/* position_aware (Mitchell, Silling and Littlewood 2015): every node's energy under every
 * uniform strain is the classical one, so the bar is E A within 2% for PMB as for LPS. */
Test(surface_correction, bar_3d_position_aware_within_2_percent_of_EA, .timeout = 600) {
  const double pmb = bar_strain_ratio("pmb", "", "position_aware");
  const double lps = bar_strain_ratio("lps", ", poisson_ratio: 0.3", "position_aware");
  cr_expect(fabs(pmb - 1.0) < 0.02, "position-aware 3D PMB bar: strain %g of F/(EA)", pmb);
  cr_expect(fabs(lps - 1.0) < 0.02, "position-aware 3D LPS bar: strain %g of F/(EA)", lps);
}

/* The free plate: uniform within 2% up to the surface node. */
Test(surface_correction, plate_column_position_aware_within_2_percent, .timeout = 600) {
  const double worst = plate_column("position_aware");
  cr_expect(worst < 0.02, "position-aware plate column: largest deviation %g from E eps", worst);
}

/* position_aware in 1D, 2D and 3D, PMB and LPS: a uniform uniaxial stress state imposed on
 * every node, u = eps (x, -nu y, -nu z); the stress of every node on a line from the
 * surface to the middle (all nodes of the 1D bar, ends included) is E eps within 0.5% (the
 * factors make every node's energy, and so its collapsed stress, exact under uniform strain;
 * the ridge of position_aware.c leaves about 1e-3). */
static const char *uniform =
    "dimension: %d\n%s"
    "materials:\n"
    "  steel: {model: %s, density: 7850, youngs_modulus: 200e9%s}\n"
    "discretization:\n"
    "  spacing: 1.0e-3\n"
    "  m: 3\n"
    "%s"
    "  surface_correction: position_aware\n"
    "  fill: [{shape: %s, min: %s, max: %s}]\n"
    "boundary_conditions:\n"
    "  - {type: displacement, region: all, x: \"1.0e-4*x\"%s}\n"
    "solver: {type: adr, load_steps: 1, breaking: false}\n"
    "output: {picture: false}\n";

static double uniform_worst(int dim, const char *model, double nu) {
  char deck[4096], nu_key[64] = "", lateral[128] = "";
  if (strcmp(model, "lps") == 0) snprintf(nu_key, sizeof nu_key, ", poisson_ratio: %g", nu);
  if (dim >= 2) snprintf(lateral, sizeof lateral, ", y: \"%g*y\"%s", -nu * 1e-4, dim == 3 ? "" : "");
  if (dim == 3) snprintf(lateral + strlen(lateral), sizeof lateral - strlen(lateral), ", z: \"%g*z\"", -nu * 1e-4);
  const char *shape = dim == 1 ? "interval" : dim == 2 ? "rectangle" : "box";
  const char *lo = dim == 1 ? "[0]" : dim == 2 ? "[0, 0]" : "[0, 0, 0]";
  const char *hi = dim == 1 ? "[0.02]" : dim == 2 ? "[0.02, 0.012]" : "[0.016, 0.008, 0.008]";
  const char *size = dim == 1 ? "  cross_section: 1.0e-6\n" : dim == 2 ? "  thickness: 1.0e-3\n" : "";
  snprintf(deck, sizeof deck, uniform, dim, dim == 2 ? "plane: stress\n" : "", model, nu_key, size, shape, lo, hi,
           lateral);
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0, "deck:\n%s", deck);
  peri_apply_initial_conditions(&s);
  cr_assert_eq(peri_solve_quasi_static(&s, NULL, NULL), 0);
  const int32_t n = s.disc.p.n_owned;
  double *sigma = malloc(sizeof(double) * 9 * (size_t)n);
  peri_stress(&s, sigma);
  const double xmid = dim == 3 ? 0.0085 : 0.0105, zmid = 0.0045;
  double worst = 0.0;
  for (int32_t i = 0; i < n; ++i) {
    const double *x = &s.disc.p.x[3 * i];
    if (dim >= 2 && (fabs(x[0] - xmid) > 1e-6 || (dim == 3 && fabs(x[2] - zmid) > 1e-6))) continue;
    worst = fmax(worst, fabs(sigma[9 * (size_t)i] / (200e9 * 1e-4) - 1.0));
  }
  cr_assert(s.disc.bonds.surface_lowest >= 0.0, "a negative factor %g", s.disc.bonds.surface_lowest);
  cr_log_info("%dD %s, position_aware, uniform stress: largest |sigma_xx/(E eps) - 1| = %.2e", dim, model, worst);
  free(sigma);
  peri_sim_free(&s);
  return worst;
}

Test(surface_correction, position_aware_uniform_stress_1d_2d_3d, .timeout = 600) {
  cr_expect(uniform_worst(1, "pmb", 0.0) < 0.005);
  cr_expect(uniform_worst(1, "lps", 0.0) < 0.005);
  cr_expect(uniform_worst(2, "pmb", 1.0 / 3.0) < 0.005); /* plane stress PMB: nu = 1/3 */
  cr_expect(uniform_worst(2, "lps", 0.3) < 0.005);
  cr_expect(uniform_worst(3, "pmb", 0.25) < 0.005);
  cr_expect(uniform_worst(3, "lps", 0.3) < 0.005);
}

/* The circular hole (docs/verification.md case 19) at its coarsest size: radius a = 10 mm in a
 * square plate 10a wide, delta/a = 0.4, m = 3 (5604 nodes), LPS plane stress nu = 0.4, the
 * left band held, 1 MPa on the right band. The measured quantity is sigma_xx of the surface
 * node on top of the hole (the first node above it, next to the centre line) from the node's
 * strain, the nonlocal deformation gradient (docs/model_reference.md 10), through plane-stress
 * Hooke: E (eps_xx + nu eps_yy)/(1 - nu^2). Its classical value is the handbook concentration
 * for this width (Heywood, gross section, d/W = 0.2: 3.13). */
static const char *hole =
    "dimension: 2\n"
    "plane: stress\n"
    "materials:\n"
    "  steel: {model: lps, density: 7800, bulk_modulus: 100.0e9, poisson_ratio: 0.4}\n"
    "discretization:\n"
    "  spacing: 0.001333333333\n"
    "  horizon: 0.004\n"
    "  thickness: 1.0e-3\n"
    "  origin: [0.05, 0.05]\n"
    "  surface_correction: %s\n"
    "  fill: [{shape: rectangle, min: [0, 0], max: [0.1, 0.1]}]\n"
    "  remove: [{shape: circle, center: [0.05, 0.05], radius: 0.01}]\n"
    "regions:\n"
    "  left_edge: {shape: rectangle, min: [-1, -1], max: [0.004, 1]}\n"
    "  right_edge: {shape: rectangle, min: [0.096, -1], max: [1, 1]}\n"
    "boundary_conditions:\n"
    "  - {type: displacement, region: left_edge, x: 0, y: 0}\n"
    "  - {type: traction, region: right_edge, x: 1.0e6, layer: 0.004}\n"
    "solver: {type: nlcg, tolerance: 1.0e-8, breaking: false}\n"
    "output: {picture: false}\n";

static double hole_surface_concentration(const char *correction) {
  char deck[4096];
  snprintf(deck, sizeof deck, hole, correction);
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0);
  peri_apply_initial_conditions(&s);
  cr_assert_eq(peri_solve_quasi_static(&s, NULL, NULL), 0, "nlcg did not converge");
  const double dx = 0.001333333333, qx = 0.05 + 0.5 * dx, qy = 0.06 + 0.3 * dx;
  int32_t node = 0;
  double best = INFINITY;
  for (int32_t i = 0; i < s.disc.p.n_owned; ++i) {
    const double d = hypot(s.disc.p.x[3 * i] - qx, s.disc.p.x[3 * i + 1] - qy);
    if (d < best) best = d, node = i;
  }
  double *eps = malloc(sizeof(double) * 9 * (size_t)s.disc.p.n_owned);
  peri_strain(&s, eps);
  const double E = s.mat.materials[0].E, nu = s.mat.materials[0].nu;
  const double *e = &eps[9 * (size_t)node];
  const double concentration = E / (1.0 - nu * nu) * (e[0] + nu * e[4]) / 1.0e6;
  cr_log_info("hole, delta/a = 0.4, correction %s: surface node at r/a = %.4f, strain-based sigma_xx/sigma = %.4f",
              correction, hypot(s.disc.p.x[3 * node] - 0.05, s.disc.p.x[3 * node + 1] - 0.05) / 0.01, concentration);
  free(eps);
  peri_sim_free(&s);
  return concentration;
}

/* With the correction the surface node's concentration moves toward the handbook 3.13 (it
 * stays below it: the family reaches into material where the stress has fallen). */
Test(surface_correction, hole_surface_node_moves_toward_handbook, .timeout = 600) {
  const double handbook = 3.13; /* Heywood, d/W = 0.2 (Pilkey, Peterson's Stress Concentration Factors) */
  const double plain = hole_surface_concentration("none");
  const double corrected = hole_surface_concentration("position_aware");
  cr_expect(fabs(corrected - handbook) < fabs(plain - handbook),
            "the corrected surface node (%g) should be nearer 3.13 than the uncorrected one (%g)", corrected, plain);
  cr_expect(corrected < handbook, "a one-sided family in a falling field reads below the edge value (%g)", corrected);
}
