/* Short-range contact forces (docs/contact.md; MODELS.md 17.1, the LAMMPS pair peri form):
 * the force of one pair against the published law, the fragmenting LAMMPS problem in which
 * no two nodes come much closer than their contact distance d_ij, and results independent of
 * the thread count. */
#include <criterion/criterion.h>
#include <math.h>
#include <omp.h>
#include <string.h>
#include "peri/contact.h"
#include "peri/short_range.h"
#include "peri/contribution.h"
#include "peri/solver.h"
#include "support.h"

#define DX 1.0e-3
#define K_BULK 14.9e9

/* One node of a 5 x 5 x 5 lattice pushed 0.15 dx towards its +x neighbour: r = 0.85 dx is
 * inside d = 0.9 dx of that pair only (the next pairs are at 1.31 dx > 1.27 dx and farther),
 * so the force densities are +-(15 c / delta)(0.9 - 0.85) dx V along x, c = 18 K/(pi delta^4),
 * on those two nodes and 0 on every other. */
Test(short_range, pair_force_of_the_lammps_law) {
  char deck[1024];
  snprintf(deck, sizeof deck,
           "dimension: 3\n"
           "materials: {m: {model: pmb, density: 2200, bulk_modulus: %.17g}}\n"
           "discretization:\n"
           "  spacing: %.17g\n"
           "  m: 3\n"
           "  fill: [{shape: box, min: [0, 0, 0], max: [0.005, 0.005, 0.005]}]\n"
           "contact: {short_range: {}}\n"
           "solver: {type: explicit, steps: 1, breaking: false}\n"
           "output: {picture: false}\n", K_BULK, DX);
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0);
  peri_particles *p = &s.disc.p;
  int32_t centre = -1, right = -1;
  for (int32_t i = 0; i < p->n; ++i) {
    const double *x = &p->x[3 * (size_t)i];
    if (fabs(x[1] - x[0]) < 1e-9 && fabs(x[2] - x[0]) < 1e-9 && fabs(x[0] - 0.0025) < 0.6 * DX) centre = i;
  }
  cr_assert_geq(centre, 0);
  for (int32_t i = 0; i < p->n; ++i)
    if (fabs(p->x[3 * (size_t)i] - p->x[3 * (size_t)centre] - DX) < 1e-9 && fabs(p->x[3 * (size_t)i + 1] - p->x[3 * (size_t)centre + 1]) < 1e-9 &&
        fabs(p->x[3 * (size_t)i + 2] - p->x[3 * (size_t)centre + 2]) < 1e-9)
      right = i;
  cr_assert_geq(right, 0);
  p->u[3 * (size_t)centre] = 0.15 * DX;
  peri_apply_loads(&s, 0.0);
  const double delta = s.disc.geom.horizon, c = 18.0 * K_BULK / (M_PI * pow(delta, 4));
  const double expected = 15.0 * c / delta * (0.9 - 0.85) * DX * p->volume[right];
  cr_assert_float_eq(p->b[3 * (size_t)centre], -expected, 1e-9 * expected, "%g vs %g", p->b[3 * (size_t)centre], -expected);
  cr_assert_float_eq(p->b[3 * (size_t)right], expected, 1e-9 * expected);
  for (int32_t i = 0; i < p->n; ++i)
    for (int a = 0; a < 3; ++a) {
      if ((i == centre || i == right) && a == 0) continue;
      cr_assert_eq(p->b[3 * (size_t)i + a], 0.0, "node %d component %d", i, a);
    }
  peri_sim_free(&s);
}

/* The LAMMPS examples/peri problem with a smaller target (radius and length 2.5 mm, 300
 * steps: over half the bonds break and fragments are pushed together under the indenter). */
static void fragmentation_deck(peri_sim *s, bool contact) {
  const char *sets[] = {"solver.steps=300", "discretization.fill.0.radius=0.0025", "discretization.fill.0.length=0.0025",
                        "discretization.fill.0.center=[0, -0.0025, 0]", "contact.short_range=true"};
  cr_assert_eq(peri_sim_from_deck_with(s, "examples/lammps_peri_pmb.yaml", contact ? 5 : 4, sets), 0);
}

/* The smallest |y_i - y_j| / d_ij over every pair, found independently of the pair list by a
 * sweep along x of the deformed positions (pairs farther apart than 1.35 dx along x are out
 * of reach). */
static const double *sweep_y;
static int by_x(const void *a, const void *b) {
  const double ya = sweep_y[3 * (size_t)*(const int32_t *)a], yb = sweep_y[3 * (size_t)*(const int32_t *)b];
  return (ya > yb) - (ya < yb);
}

/* The smallest ratio over the run, and the largest difference between the state's own
 * smallest ratio (capped at 1) and the value of the history column short_range_min_ratio,
 * which the force evaluation finds from the pair list. */
typedef struct closest {
  double min_ratio, column_error;
} closest;

static int track_closest(peri_sim *s, void *ctx) {
  closest *track = ctx;
  double now = INFINITY, *min_ratio = &now;
  const peri_particles *p = &s->disc.p;
  const double reach = PERI_SHORT_RANGE_RADIUS * s->disc.geom.spacing;
  double *y = malloc(sizeof(double) * 3 * (size_t)p->n);
  int32_t *order = malloc(sizeof(int32_t) * (size_t)p->n);
  for (size_t c = 0; c < 3 * (size_t)p->n; ++c) y[c] = p->x[c] + p->u[c];
  for (int32_t i = 0; i < p->n; ++i) order[i] = i;
  sweep_y = y;
  qsort(order, (size_t)p->n, sizeof *order, by_x);
  for (int32_t a = 0; a < p->n; ++a)
    for (int32_t b = a + 1; b < p->n && y[3 * (size_t)order[b]] - y[3 * (size_t)order[a]] < reach; ++b) {
      const int32_t i = order[a], j = order[b];
      double r2 = 0.0, r02 = 0.0;
      for (int k = 0; k < 3; ++k) {
        r2 += (y[3 * (size_t)i + k] - y[3 * (size_t)j + k]) * (y[3 * (size_t)i + k] - y[3 * (size_t)j + k]);
        r02 += (p->x[3 * (size_t)i + k] - p->x[3 * (size_t)j + k]) * (p->x[3 * (size_t)i + k] - p->x[3 * (size_t)j + k]);
      }
      *min_ratio = fmin(*min_ratio, sqrt(r2) / fmin(PERI_SHORT_RANGE_RATIO * sqrt(r02), reach));
    }
  free(order);
  free(y);
  track->min_ratio = fmin(track->min_ratio, now);
  if (s->contact && s->contact->short_range)
    track->column_error = fmax(track->column_error, fabs(fmin(now, 1.0) - peri_contact_min_ratio(s)));
  return 0;
}

/* The overlap a contact layer takes when a body at speed v strikes: the interface stress is
 * rho c_p v (c_p = sqrt(M/rho), M = 1.8 K the P-wave modulus of PMB, nu = 1/4); a face node's
 * partner across the interface carries (c_S/delta) p V^2 per dx^2 of face, so
 * p = rho c_p v delta / (c_S dx^4) with V = dx^3, counting the one straight partner only
 * (the diagonal ones make the layer stiffer). A suddenly loaded spring overshoots its static
 * compression by up to 2. The bound on min |y_i - y_j| / d_ij is 1 - 2 p / (0.9 dx). */
static double acoustic_bound(const peri_sim *s, double v) {
  const peri_material *m = &s->mat.materials[0];
  const double dx = s->disc.geom.spacing, delta = s->disc.geom.horizon;
  const double c_s = 15.0 * 18.0 * m->K / (M_PI * pow(delta, 4)), c_p = sqrt(1.8 * m->K / m->density);
  const double p = m->density * c_p * v * delta / (c_s * pow(dx, 4));
  return 1.0 - 2.0 * p / (PERI_SHORT_RANGE_RATIO * dx);
}

/* The fragmenting target under the indenter at 100 m/s: no two nodes closer than the bound. */
Test(short_range, fragments_keep_their_distance) {
  peri_sim s;
  fragmentation_deck(&s, true);
  closest track = {INFINITY, 0.0};
  cr_assert_eq(peri_solve_explicit(&s, track_closest, &track), 0);
  const double bound = acoustic_bound(&s, 100.0);
  cr_log_info("fragmentation: min |y_i - y_j| / d_ij = %.4f, bound %.4f, %ld of %lld bonds broken; column off by %.3g",
              track.min_ratio, bound, peri_broken_count(&s.disc.bonds), (long long)s.disc.bonds.n_bonds, track.column_error);
  cr_assert_gt(peri_broken_count(&s.disc.bonds), s.disc.bonds.n_bonds / 3, "the target fragments");
  cr_assert_geq(track.min_ratio, bound);
  /* the same pairs and the same arithmetic: equal but for the order of operations */
  cr_assert_leq(track.column_error, 1e-12, "short_range_min_ratio differs from the sweep by %g", track.column_error);
  peri_sim_free(&s);
}

/* A block cut in two by a pre-crack, its halves thrown at each other at 30 m/s each: with the
 * short-range forces the faces stop within the acoustic bound and fly apart again; without
 * them the halves pass through each other. */
static const char *halves_deck =
    "dimension: 3\n"
    "materials: {m: {model: pmb, density: 2200, bulk_modulus: 14.9e9}}\n"
    "discretization:\n"
    "  spacing: 0.001\n"
    "  m: 3\n"
    "  fill: [{shape: box, min: [0, 0, 0], max: [0.012, 0.006, 0.006]}]\n"
    "precracks: [{corner: [0.006, -0.001, -0.001], edge1: [0, 0.008, 0], edge2: [0, 0, 0.008]}]\n"
    "boundary_conditions:\n"
    "  - {type: initial_velocity, region: all, x: \"x < 0.006 ? 30 : -30\"}\n"
    "solver: {type: explicit, end_time: 4.0e-5, breaking: false}\n"
    "output: {picture: false}\n";

Test(short_range, colliding_halves) {
  for (int with = 1; with >= 0; --with) {
    const char *sets[] = {"contact.short_range=true"};
    char path[] = "/tmp/peri_test_deck_XXXXXX";
    const int fd = mkstemp(path);
    cr_assert_geq(fd, 0);
    FILE *f = fdopen(fd, "w");
    fputs(halves_deck, f);
    fclose(f);
    peri_sim s;
    cr_assert_eq(peri_sim_from_deck_with(&s, path, with, sets), 0);
    unlink(path);
    peri_apply_initial_conditions(&s);
    closest track = {INFINITY, 0.0};
    cr_assert_eq(peri_solve_explicit(&s, track_closest, &track), 0);
    const double min_ratio = track.min_ratio;
    const double bound = acoustic_bound(&s, 30.0);
    cr_log_info("halves, short-range %s: min |y_i - y_j| / d_ij = %.4f, bound %.4f; column off by %.3g", with ? "on" : "off",
                min_ratio, bound, track.column_error);
    if (with) {
      cr_assert_geq(min_ratio, bound);
      cr_assert_leq(track.column_error, 1e-12, "short_range_min_ratio differs from the sweep by %g", track.column_error);
      /* pair forces are opposite: the momentum stays 0 to round-off; the halves rebound */
      const peri_particles *p = &s.disc.p;
      double momentum = 0.0, scale = 0.0, left = 0.0, left_mass = 0.0;
      for (int32_t i = 0; i < p->n; ++i) {
        const double m = p->volume[i] * s.mat.materials[p->material[i]].density;
        momentum += m * p->v[3 * (size_t)i];
        scale += m * fabs(p->v[3 * (size_t)i]);
        if (p->x[3 * (size_t)i] < 0.006) left += m * p->v[3 * (size_t)i], left_mass += m;
      }
      cr_log_info("halves: momentum %.3g of %.3g, left half's mean velocity %.3g m/s", momentum, scale, left / left_mass);
      cr_assert_leq(fabs(momentum), 1e-12 * scale);
      cr_assert_lt(left / left_mass, 0.0, "the left half moves back after the impact");
    } else cr_assert_lt(min_ratio, 0.5, "without short-range forces the halves pass through each other");
    peri_sim_free(&s);
  }
}

/* The same run on 1 and 2 threads: the same displacements, bit for bit. */
Test(short_range, independent_of_threads) {
  double *u[2];
  int32_t n = 0;
  for (int k = 0; k < 2; ++k) {
    omp_set_num_threads(k + 1);
    peri_sim s;
    fragmentation_deck(&s, true);
    s.solver.steps = 150;
    cr_assert_eq(peri_solve_explicit(&s, NULL, NULL), 0);
    n = s.disc.p.n;
    u[k] = malloc(sizeof(double) * 3 * (size_t)n);
    memcpy(u[k], s.disc.p.u, sizeof(double) * 3 * (size_t)n);
    peri_sim_free(&s);
  }
  cr_assert_eq(memcmp(u[0], u[1], sizeof(double) * 3 * (size_t)n), 0, "displacements differ between 1 and 2 threads");
  free(u[0]);
  free(u[1]);
}
