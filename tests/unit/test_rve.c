/* Nanocomposite RVE (docs/microstructures.md section 7): eq. 3.2, the platelet generator, the
 * homogenized moduli of eqs. 3.5-3.9 and the Monte-Carlo's independence from the thread count. */
#include <criterion/criterion.h>
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>
#include "peri/rve.h"

/* A 30 x 30 cell (L = 0.3 um, Table 3.2's third row) keeps each solve well under a second. */
static peri_rve_params small(void) {
  peri_rve_params p = peri_rve_params_default();
  p.side = 0.3e-6;
  return p;
}

Test(rve, volume_fraction_eq_3_2) {
  cr_assert_eq(peri_rve_volume_fraction(0.0, 1660, 1156.5), 0.0);
  /* equal densities: volume and weight fractions coincide */
  cr_assert_float_eq(peri_rve_volume_fraction(0.05, 1200, 1200), 0.05, 1e-15);
  /* a denser filler takes less volume than its weight share */
  cr_assert_lt(peri_rve_volume_fraction(0.05, 1660, 1156.5), 0.05);
}

Test(rve, generator_reproducible_and_count_from_eq_3_2) {
  peri_rve_params p = peri_rve_params_default();
  p.side = 0.6e-6; /* 60 x 60 */
  peri_rve_geometry a, b, c;
  cr_assert_eq(peri_rve_generate(&p, 3, &a), 0);
  cr_assert_eq(peri_rve_generate(&p, 3, &b), 0);
  cr_assert_eq(peri_rve_generate(&p, 4, &c), 0);
  const size_t bytes = (size_t)a.n * a.n * sizeof(int32_t);
  cr_assert_eq(memcmp(a.platelet, b.platelet, bytes), 0, "same seed and realization, same cell");
  cr_assert_neq(memcmp(a.platelet, c.platelet, bytes), 0, "another realization, another cell");
  /* Filler nodes closest to vol n^2: off by at most half the nodes of one platelet, which for
   * AR <= mean + 6 std covers at most sqrt(2) length/dx + 2 nodes (a diagonal run). */
  const double target = peri_rve_volume_fraction(p.weight_fraction, p.rho_filler, p.rho_matrix) * a.n * a.n;
  const double longest = sqrt(2.0) * (p.aspect_mean + 6 * p.aspect_std) * p.thickness / p.spacing + 2;
  cr_assert_leq(fabs((double)a.filler_nodes - target), longest / 2 + 1, "filler %ld, target %g",
                a.filler_nodes, target);
  long counted = 0;
  for (long i = 0; i < (long)a.n * a.n; ++i) counted += a.platelet[i] >= 0;
  cr_assert_eq(counted, a.filler_nodes);
  peri_rve_geometry_free(&a), peri_rve_geometry_free(&b), peri_rve_geometry_free(&c);
}

Test(rve, platelets_wrap_periodically) {
  /* One straight platelet of 20 spacings in a 30 x 30 cell, anywhere: with the periodic wrap it
   * always keeps all its nodes. A segment of length l at angle theta crosses between
   * l max(|cos|, |sin|)/dx (>= 20/sqrt(2), at 45 degrees) and l (|cos| + |sin|)/dx + 1
   * (<= 20 sqrt(2) + 1) cells. */
  peri_rve_params p = small();
  p.aspect_std = 0, p.max_turn = 0, p.aspect_mean = 200; /* 200 nm = 20 dx */
  p.rho_filler = p.rho_matrix, p.weight_fraction = 20.0 / 900.0;
  int crossing = 0;
  for (uint64_t k = 0; k < 40; ++k) {
    peri_rve_geometry g;
    cr_assert_eq(peri_rve_generate(&p, k, &g), 0);
    cr_assert_eq(g.platelets, 1);
    cr_assert(g.filler_nodes >= 14 && g.filler_nodes <= 30, "realization %d: %ld nodes", (int)k,
              g.filler_nodes);
    int lo = 0, hi = 0;
    for (int j = 0; j < g.n; ++j) lo |= g.platelet[j * g.n] >= 0, hi |= g.platelet[g.n - 1 + j * g.n] >= 0;
    crossing += lo && hi;
    peri_rve_geometry_free(&g);
  }
  cr_assert_gt(crossing, 0, "some platelets cross the x edges");
}

/* kappa = 1 and E_nf = E_m: every bond class has E_m, the cell is homogeneous. The discrete
 * moduli then are the lattice sums of rule (a) (linear partial-volume ramp) at m = 8 over the
 * continuum integrals: sum beta cos^4/|xi| dx^2 / (pi delta^3/4) = 1.00093 and sum beta
 * cos^2 sin^2 / sum beta cos^4 = 0.33105 (computed directly from the ramp), so E = 1.0026 E_m
 * and nu = 0.3311: E within 0.5% and nu within 1% of 1/3 are the quadrature's tolerances. */
Test(rve, homogeneous_cell_gives_the_matrix) {
  peri_rve_params p = small();
  p.kappa = 1, p.E_filler = p.E_matrix;
  peri_rve_geometry g;
  cr_assert_eq(peri_rve_generate(&p, 0, &g), 0);
  cr_assert_gt(g.platelets, 0);
  peri_rve_moduli r;
  cr_assert_eq(peri_rve_homogenize(&p, &g, &r), 0);
  cr_assert_float_eq(r.E11 / p.E_matrix, 1.0, 5e-3, "E11 = %g", r.E11);
  cr_assert_float_eq(r.E22 / p.E_matrix, 1.0, 5e-3, "E22 = %g", r.E22);
  cr_assert_float_eq(r.nu12 * 3, 1.0, 1e-2, "nu12 = %g", r.nu12);
  cr_assert_float_eq(r.nu21 * 3, 1.0, 1e-2, "nu21 = %g", r.nu21);
  peri_rve_geometry_free(&g);
}

/* Minimum potential energy under prescribed displacements grows with every bond's stiffness:
 * stiffer filler bonds (kappa = 1) cannot lower a11 below the matrix's, a soft interphase
 * (kappa = 0.1, E_nf = E_m, so every class is <= E_m) cannot raise it. E_m's own a11 is the
 * homogeneous cell's. */
Test(rve, bond_classes_bound_the_moduli) {
  peri_rve_params hom = small(), stiff = small(), soft = small();
  hom.kappa = 1, hom.E_filler = hom.E_matrix;
  stiff.kappa = 1;
  soft.E_filler = soft.E_matrix; /* kappa 0.1: interphase and agglomeration 0.1 E_m */
  peri_rve_geometry g;
  cr_assert_eq(peri_rve_generate(&hom, 1, &g), 0);
  peri_rve_moduli h, s, w;
  cr_assert_eq(peri_rve_homogenize(&hom, &g, &h), 0);
  cr_assert_eq(peri_rve_homogenize(&stiff, &g, &s), 0);
  cr_assert_eq(peri_rve_homogenize(&soft, &g, &w), 0);
  const double a11h = h.E11 / (1 - h.nu21 * h.nu21), a11s = s.E11 / (1 - s.nu21 * s.nu21);
  const double a11w = w.E11 / (1 - w.nu21 * w.nu21);
  cr_assert_gt(a11s, a11h * (1 + 1e-3), "stiff filler: %g vs %g", a11s, a11h);
  cr_assert_lt(a11w, a11h * (1 - 1e-3), "soft interphase: %g vs %g", a11w, a11h);
  peri_rve_geometry_free(&g);
}

Test(rve, monte_carlo_independent_of_threads) {
  peri_rve_params p = small();
  peri_rve_moduli one[4], two[4];
  memset(one, 0, sizeof one), memset(two, 0, sizeof two); /* padding */
  omp_set_num_threads(1);
  cr_assert_eq(peri_rve_monte_carlo(&p, 4, one), 0);
  omp_set_num_threads(2);
  cr_assert_eq(peri_rve_monte_carlo(&p, 4, two), 0);
  cr_assert_eq(memcmp(one, two, sizeof one), 0, "bit for bit");
  cr_assert(one[0].E11 != one[1].E11, "realizations differ");
  double mean, std;
  const double v[3] = {1, 2, 4};
  peri_rve_mean_std(v, 3, &mean, &std);
  cr_assert_float_eq(mean, 7.0 / 3, 1e-15);
  cr_assert_float_eq(std, sqrt(7.0 / 3), 1e-15); /* ((4/3)^2 + (1/3)^2 + (5/3)^2) / 2 = 7/3 */
}
