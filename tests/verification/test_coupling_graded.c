/* The PD-FEM coupling on a graded FEM mesh (docs/coupling.md, "Graded meshes";
 * src/fem/graded_mesh.c): a 48 x 32 plate, dx = 1, delta = 3 (m = 3), bond-based PD block
 * [19, 29] x [13, 19] inside a fine zone [14, 34] x [8, 24] of lattice cells, and elements of
 * 2, 4 and 8 dx away from it (levels 3, layers 2), with triangles where a coarse cell meets a
 * finer one. Checked:
 *  - the mesh is graded: coarse elements and transition triangles exist, lattice nodes inside
 *    coarse elements are gone, and the element areas sum to the area the lattice's own mesh
 *    covers (47 x 31: the elements join node centres), to round-off;
 *  - patch test, imposed: u = a + H x on every node gives F = K u = 0 on every node off the
 *    plate's outer boundary (FEM, transition and PD nodes alike) and e_r at round-off (1e-13),
 *    plane stress and plane strain; a quadratic field does not (e_r > 1e-6), so the check can
 *    fail (it does when a coarse cell with a middle node is left a Q4: that node's force is then
 *    of the order of the others);
 *  - patch test, solved: the outer boundary nodes prescribed u = a + H x, the coupled model
 *    solved by the implicit solver (LU): every node has u = a + H x to 1e-9 of |u|. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "peri/coupling.h"
#include "peri/quasistatic.h"
#include "peri/solver.h"
#include "peri/sim.h"
#include "support.h"

static const char *const plate =
    "dimension: 2\n"
    "plane: %s\n"
    "materials: {m: {model: pmb, density: 1, youngs_modulus: 1.0e3, critical_stretch: 1}}\n"
    "discretization: {spacing: 1, m: 3, thickness: 1, fill: [{shape: rectangle, min: [0, 0], max: [48, 32]}]}\n"
    "regions:\n"
    "  pd: {shape: rectangle, min: [19, 13], max: [29, 19]}\n"
    "  inside: {shape: rectangle, min: [0.9, 0.9], max: [47.1, 31.1]}\n"
    "  edge: {difference: [all, inside]}\n"
    "coupling:\n"
    "  pd_region: pd\n"
    "  graded_mesh: {fine: {shape: rectangle, min: [14, 8], max: [34, 24]}, levels: 3, layers: 2}\n"
    "%s";

static void linear(const double *x, double *u) {
  u[0] = 0.1 + 0.01 * x[0] - 0.02 * x[1];
  u[1] = -0.2 + 0.005 * x[0] + 0.013 * x[1];
}

static void quadratic(const double *x, double *u) {
  u[0] = 0.0;
  u[1] = 1e-4 * x[0] * x[0];
}

static void build(peri_sim *s, const char *plane, const char *extra) {
  char deck[4096];
  snprintf(deck, sizeof deck, plate, plane, extra);
  cr_assert_eq(sim_from_string(s, deck), 0, "deck:\n%s", deck);
  cr_assert_not_null(s->coupling);
}

static bool on_edge(const double *x) { return x[0] < 1 || x[0] > 47 || x[1] < 1 || x[1] > 31; }

/* F = K u of the field f on every node; returns e_r, and the largest |F| off the outer boundary
 * relative to the largest on it in *inner */
static double imposed(peri_sim *s, void (*f)(const double *, double *), double *inner) {
  peri_particles *p = &s->disc.p;
  for (int32_t i = 0; i < p->n; ++i) f(&p->x[3 * (size_t)i], &p->u[3 * (size_t)i]);
  peri_coupling_force(s);
  double edge = 0.0, in = 0.0;
  for (int32_t i = 0; i < p->n; ++i) {
    const double F = p->volume[i] * hypot(p->f[3 * (size_t)i], p->f[3 * (size_t)i + 1]);
    if (on_edge(&p->x[3 * (size_t)i])) edge = fmax(edge, F);
    else in = fmax(in, F);
  }
  *inner = in / edge;
  double net[3], ratio[4];
  peri_coupling_balance(s, net, ratio);
  return ratio[3];
}

Test(coupling_graded, mesh_and_imposed_patch_test) {
  static const char *const planes[] = {"stress", "strain"};
  for (int k = 0; k < 2; ++k) {
    peri_sim s;
    build(&s, planes[k], "solver: {type: implicit, load_steps: 1}\n");
    const peri_coupling *c = s.coupling;
    int32_t triangles = 0;
    double area = 0.0;
    for (int32_t e = 0; e < c->n_elements; ++e) {
      const int64_t a0 = c->element_offset[e], n = c->element_offset[e + 1] - a0;
      triangles += n == 3;
      for (int64_t a = 0; a < n; ++a) {
        const double *p = &s.disc.p.x[3 * (size_t)c->element_nodes[a0 + a]];
        const double *q = &s.disc.p.x[3 * (size_t)c->element_nodes[a0 + (a + 1) % n]];
        area += 0.5 * (p[0] * q[1] - q[0] * p[1]);
      }
    }
    cr_assert(c->coarse_nodes > 0 && c->removed_nodes > 0 && triangles > 0,
              "not graded: %d coarse nodes, %d removed, %d triangles", c->coarse_nodes, c->removed_nodes, triangles);
    cr_assert_eq(s.disc.p.n + c->removed_nodes, 48 * 32, "%d nodes kept and %d left out of the 48 x 32 lattice",
                 s.disc.p.n, c->removed_nodes);
    cr_assert_lt(fabs(area - 47.0 * 31.0), 1e-9, "the elements cover %.12g, not 47 x 31", area);
    double inner;
    const double e_r = imposed(&s, linear, &inner);
    cr_expect_lt(e_r, 1e-13, "plane %s: linear field e_r = %g", planes[k], e_r);
    cr_expect_lt(inner, 1e-13, "plane %s: a node off the boundary has |F| = %g of the boundary's", planes[k], inner);
    const double e_q = imposed(&s, quadratic, &inner);
    cr_expect_gt(e_q, 1e-6, "plane %s: quadratic field e_r = %g", planes[k], e_q);
    peri_sim_free(&s);
  }
}

Test(coupling_graded, solved_patch_test) {
  peri_sim s;
  build(&s, "strain",
        "boundary_conditions:\n"
        "  - {type: displacement, region: edge, x: \"0.1 + 0.01*x - 0.02*y\", y: \"-0.2 + 0.005*x + 0.013*y\"}\n"
        "solver: {type: implicit, load_steps: 1, tolerance: 1.0e-12}\n");
  s.out.quiet = true;
  peri_apply_initial_conditions(&s);
  cr_assert_eq(peri_solve_quasi_static(&s, NULL, NULL), 0);
  double worst = 0.0;
  for (int32_t i = 0; i < s.disc.p.n; ++i) {
    double u[3];
    linear(&s.disc.p.x[3 * (size_t)i], u);
    worst = fmax(worst, hypot(s.disc.p.u[3 * (size_t)i] - u[0], s.disc.p.u[3 * (size_t)i + 1] - u[1]) / hypot(u[0], u[1]));
  }
  cr_expect_lt(worst, 1e-9, "the solved field is off the linear one by %g (relative)", worst);
  peri_sim_free(&s);
}
