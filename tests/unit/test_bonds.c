/* Bond families: family sizes on regular grids, the LAMMPS example, partial volumes,
 * symmetry, agreement with a brute-force search, thread-count independence. */
#include <criterion/criterion.h>
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>
#include "peri/bonds.h"
#include "peri/discretize.h"
#include "peri/region.h"

static peri_shape box_shape(double lo0, double lo1, double lo2, double hi0, double hi1,
                            double hi2) {
  peri_shape s;
  memset(&s, 0, sizeof s);
  s.kind = PERI_SHAPE_BOX;
  s.min[0] = lo0, s.min[1] = lo1, s.min[2] = lo2;
  s.max[0] = hi0, s.max[1] = hi1, s.max[2] = hi2;
  return s;
}

/* Lattice grid dx = 1 over [-h, h]^dim. */
static void unit_lattice(peri_particles *p, int dim, double h) {
  peri_fill fill = {.shape = box_shape(-h, -h, -h, h, h, h), .material = 0};
  peri_grid_params g = {.dim = dim,
                        .spacing = 1.0,
                        .placement = PERI_PLACE_LATTICE,
                        .thickness = 1,
                        .cross_section = 1,
                        .n_fill = 1,
                        .fill = &fill};
  cr_assert_gt(peri_grid_generate(p, &g), 0);
}

static int32_t nearest(const peri_particles *p, const double c[3]) {
  int32_t best = -1;
  double bd = INFINITY;
  for (int32_t i = 0; i < p->n; i++) {
    double d2 = 0;
    for (int d = 0; d < 3; d++) d2 += (p->x[3 * i + d] - c[d]) * (p->x[3 * i + d] - c[d]);
    if (d2 < bd) bd = d2, best = i;
  }
  return best;
}

static void check_family_sizes(int dim, const double *m, const int64_t *expect, int count) {
  peri_particles p;
  unit_lattice(&p, dim, 6);
  const double c[3] = {0, 0, 0};
  int32_t i = nearest(&p, c);
  for (int k = 0; k < count; k++) {
    peri_family_params fp = {
        .horizon = m[k], .spacing = 1, .rule = PERI_PV_NONE, .influence = PERI_INFLUENCE_CONSTANT};
    peri_bonds b;
    peri_bonds_build(&b, &p, &fp);
    cr_expect_eq(b.offset[i + 1] - b.offset[i], expect[k], "%dD m=%g: family %lld, expected %lld",
                 dim, m[k], (long long)(b.offset[i + 1] - b.offset[i]), (long long)expect[k]);
    peri_bonds_free(&b);
  }
  peri_particles_free(&p);
}

Test(bonds, family_sizes_3d) {
  const double m[] = {2.015, 3.015, 4.015, 5.0};
  const int64_t e[] = {32, 122, 256, 514};
  check_family_sizes(3, m, e, 4);
}

Test(bonds, family_sizes_2d) {
  const double m[] = {2.015, 3.015, 4.015, 5.0};
  const int64_t e[] = {12, 28, 48, 80};
  check_family_sizes(2, m, e, 4);
}

Test(bonds, family_sizes_1d) {
  const double m[] = {1.0, 3.015, 5.0};
  const int64_t e[] = {2, 6, 10};
  check_family_sizes(1, m, e, 3);
}

/* LAMMPS peri example: sc lattice a = 0.5 mm, cylinder of radius 5 mm along y, y in
 * [-5, 0] mm, horizon 1.5001 mm. */
Test(bonds, lammps_cylinder) {
  peri_fill fill;
  memset(&fill, 0, sizeof fill);
  fill.shape.kind = PERI_SHAPE_CYLINDER;
  fill.shape.axis = 1;
  fill.shape.center[1] = -0.005;
  fill.shape.radius = 0.005;
  fill.shape.top_radius = 0.005;
  fill.shape.length = 0.005;
  peri_grid_params g = {.dim = 3,
                        .spacing = 0.5e-3,
                        .placement = PERI_PLACE_LATTICE,
                        .origin_given = true,
                        .n_fill = 1,
                        .fill = &fill};
  peri_particles p;
  cr_assert_eq(peri_grid_generate(&p, &g), 3487);
  cr_assert_eq(p.n, 3487);
  cr_assert_float_eq(p.volume[0], 0.125e-9, 1e-22);
  const peri_partial_volume rules[] = {PERI_PV_LAMMPS, PERI_PV_NONE};
  for (int r = 0; r < 2; r++) {
    peri_family_params fp = {.horizon = 0.0015001,
                             .spacing = 0.5e-3,
                             .rule = rules[r],
                             .influence = PERI_INFLUENCE_CONSTANT};
    peri_bonds b;
    peri_bonds_build(&b, &p, &fp);
    cr_expect_eq(b.n_bonds, 335966, "rule %d: %lld bonds", (int)rules[r], (long long)b.n_bonds);
    cr_expect_eq(b.offset[b.n_nodes], b.n_bonds);
    peri_bonds_free(&b);
  }
  peri_particles_free(&p);
}

Test(bonds, partial_volume_factor) {
  const double d = 3, dx = 1;
  cr_expect_float_eq(peri_partial_volume_factor(PERI_PV_NONE, 3.0, d, dx), 1.0, 1e-15);
  cr_expect_float_eq(peri_partial_volume_factor(PERI_PV_NONE, 3.0 + 1e-9, d, dx), 0.0, 1e-15);
  cr_expect_float_eq(peri_partial_volume_factor(PERI_PV_NONE, 0.5, d, dx), 1.0, 1e-15);

  cr_expect_float_eq(peri_partial_volume_factor(PERI_PV_LINEAR, 2.0, d, dx), 1.0, 1e-15);
  cr_expect_float_eq(peri_partial_volume_factor(PERI_PV_LINEAR, 2.5, d, dx), 1.0, 1e-15);
  cr_expect_float_eq(peri_partial_volume_factor(PERI_PV_LINEAR, 2.75, d, dx), 0.75, 1e-15);
  cr_expect_float_eq(peri_partial_volume_factor(PERI_PV_LINEAR, 3.0, d, dx), 0.5, 1e-15);
  cr_expect_float_eq(peri_partial_volume_factor(PERI_PV_LINEAR, 3.25, d, dx), 0.25, 1e-15);
  cr_expect_float_eq(peri_partial_volume_factor(PERI_PV_LINEAR, 3.5, d, dx), 0.0, 1e-15);
  cr_expect_float_eq(peri_partial_volume_factor(PERI_PV_LINEAR, 4.0, d, dx), 0.0, 1e-15);

  cr_expect_float_eq(peri_partial_volume_factor(PERI_PV_LAMMPS, 2.5, d, dx), 1.0, 1e-15);
  cr_expect_float_eq(peri_partial_volume_factor(PERI_PV_LAMMPS, 2.75, d, dx), 0.75, 1e-15);
  cr_expect_float_eq(peri_partial_volume_factor(PERI_PV_LAMMPS, 3.0, d, dx), 0.5, 1e-15);
  cr_expect_float_eq(peri_partial_volume_factor(PERI_PV_LAMMPS, 3.25, d, dx), 0.0, 1e-15);
}

Test(bonds, influence) {
  cr_expect_float_eq(peri_influence_value(PERI_INFLUENCE_CONSTANT, 2.0, 3.0), 1.0, 1e-15);
  cr_expect_float_eq(peri_influence_value(PERI_INFLUENCE_INVERSE, 2.0, 3.0), 0.5, 1e-15);
  cr_expect_float_eq(peri_influence_value(PERI_INFLUENCE_GAUSSIAN, 2.0, 3.0), exp(-4.0 / 9.0),
                     1e-15);
}

/* Deterministic pseudo-random cloud in [0, L)^dim. */
static void cloud(peri_particles *p, int dim, int32_t n, double L, uint64_t paper) {
  peri_particles_init(p, dim);
  uint64_t s = paper;
  for (int32_t i = 0; i < n; i++) {
    double x[3] = {0, 0, 0};
    for (int d = 0; d < dim; d++) {
      s = s * 6364136223846793005ULL + 1442695040888963407ULL;
      x[d] = L * (double)(s >> 11) / 9007199254740992.0;
    }
    peri_particles_add(p, x, 1.0, 0, 1);
  }
}

static void check_brute_force(int dim, peri_partial_volume rule, peri_influence w) {
  peri_particles p;
  cloud(&p, dim, dim == 3 ? 3000 : 2000, 1.0, 42 + (uint64_t)dim);
  peri_family_params fp = {
      .horizon = dim == 3 ? 0.12 : 0.07, .spacing = 0.02, .rule = rule, .influence = w};
  double cut = fp.horizon + (rule == PERI_PV_LINEAR ? fp.spacing / 2 : 0);
  peri_bonds b;
  peri_bonds_build(&b, &p, &fp);
  cr_assert_eq(b.n_nodes, p.n);
  int64_t k = 0;
  for (int32_t i = 0; i < p.n; i++) {
    cr_assert_eq(b.offset[i], k);
    for (int32_t j = 0; j < p.n; j++) {
      if (j == i) continue;
      double r2 = 0;
      for (int d = 0; d < 3; d++)
        r2 += (p.x[3 * i + d] - p.x[3 * j + d]) * (p.x[3 * i + d] - p.x[3 * j + d]);
      double r = sqrt(r2);
      if (r > cut * (1 + 1e-12)) continue;
      double beta = peri_partial_volume_factor(rule, r, fp.horizon, fp.spacing);
      if (beta <= 0) continue;
      cr_assert_lt(k, b.offset[i + 1], "node %d: search found fewer neighbours", i);
      cr_assert_eq(b.neighbor[k], j, "node %d: neighbour %lld is %d, brute force %d", i,
                   (long long)(k - b.offset[i]), b.neighbor[k], j);
      const double r0 = peri_bond_length(p.x, i, j);
      cr_assert_float_eq(r0, r, 1e-15);
      cr_assert_float_eq(peri_bonds_beta(&b, r0), beta, 1e-15);
      cr_assert_float_eq(peri_bonds_omega(&b, r0), peri_influence_value(w, r, fp.horizon), 1e-12);
      cr_assert_eq(b.broken[k], 0);
      k++;
    }
    cr_assert_eq(b.offset[i + 1], k, "node %d: search found more neighbours", i);
  }
  cr_assert_eq(b.n_bonds, k);
  cr_assert_gt(k, 10 * p.n); /* the test means something */
  peri_bonds_free(&b);
  peri_particles_free(&p);
}

Test(bonds, brute_force_2d) { check_brute_force(2, PERI_PV_LINEAR, PERI_INFLUENCE_INVERSE); }
Test(bonds, brute_force_3d) { check_brute_force(3, PERI_PV_NONE, PERI_INFLUENCE_GAUSSIAN); }
Test(bonds, brute_force_3d_lammps) {
  check_brute_force(3, PERI_PV_LAMMPS, PERI_INFLUENCE_CONSTANT);
}

Test(bonds, symmetric) {
  peri_particles p;
  cloud(&p, 3, 2000, 1.0, 7);
  peri_family_params fp = {
      .horizon = 0.1, .spacing = 0.03, .rule = PERI_PV_LINEAR, .influence = PERI_INFLUENCE_INVERSE};
  peri_bonds b;
  peri_bonds_build(&b, &p, &fp);
  for (int32_t i = 0; i < b.n_nodes; i++)
    for (int64_t k = b.offset[i]; k < b.offset[i + 1]; k++) {
      if (k > b.offset[i]) cr_assert_lt(b.neighbor[k - 1], b.neighbor[k], "family not sorted");
      int32_t j = b.neighbor[k];
      int64_t back = peri_bonds_find(&b, j, i);
      cr_assert_geq(back, 0, "bond %d->%d has no reverse", i, j);
      cr_assert_eq(b.neighbor[back], i);
      const double r0 = peri_bond_length(p.x, i, j);
      cr_assert_eq(peri_bond_length(p.x, j, i), r0, "reference length not symmetric");
      cr_assert_gt(peri_bonds_beta(&b, r0), 0);
      cr_assert_leq(peri_bonds_beta(&b, r0), 1);
      cr_assert_eq(peri_bonds_find(&b, i, j), k);
    }
  cr_assert_eq(peri_bonds_find(&b, 0, 0), -1);
  /* 32-bit neighbour index and a byte flag: nothing else is stored per bond */
  cr_assert_eq(peri_bonds_bytes_per_bond(&b), 5.0);
  peri_bonds_free(&b);
  peri_particles_free(&p);
}

Test(bonds, thread_count_independent) {
  peri_particles p;
  cloud(&p, 3, 4000, 1.0, 99);
  peri_family_params fp = {.horizon = 0.08,
                           .spacing = 0.02,
                           .rule = PERI_PV_LINEAR,
                           .influence = PERI_INFLUENCE_GAUSSIAN};
  peri_bonds b1, b2;
  omp_set_num_threads(1);
  peri_bonds_build(&b1, &p, &fp);
  omp_set_num_threads(2);
  peri_bonds_build(&b2, &p, &fp);
  cr_assert_eq(b1.n_bonds, b2.n_bonds);
  cr_assert_gt(b1.n_bonds, 0);
  size_t nb = (size_t)b1.n_bonds;
  cr_assert(!memcmp(b1.offset, b2.offset, sizeof(int64_t) * ((size_t)b1.n_nodes + 1)));
  cr_assert(!memcmp(b1.neighbor, b2.neighbor, sizeof(int32_t) * nb));
  peri_bonds_free(&b1);
  peri_bonds_free(&b2);
  peri_particles_free(&p);
}

/* Ghosts (after the owned nodes) are neighbours but have no family of their own. */
Test(bonds, ghosts) {
  peri_particles p;
  unit_lattice(&p, 2, 3);
  int32_t n = p.n;
  p.n_owned = n - 7; /* pretend the last 7 are ghosts */
  peri_family_params fp = {
      .horizon = 1.5, .spacing = 1, .rule = PERI_PV_NONE, .influence = PERI_INFLUENCE_CONSTANT};
  peri_bonds b;
  peri_bonds_build(&b, &p, &fp);
  cr_assert_eq(b.n_nodes, n - 7);
  bool ghost_neighbor = false;
  for (int64_t k = 0; k < b.n_bonds; k++) ghost_neighbor |= b.neighbor[k] >= n - 7;
  cr_assert(ghost_neighbor);
  /* a new node after the ghosts is a ghost */
  const double x[3] = {10, 10, 0};
  peri_particles_add(&p, x, 1, 0, 1);
  cr_assert_eq(p.n, n + 1);
  cr_assert_eq(p.n_owned, n - 7);
  peri_bonds_free(&b);
  peri_particles_free(&p);
}

Test(bonds, empty_and_isolated) {
  peri_particles p;
  peri_particles_init(&p, 3);
  peri_family_params fp = {.horizon = 1, .spacing = 1, .rule = PERI_PV_LINEAR};
  peri_bonds b;
  peri_bonds_build(&b, &p, &fp);
  cr_assert_eq(b.n_bonds, 0);
  cr_assert_eq(peri_bonds_bytes_per_bond(&b), 0.0);
  peri_bonds_free(&b);
  /* two far-apart nodes with a tiny horizon: no bonds, no absurd bin count */
  const double a[3] = {0, 0, 0}, c[3] = {1e3, 1e3, 1e3};
  peri_particles_add(&p, a, 1, 0, 1);
  peri_particles_add(&p, c, 1, 0, 1);
  fp.horizon = 1e-9;
  fp.spacing = 1e-9;
  peri_bonds_build(&b, &p, &fp);
  cr_assert_eq(b.n_bonds, 0);
  cr_assert_eq(b.n_nodes, 2);
  peri_bonds_free(&b);
  peri_particles_free(&p);
}

Test(region, collect) {
  peri_particles p;
  unit_lattice(&p, 2, 5);
  peri_region r;
  memset(&r, 0, sizeof r);
  r.name = strdup("left");
  r.shape = box_shape(-5, -5, 0, -4, 5, 0);
  peri_region_collect(&r, &p, 1e-9);
  cr_assert_eq(r.count, 22);
  for (int32_t k = 0; k < r.count; k++) {
    cr_assert_leq(p.x[3 * r.nodes[k]], -4 + 1e-9);
    if (k) cr_assert_lt(r.nodes[k - 1], r.nodes[k]);
  }
  peri_region_collect(&r, &p, 1e-9); /* again: the old list is replaced */
  cr_assert_eq(r.count, 22);
  peri_region_free(&r);
  peri_particles_free(&p);
}
