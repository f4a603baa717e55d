/* Stress recovery (docs/model_reference.md 10) and the plate with a hole (docs/verification.md Elasticity 6).
 *  - Homogeneous deformation u = H x: the nonlocal deformation gradient is exact at every
 *    node (A = (I + H) K), so the strain equals sym(H) to round-off; the PD stress of
 *    nodes more than 2 delta inside equals the classical C : eps within 1% at m = 5 (the
 *    quadrature accuracy of the discrete sums, as the energy of docs/verification.md
 *    Elasticity 1).
 *  - Von Mises and principal stresses of known tensors, exactly.
 *  - Plate with a hole at a small size (delta = 3 mm, m = 3): far-field stress within 2%
 *    of the applied 1 MPa; SCF symmetric top/bottom; SCF between the horizon-averaged
 *    classical value (2.87: the Kirsch profile, scaled to the finite-width 3.7, averaged over
 *    the half-disk family of the hole-top node, whose centroid lies 4 delta/(3 pi) = 1.27 mm
 *    above the edge) less 5%, and 3.7 + 10%; ADR and NLCG agree on the maximum von Mises
 *    stress within 1%. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <time.h>
#include "peri/probe.h"
#include "peri/quasistatic.h"
#include "peri/setup.h"
#include "peri/stress.h"
#include "support.h"

static const char *block2d =
    "dimension: 2\n"
    "plane: %s\n"
    "materials:\n"
    "  m: {model: lps, density: 1000, bulk_modulus: 100e9, poisson_ratio: 0.4}\n"
    "discretization:\n"
    "  spacing: 1e-3\n"
    "  m: 5\n"
    "  fill: [{shape: rectangle, min: [0, 0], max: [0.04, 0.04]}]\n"
    "solver: {type: explicit, steps: 1}\n"
    "output: {picture: false}\n";

static void check_homogeneous(const char *plane) {
  char deck[2048];
  snprintf(deck, sizeof deck, block2d, plane);
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0);
  const double H[2][2] = {{1.0e-4, 0.3e-4}, {-0.1e-4, -0.5e-4}};
  const int32_t n = s.disc.p.n_owned;
  for (int32_t i = 0; i < n; ++i)
    for (int a = 0; a < 2; ++a) s.disc.p.u[3 * i + a] = H[a][0] * s.disc.p.x[3 * i] + H[a][1] * s.disc.p.x[3 * i + 1];
  double *sig = malloc(sizeof(double) * 9 * n), *eps = malloc(sizeof(double) * 9 * n);
  cr_assert_eq(peri_stress(&s, sig), 0);
  peri_strain(&s, eps);
  const double K = 100e9, nu = 0.4, E = 3 * K * (1 - 2 * nu), mu = E / (2 * (1 + nu));
  const double e11 = H[0][0], e22 = H[1][1], e12 = 0.5 * (H[0][1] + H[1][0]);
  double s11, s22, s12 = 2 * mu * e12;
  if (!strcmp(plane, "stress")) {
    s11 = E / (1 - nu * nu) * (e11 + nu * e22);
    s22 = E / (1 - nu * nu) * (e22 + nu * e11);
  } else {
    const double lam = E * nu / ((1 + nu) * (1 - 2 * nu));
    s11 = lam * (e11 + e22) + 2 * mu * e11;
    s22 = lam * (e11 + e22) + 2 * mu * e22;
  }
  const double scale = fabs(s11) + fabs(s22) + fabs(s12), delta = s.disc.geom.horizon;
  double worst_strain = 0.0, worst_stress = 0.0;
  int interior = 0;
  for (int32_t i = 0; i < n; ++i) {
    const double *e = &eps[9 * i];
    worst_strain = fmax(worst_strain, fabs(e[0] - e11) + fabs(e[4] - e22) + fabs(e[1] - e12) + fabs(e[3] - e12));
    const double x = s.disc.p.x[3 * i], y = s.disc.p.x[3 * i + 1];
    /* the stress of i uses the dilatation of its neighbours: unaffected beyond 2 delta */
    const double d = 2 * delta + 1e-3;
    if (x < d || y < d || x > 0.04 - d || y > 0.04 - d) continue;
    const double *g = &sig[9 * i];
    worst_stress = fmax(worst_stress, (fabs(g[0] - s11) + fabs(g[4] - s22) + fabs(g[1] - s12)) / scale);
    ++interior;
  }
  cr_assert(interior > 0);
  cr_log_info("homogeneous %s: strain error %.3g (of 1e-4), interior stress error %.4f%%", plane, worst_strain,
              100 * worst_stress);
  cr_expect(worst_strain < 1e-12, "plane %s: strain from F differs from sym(H) by %g", plane, worst_strain);
  cr_expect(worst_stress < 0.01, "plane %s: interior PD stress differs from C:eps by %.3f%%", plane,
            100 * worst_stress);
  free(sig);
  free(eps);
  peri_sim_free(&s);
}

Test(stress, homogeneous_plane_stress) { check_homogeneous("stress"); }
Test(stress, homogeneous_plane_strain) { check_homogeneous("strain"); }

Test(stress, von_mises_and_principal) {
  peri_sim s = {0};
  s.disc.geom.dim = 2;
  s.disc.geom.plane = PERI_PLANE_STRESS;
  const double uni[9] = {5, 0, 0, 0, 0, 0, 0, 0, 0}, shear[9] = {0, 2, 0, 2, 0, 0, 0, 0, 0};
  cr_expect(fabs(peri_von_mises(&s, uni, 0.3) - 5.0) < 1e-12);
  cr_expect(fabs(peri_von_mises(&s, shear, 0.3) - 2.0 * sqrt(3.0)) < 1e-12);
  double pr[3];
  peri_principal_stresses(&s, shear, 0.3, pr);
  cr_expect(fabs(pr[0] - 2) < 1e-12 && fabs(pr[1]) < 1e-12 && fabs(pr[2] + 2) < 1e-12);
  /* plane strain: s33 = nu (s11 + s22); equibiaxial 1, 1 with nu = 0.5 is hydrostatic */
  s.disc.geom.plane = PERI_PLANE_STRAIN;
  const double bi[9] = {1, 0, 0, 0, 1, 0, 0, 0, 0};
  cr_expect(fabs(peri_von_mises(&s, bi, 0.5)) < 1e-12);
  /* 3D: a rotated uniaxial tension 3 along (1,1,1)/sqrt3 */
  s.disc.geom.dim = 3;
  double t[9];
  for (int a = 0; a < 9; ++a) t[a] = 1.0;
  peri_principal_stresses(&s, t, 0.3, pr);
  cr_expect(fabs(pr[0] - 3) < 1e-12 && fabs(pr[1]) < 1e-12 && fabs(pr[2]) < 1e-12, "%g %g %g", pr[0], pr[1], pr[2]);
  cr_expect(fabs(peri_von_mises(&s, t, 0.3) - 3.0) < 1e-12);
}

static double wall(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* The example deck at delta = 3 mm, m = 3, bands one horizon deep. */
static void solve_plate(peri_sim *s, const char *solver, double *seconds) {
  char type[64];
  snprintf(type, sizeof type, "solver.type=%s", solver);
  const char *sets[] = {"discretization.horizon=3e-3", "discretization.spacing=1e-3", "regions.left_edge.max=[0.003, 1]",
                        "regions.right_edge.min=[0.097, -1]", "boundary_conditions.1.layer=3e-3", type};
  cr_assert_eq(peri_sim_from_deck_with(s, "examples/plate_with_hole.yaml", 6, sets), 0);
  peri_apply_initial_conditions(s);
  double t0 = wall();
  cr_assert_eq(peri_solve_quasi_static(s, NULL, NULL), 0, "%s: not converged", solver);
  *seconds = wall() - t0;
}

static double probe(peri_sim *s, const char *q) {
  double v = NAN;
  cr_assert_eq(peri_probe(s, q, &v), 0);
  return v;
}

Test(stress, plate_with_hole_small) {
  peri_sim a, b;
  double ta, tb;
  solve_plate(&a, "nlcg", &ta);
  const double far = probe(&a, "mean:stress_xx@x=0.02");
  const double nominal = -probe(&a, "reaction_left_edge_x") / (0.05 * 1e-3);
  const double top = probe(&a, "stress_xx@0.0495,0.0355"), bottom = probe(&a, "stress_xx@0.0495,0.0145");
  const double scf = probe(&a, "max:stress_xx@x=0.0495") / far;
  const double vm_a = probe(&a, "max_von_mises");
  long it_a = a.solver.qs.iterations;
  peri_sim_free(&a);
  solve_plate(&b, "adr", &tb);
  const double vm_b = probe(&b, "max_von_mises");
  long it_b = b.solver.qs.iterations;
  peri_sim_free(&b);
  cr_log_info("plate with hole (delta 3 mm, m 3): far field %.6g Pa (nominal %.6g), SCF %.4f (top %.6g, bottom "
              "%.6g); max von Mises nlcg %.6g (%ld it, %.2f s), adr %.6g (%ld it, %.2f s), differ %.3g%%",
              far, nominal, scf, top, bottom, vm_a, it_a, ta, vm_b, it_b, tb, 100 * fabs(vm_a / vm_b - 1));
  cr_expect(fabs(far / 1e6 - 1) < 0.02, "far-field stress %g Pa, applied 1 MPa", far);
  cr_expect(fabs(top / bottom - 1) < 1e-6, "top %g and bottom %g differ (the grid is symmetric)", top, bottom);
  cr_expect(scf > 0.95 * 2.87 && scf < 1.10 * 3.7, "SCF %g outside [%g, %g]", scf, 0.95 * 2.87, 1.1 * 3.7);
  cr_expect(fabs(vm_a / vm_b - 1) < 0.01, "max von Mises: nlcg %g, adr %g", vm_a, vm_b);
}
