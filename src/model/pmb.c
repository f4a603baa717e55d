/* Bond-based prototype microelastic brittle (PMB) model (docs/model_reference.md 2; Le 2014 eqs. 1.3-1.8):
 * pair force f = c omega s M, with the micromodulus c of each end (half-bond rule,
 * c_ij = (c_i + c_j)/2, docs/model_reference.md 8). */
#include <math.h>
#include <string.h>
#include "peri/constants.h"
#include "peri/error.h"
#include "peri/model.h"
#include "bond_kernel.h"

static int pmb_init(peri_sim *s) {
  double calibration = peri_influence_calibration(s->family.influence, s->geom.dim, s->geom.horizon);
  for (int m = 0; m < s->n_materials; ++m) {
    peri_material *mat = &s->materials[m];
    if (!mat->micromodulus_given)
      mat->micromodulus = peri_pmb_micromodulus(&s->geom, mat->E, mat->K) * calibration;
    mat->c_stable = mat->micromodulus;
  }
  peri_particles *p = &s->p;
  p->coef = peri_malloc(sizeof(double) * (size_t)(p->n > 0 ? p->n : 1));
  return PERI_OK;
}

/* Force density on node i from the intact bonds to nbr[0 .. count-1], their minimum
 * mechanical stretch, and whether any stretch passes the screening bound (a candidate for
 * breaking). Constant arguments (multi-material, thermal, influence) specialize the loop. */
static inline __attribute__((always_inline)) long pmb_node(const peri_bond_view *w, int32_t i, const int32_t *restrict nbr,
                                                           int64_t count, bool multi, bool thermal,
                                                           peri_influence influence, bool uniform, double f[3],
                                                           double *smin_out) {
  const double xi0 = w->x[3 * i], xi1 = w->x[3 * i + 1], xi2 = w->x[3 * i + 2];
  const double ui0 = w->u[3 * i], ui1 = w->u[3 * i + 1], ui2 = w->u[3 * i + 2];
  const double ci = w->coef[i], eth_i = thermal ? w->eth[i] : 0.0, bound_i = w->s0_bound[i], V_i = w->V[i];
  /* local copies: the loop then reads no pointer through w */
  const double *restrict x = w->x, *restrict u = w->u, *restrict V = w->V, *restrict c_node = w->coef,
                         *restrict eth = w->eth, *restrict s0_bound = w->s0_bound;
  const peri_family_eval fam = w->fam;
  double fx = 0.0, fy = 0.0, fz = 0.0, smin = INFINITY;
  double excess = -INFINITY; /* largest stretch above the screening bound */
#pragma omp simd reduction(+ : fx, fy, fz) reduction(min : smin) reduction(max : excess)
  for (int64_t a = 0; a < count; ++a) {
    const int32_t j = nbr[a];
    const double x0 = x[3 * j] - xi0, x1 = x[3 * j + 1] - xi1, x2 = x[3 * j + 2] - xi2;
    const double y0 = x0 + (u[3 * j] - ui0), y1 = x1 + (u[3 * j + 1] - ui1),
                 y2 = x2 + (u[3 * j + 2] - ui2);
    const double r0 = sqrt(x0 * x0 + x1 * x1 + x2 * x2);
    const double r = sqrt(y0 * y0 + y1 * y1 + y2 * y2);
    const double inv_r0_r = 1.0 / (r0 * r); /* the loop's one division */
    double stretch = (r - r0) * r * inv_r0_r;
    if (thermal) stretch -= 0.5 * (eth_i + eth[j]);
    const double bound = peri_min(bound_i, s0_bound[j]) - PERI_S0_SCREEN_MARGIN;
    excess = peri_max(excess, stretch - bound);
    smin = peri_min(smin, stretch);
    const double c = multi ? 0.5 * (ci + c_node[j]) : ci;
    const double scale = c * stretch * peri_eval_omega(&fam, influence, r0) * peri_eval_beta(&fam, r0) *
                         (uniform ? V_i : V[j]) * r0 * inv_r0_r;
    const double g = r > 0.0 ? scale : 0.0;
    fx += g * y0;
    fy += g * y1;
    fz += g * y2;
  }
  f[0] = fx;
  f[1] = fy;
  f[2] = fz;
  *smin_out = smin;
  return excess > 0.0;
}

/* One function per specialization: the OpenMP region below is outlined before inlining, so
 * the constants must be fixed inside a function of their own to reach the vector loop. */
typedef long (*pmb_node_fn)(const peri_bond_view *, int32_t, int64_t, int64_t, double *, double *);
#define PMB_NODE_VARIANT(NAME, MULTI, THERMAL, INFLUENCE, UNIFORM)                                    \
  static long NAME(const peri_bond_view *w, int32_t i, int64_t k0, int64_t k1, double *f, double *smin) {     \
    if (!memchr(w->broken + k0, 1, (size_t)(k1 - k0)))                                                \
      return pmb_node(w, i, w->neighbor + k0, k1 - k0, MULTI, THERMAL, INFLUENCE, UNIFORM, f, smin);  \
    int32_t intact[PERI_INTACT_CHUNK];                                                                \
    long candidate = 0;                                                                               \
    f[0] = f[1] = f[2] = 0.0;                                                                         \
    *smin = INFINITY;                                                                                 \
    for (int64_t k = k0; k < k1;) {                                                                   \
      const int n = peri_next_intact(w->neighbor, w->broken, &k, k1, intact);                         \
      double fc[3], sc;                                                                               \
      candidate |= pmb_node(w, i, intact, n, MULTI, THERMAL, INFLUENCE, UNIFORM, fc, &sc);            \
      for (int d = 0; d < 3; ++d) f[d] += fc[d];                                                      \
      *smin = peri_min(*smin, sc);                                                                    \
    }                                                                                                 \
    return candidate;                                                                                 \
  }
/* "uniform": every node has the same volume (a grid), so the loop does not gather it */
PMB_NODE_VARIANT(pmb_node_uniform, false, false, PERI_INFLUENCE_CONSTANT, true)
PMB_NODE_VARIANT(pmb_node_plain, false, false, PERI_INFLUENCE_CONSTANT, false)
PMB_NODE_VARIANT(pmb_node_multi, true, false, PERI_INFLUENCE_CONSTANT, false)
PMB_NODE_VARIANT(pmb_node_thermal, false, true, PERI_INFLUENCE_CONSTANT, false)
PMB_NODE_VARIANT(pmb_node_multi_thermal, true, true, PERI_INFLUENCE_CONSTANT, false)
PMB_NODE_VARIANT(pmb_node_inverse, true, false, PERI_INFLUENCE_INVERSE, false)
PMB_NODE_VARIANT(pmb_node_inverse_thermal, true, true, PERI_INFLUENCE_INVERSE, false)
PMB_NODE_VARIANT(pmb_node_gaussian, true, false, PERI_INFLUENCE_GAUSSIAN, false)
PMB_NODE_VARIANT(pmb_node_gaussian_thermal, true, true, PERI_INFLUENCE_GAUSSIAN, false)

static long pmb_force(peri_sim *s) {
  peri_particles *p = &s->p;
  peri_bonds *b = &s->bonds;
  /* per-node copies of the material data the loop gathers (O(n), refreshed so that they
   * follow any change of the materials) */
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n; ++i) p->coef[i] = s->materials[p->material[i]].micromodulus;
  peri_update_s0_bound(s);
  const bool uniform = peri_uniform_volume(p);
  const bool multi = s->n_materials > 1, thermal = s->thermal_strain != NULL;
  pmb_node_fn node = multi ? (thermal ? pmb_node_multi_thermal : pmb_node_multi)
                           : (thermal ? pmb_node_thermal : uniform ? pmb_node_uniform : pmb_node_plain);
  if (s->family.influence == PERI_INFLUENCE_INVERSE) node = thermal ? pmb_node_inverse_thermal : pmb_node_inverse;
  if (s->family.influence == PERI_INFLUENCE_GAUSSIAN) node = thermal ? pmb_node_gaussian_thermal : pmb_node_gaussian;
  const peri_bond_view w = peri_bond_view_of(s);
  const bool track_smin = s->s0_node != NULL, breaking = s->breaking;
  long n_broken = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : n_broken)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const int64_t k0 = b->offset[i], k1 = b->offset[i + 1];
    double f[3], smin;
    const long candidates = node(&w, i, k0, k1, f, &smin);
    if (breaking && candidates > 0) {
      const long nb = peri_break_family(s, i);
      if (nb > 0) {
        n_broken += nb;
        double unused;
        node(&w, i, k0, k1, f, &unused);
      }
    }
    for (int d = 0; d < 3; ++d) p->f[3 * i + d] = f[d];
    if (track_smin) p->smin[i] = smin;
  }
  if (s->s0_node) peri_update_lammps_s0(s);
  return n_broken;
}

/* Sum over node i's intact bonds of w beta V_j with the micropotential w = c omega s^2 |xi| / 2. */
static inline __attribute__((always_inline)) double pmb_node_energy(const peri_bond_view *w, int32_t i,
                                                                    const int32_t *restrict nbr, int64_t count,
                                                                    bool thermal, peri_influence influence) {
  const double xi0 = w->x[3 * i], xi1 = w->x[3 * i + 1], xi2 = w->x[3 * i + 2];
  const double ui0 = w->u[3 * i], ui1 = w->u[3 * i + 1], ui2 = w->u[3 * i + 2];
  const double *restrict x = w->x, *restrict u = w->u, *restrict V = w->V, *restrict c_node = w->coef,
                         *restrict eth = w->eth;
  const peri_family_eval fam = w->fam;
  const double ci = c_node[i], eth_i = thermal ? eth[i] : 0.0;
  double sum = 0.0;
#pragma omp simd reduction(+ : sum)
  for (int64_t a = 0; a < count; ++a) {
    const int32_t j = nbr[a];
    const double x0 = x[3 * j] - xi0, x1 = x[3 * j + 1] - xi1, x2 = x[3 * j + 2] - xi2;
    const double y0 = x0 + (u[3 * j] - ui0), y1 = x1 + (u[3 * j + 1] - ui1), y2 = x2 + (u[3 * j + 2] - ui2);
    const double r0 = sqrt(x0 * x0 + x1 * x1 + x2 * x2);
    const double stretch = (sqrt(y0 * y0 + y1 * y1 + y2 * y2) - r0) / r0 - (thermal ? 0.5 * (eth_i + eth[j]) : 0.0);
    const double e = 0.25 * (ci + c_node[j]) * peri_eval_omega(&fam, influence, r0) * stretch * stretch * r0 *
                     peri_eval_beta(&fam, r0) * V[j];
    sum += e;
  }
  return sum;
}

typedef double (*pmb_energy_fn)(const peri_bond_view *, int32_t, int64_t, int64_t);
#define PMB_ENERGY_VARIANT(NAME, THERMAL, INFLUENCE)                                           \
  static double NAME(const peri_bond_view *w, int32_t i, int64_t k0, int64_t k1) {                  \
    if (!memchr(w->broken + k0, 1, (size_t)(k1 - k0)))                                        \
      return pmb_node_energy(w, i, w->neighbor + k0, k1 - k0, THERMAL, INFLUENCE);            \
    int32_t intact[PERI_INTACT_CHUNK];                                                        \
    double sum = 0.0;                                                                         \
    for (int64_t k = k0; k < k1;) {                                                           \
      const int n = peri_next_intact(w->neighbor, w->broken, &k, k1, intact);                 \
      sum += pmb_node_energy(w, i, intact, n, THERMAL, INFLUENCE);                            \
    }                                                                                         \
    return sum;                                                                               \
  }
PMB_ENERGY_VARIANT(pmb_energy_constant, false, PERI_INFLUENCE_CONSTANT)
PMB_ENERGY_VARIANT(pmb_energy_constant_thermal, true, PERI_INFLUENCE_CONSTANT)
PMB_ENERGY_VARIANT(pmb_energy_inverse, false, PERI_INFLUENCE_INVERSE)
PMB_ENERGY_VARIANT(pmb_energy_inverse_thermal, true, PERI_INFLUENCE_INVERSE)
PMB_ENERGY_VARIANT(pmb_energy_gaussian, false, PERI_INFLUENCE_GAUSSIAN)
PMB_ENERGY_VARIANT(pmb_energy_gaussian_thermal, true, PERI_INFLUENCE_GAUSSIAN)

/* W_i = 1/2 sum_j w_ij beta V_j. Not on the time-step path (history rows only). */
static void pmb_energy(peri_sim *s, double *W) {
  peri_particles *p = &s->p;
  const peri_bonds *b = &s->bonds;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n; ++i) p->coef[i] = s->materials[p->material[i]].micromodulus;
  const peri_bond_view w = peri_bond_view_of(s);
  const bool thermal = s->thermal_strain != NULL;
  pmb_energy_fn node = thermal ? pmb_energy_constant_thermal : pmb_energy_constant;
  if (s->family.influence == PERI_INFLUENCE_INVERSE) node = thermal ? pmb_energy_inverse_thermal : pmb_energy_inverse;
  if (s->family.influence == PERI_INFLUENCE_GAUSSIAN) node = thermal ? pmb_energy_gaussian_thermal : pmb_energy_gaussian;
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) W[i] = 0.5 * node(&w, i, b->offset[i], b->offset[i + 1]);
}

static double pmb_pair_force(const peri_sim *s, int32_t i, int64_t k, double r) {
  const peri_particles *p = &s->p;
  const peri_bonds *b = &s->bonds;
  const int32_t j = b->neighbor[k];
  const double r0 = peri_bond_length(p->x, i, j);
  const double stretch = (r - r0) / r0 - peri_bond_thermal_stretch(s->thermal_strain, i, j);
  const double c = 0.5 * (s->materials[p->material[i]].micromodulus + s->materials[p->material[j]].micromodulus);
  return c * stretch * peri_bonds_omega(b, r0);
}

const peri_model_ops peri_model_pmb = {
    .name = "pmb",
    .description = "bond-based PMB (Poisson ratio fixed: 1/4 in 1D, 3D and plane strain, 1/3 in plane stress)",
    .fixed_poisson = 1,
    .init = pmb_init,
    .force = pmb_force,
    .energy = pmb_energy,
    .pair_force = pmb_pair_force,
    .tangent = peri_pmb_tangent, .tangent_reach = 1, /* src/model/pmb_tangent.c */
};
