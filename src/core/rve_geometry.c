/* Random periodic platelet geometry of a nanocomposite RVE (002_b20c318388227af9.txt §3.3.1):
 * Gaussian aspect ratio, uniformly drawn centre node, orientation and curvature, periodic
 * wrap, overlap allowed, platelets added until the filler share of the nodes is closest to
 * the volume fraction of eq. 3.2. */
#include "peri/rve_geometry.h"
#include "peri/error.h"
#include <math.h>
#include <stdlib.h>

static const double PI = 3.14159265358979323846;

peri_rve_params peri_rve_params_default(void) {
  /* 002_b20c318388227af9.txt Table 3.1, with L = 1.5 um (Table 3.2's last row). */
  peri_rve_params p = {
      .side = 1.5e-6, .spacing = 10e-9, .m = 8, .E_matrix = 3.5e9, .E_filler = 178e9,
      .rho_matrix = 1156.5, .rho_filler = 1660.0, .weight_fraction = 0.05, .kappa = 0.1,
      .aspect_mean = 300.0, .aspect_std = 60.0,
      .thickness = 1e-9,   /* one clay layer; the seed does not print it */
      .max_turn = PI / 4,  /* the seed does not print the curvature range */
      .strain = 0.01,      /* 002_b20c318388227af9.txt §3.3.2: eps = 0.01 */
      .seed = 1};
  return p;
}

int peri_rve_params_check(const peri_rve_params *p) {
#define NEED(cond, what)                                    \
  if (!(cond)) {                                            \
    peri_error("rve: %s", what);                            \
    return -1;                                              \
  }
  NEED(p->spacing > 0 && isfinite(p->spacing), "spacing must be a number > 0");
  NEED(p->side >= p->spacing && p->side / p->spacing <= 4096, "side must be between 1 and 4096 spacings");
  NEED(p->m >= 1 && p->m <= 32, "m must be an integer from 1 to 32");
  NEED(p->E_matrix > 0 && isfinite(p->E_matrix), "E_matrix must be a number > 0");
  NEED(p->E_filler > 0 && isfinite(p->E_filler), "E_filler must be a number > 0");
  NEED(p->rho_matrix > 0 && p->rho_filler > 0, "rho_matrix and rho_filler must be > 0");
  NEED(p->weight_fraction >= 0 && p->weight_fraction < 1, "weight_fraction must be in [0, 1)");
  NEED(p->kappa > 0 && isfinite(p->kappa), "kappa must be a number > 0");
  NEED(p->aspect_mean > 0 && p->aspect_std >= 0, "aspect_mean must be > 0 and aspect_std >= 0");
  NEED(p->thickness > 0 && isfinite(p->thickness), "thickness must be a number > 0");
  NEED(p->max_turn >= 0 && p->max_turn <= 2 * PI, "max_turn must be in [0, 2 pi] (radians)");
  NEED(p->strain != 0 && fabs(p->strain) < 1, "strain must be nonzero and below 1 in magnitude");
#undef NEED
  return 0;
}

double peri_rve_volume_fraction(double wt, double rho_filler, double rho_matrix) {
  const double f = wt / rho_filler, m = (1.0 - wt) / rho_matrix; /* eq. 3.2 */
  return f / (f + m);
}

/* splitmix64 (Steele, Lea, Flood 2014): a fixed, portable stream per (seed, realization). */
typedef struct { uint64_t s; } rng;
static uint64_t next_u64(rng *r) {
  uint64_t z = (r->s += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}
static double uniform01(rng *r) { return (double)(next_u64(r) >> 11) * 0x1.0p-53; }
static long uniform_int(rng *r, long n) { return (long)(uniform01(r) * (double)n); }
static double gaussian(rng *r, double mean, double std) {
  double u = uniform01(r);
  while (u <= 0.0) u = uniform01(r);
  return mean + std * sqrt(-2.0 * log(u)) * cos(2.0 * PI * uniform01(r)); /* Box-Muller */
}

static int wrap(long i, int n) {
  long k = i % n;
  return (int)(k < 0 ? k + n : k);
}

/* Marks the nodes of one circular arc (a straight segment when the turn is 0) with id where they
 * are matrix; returns the number of nodes it newly covered. */
static long draw_platelet(peri_rve_geometry *g, double dx, double cx, double cy, double theta,
                          double turn, double length, int32_t id) {
  const double k = turn / length; /* curvature */
  const double step = dx / 4;
  const long samples = (long)ceil(length / step);
  long added = 0;
  for (long s = 0; s <= samples; ++s) {
    const double a = -length / 2 + length * (double)s / (double)samples;
    double x, y;
    if (fabs(k * length) < 1e-12) {
      x = cx + a * cos(theta), y = cy + a * sin(theta);
    } else {
      x = cx + (sin(theta + k * a) - sin(theta)) / k;
      y = cy - (cos(theta + k * a) - cos(theta)) / k;
    }
    const int i = wrap((long)floor(x / dx), g->n), j = wrap((long)floor(y / dx), g->n);
    int32_t *cell = &g->platelet[i + (long)g->n * j];
    if (*cell < 0) *cell = id, ++added;
  }
  return added;
}

int peri_rve_generate(const peri_rve_params *p, uint64_t realization, peri_rve_geometry *g) {
  const int n = (int)lround(p->side / p->spacing);
  const long nodes = (long)n * n;
  g->n = n, g->platelets = 0, g->filler_nodes = 0;
  g->platelet = malloc((size_t)nodes * sizeof(int32_t));
  if (!g->platelet) return -1;
  for (long i = 0; i < nodes; ++i) g->platelet[i] = -1;
  const double vol = peri_rve_volume_fraction(p->weight_fraction, p->rho_filler, p->rho_matrix);
  const long target = lround(vol * (double)nodes);
  rng r = {p->seed * 0xd1b54a32d192ed03ULL ^ (realization + 1) * 0x9e3779b97f4a7c15ULL};
  const double dx = p->spacing;
  /* A platelet that covers no new node (all overlap) still counts as drawn; stop after many in a row. */
  int idle = 0;
  while (g->filler_nodes < target && idle < 1000) {
    double ar = gaussian(&r, p->aspect_mean, p->aspect_std);
    if (ar < 1.0) ar = 1.0; /* the Gaussian's tail below one thickness */
    const double length = ar * p->thickness;
    const double cx = ((double)uniform_int(&r, n) + 0.5) * dx; /* centre: a node */
    const double cy = ((double)uniform_int(&r, n) + 0.5) * dx;
    const double theta = PI * uniform01(&r);
    const double turn = p->max_turn * (2.0 * uniform01(&r) - 1.0);
    const int32_t id = g->platelets;
    const long before = g->filler_nodes;
    const long added = draw_platelet(g, dx, cx, cy, theta, turn, length, id);
    idle = added ? 0 : idle + 1;
    if (before + added > target && before + added - target > target - before) {
      for (long i = 0; i < nodes; ++i) /* the last platelet overshoots more than it helps */
        if (g->platelet[i] == id) g->platelet[i] = -1;
      break;
    }
    g->filler_nodes += added, g->platelets += 1;
  }
  return 0;
}

void peri_rve_geometry_free(peri_rve_geometry *g) {
  free(g->platelet);
  g->platelet = NULL;
}
