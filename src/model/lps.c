/* Ordinary state-based linear peridynamic solid (LPS): Silling 2007 in 3D, Le's plane
 * stress and plane strain model in 2D (Le 2014 ch. 2), one discrete algorithm for all
 * dimensions (docs/model_reference.md 3.3):
 *   theta_i = (n_theta/m_i) sum_j w e |xi| W_ij,       e^d = e - theta_i |xi|/3
 *   P_i     = sum_j w e^d |xi| W_ij,                   alpha_i = (alpha m)/m_i
 *   t_ij    = n_theta (K_theta theta_i - alpha_i P_i/3) w |xi|/m_i + alpha_i w e^d_ij
 *   f_i     = sum_j (t_ij + t_ji) M_ij W_ij,           W_ij = chi beta V_j
 * Each end uses its own material's constants (half-bond rule, docs/model_reference.md 8). */
#include <math.h>
#include <string.h>
#include "peri/constants.h"
#include "peri/error.h"
#include "peri/model.h"
#include "bond_kernel.h"

static int lps_init(peri_sim *s) {
  peri_particles *p = &s->p;
  const peri_bonds *b = &s->bonds;
  for (int m = 0; m < s->n_materials; ++m) {
    peri_material *mat = &s->materials[m];
    peri_lps_constants(&s->geom, mat->K, mat->mu, &mat->n_theta, &mat->K_theta, &mat->alpha_m);
    mat->c_stable = peri_stable_micromodulus(
        &s->geom, peri_pwave_modulus(&s->geom, mat->E, mat->nu, mat->K, mat->mu));
  }
  p->theta = peri_calloc(p->n, sizeof(double));
  p->pstate = peri_calloc(p->n, sizeof(double));
  p->wvol = peri_calloc(p->n, sizeof(double));
  p->coef = peri_calloc(2 * (size_t)p->n, sizeof(double));
  if (s->analytic_weighted_volume) {
    double m = peri_weighted_volume_analytic(&s->geom, s->family.influence);
    for (int32_t i = 0; i < p->n; ++i) p->wvol[i] = m;
    return PERI_OK;
  }
  /* Discrete weighted volume over the reference family (not updated as bonds break). */
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double m = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k)
    {
      const int32_t j = b->neighbor[k];
      const double r0 = peri_bond_length(p->x, i, j);
      m += peri_bonds_omega(b, r0) * r0 * r0 * peri_bonds_beta(b, r0) * p->volume[j];
    }
    p->wvol[i] = m;
  }
  for (int32_t i = 0; i < p->n_owned; ++i) {
    if (!(p->wvol[i] > 0.0)) {
      peri_error("node %d at (%g, %g, %g) has no bonds: the LPS model needs a family "
                 "(increase the horizon or check the geometry)",
                 i, p->x[3 * i], p->x[3 * i + 1], p->x[3 * i + 2]);
      return PERI_ERR_INPUT;
    }
  }
  return PERI_OK;
}

/* Pass-1 sums of node i over the intact bonds to nbr[0 .. count-1]: sum w e and sum w |xi| with w = omega |xi| beta V_j
 * and e the extension less node i's thermal part; the minimum mechanical stretch; and
 * whether any bond is a candidate for breaking (as in the PMB loop). */
static inline __attribute__((always_inline)) long lps_node_sums(const peri_bond_view *w, int32_t i, const int32_t *restrict nbr,
                                                                int64_t count, bool thermal, peri_influence influence,
                                                                bool uniform,
                                                                double *we_x_out, double *w_xx_out, double *smin_out) {
  const double xi0 = w->x[3 * i], xi1 = w->x[3 * i + 1], xi2 = w->x[3 * i + 2];
  const double ui0 = w->u[3 * i], ui1 = w->u[3 * i + 1], ui2 = w->u[3 * i + 2];
  const double eth_i = thermal ? w->eth[i] : 0.0, bound_i = w->s0_bound[i], V_i = w->V[i];
  const double *restrict x = w->x, *restrict u = w->u, *restrict V = w->V, *restrict eth = w->eth,
                         *restrict s0_bound = w->s0_bound;
  const peri_family_eval fam = w->fam;
  double we_x = 0.0, w_xx = 0.0, smin = INFINITY;
  double excess = -INFINITY; /* largest stretch above the screening bound */
#pragma omp simd reduction(+ : we_x, w_xx) reduction(min : smin) reduction(max : excess)
  for (int64_t a = 0; a < count; ++a) {
    const int32_t j = nbr[a];
    const double x0 = x[3 * j] - xi0, x1 = x[3 * j + 1] - xi1, x2 = x[3 * j + 2] - xi2;
    const double y0 = x0 + (u[3 * j] - ui0), y1 = x1 + (u[3 * j + 1] - ui1),
                 y2 = x2 + (u[3 * j + 2] - ui2);
    const double r0 = sqrt(x0 * x0 + x1 * x1 + x2 * x2);
    const double e_total = sqrt(y0 * y0 + y1 * y1 + y2 * y2) - r0;
    double s_mech = e_total / r0;
    if (thermal) s_mech -= 0.5 * (eth_i + eth[j]); /* symmetric in i, j */
    const double bound = peri_min(bound_i, s0_bound[j]) - PERI_S0_SCREEN_MARGIN;
    excess = peri_max(excess, s_mech - bound);
    smin = peri_min(smin, s_mech);
    const double wt = peri_eval_omega(&fam, influence, r0) * r0 * peri_eval_beta(&fam, r0) * (uniform ? V_i : V[j]);
    we_x += wt * (e_total - eth_i * r0);
    w_xx += wt * r0;
  }
  *we_x_out = we_x;
  *w_xx_out = w_xx;
  *smin_out = smin;
  return excess > 0.0;
}

/* Pass 1 for every owned node: break bonds beyond their critical stretch, then the dilatation
 * theta, P and the two per-node coefficients of the force pass. With
 *   A_i = n_theta (K_theta theta_i - alpha_i P_i/3)/m_i,  B_i = alpha_i = (alpha m)/m_i,
 *   D_i = A_i - B_i (alpha_T dT_i + theta_i/3),
 * the pair force of the header is t_ij + t_ji = omega (|xi| (D_i + D_j) + e (B_i + B_j)), so the
 * force pass gathers two numbers per neighbour. */
/* One function per specialization (the OpenMP region is outlined before inlining). A damaged
 * family runs the loop on its intact neighbours only, copied a chunk at a time. */
typedef long (*lps_sums_fn)(const peri_bond_view *, int32_t, int64_t, int64_t, double *, double *, double *);
#define LPS_SUMS_VARIANT(NAME, THERMAL, INFLUENCE, UNIFORM)                                                  \
  static long NAME(const peri_bond_view *w, int32_t i, int64_t k0, int64_t k1, double *we_x, double *w_xx,          \
                   double *smin) {                                                                           \
    if (!memchr(w->broken + k0, 1, (size_t)(k1 - k0)))                                                       \
      return lps_node_sums(w, i, w->neighbor + k0, k1 - k0, THERMAL, INFLUENCE, UNIFORM, we_x, w_xx, smin);  \
    int32_t intact[PERI_INTACT_CHUNK];                                                                       \
    long candidate = 0;                                                                                      \
    *we_x = *w_xx = 0.0;                                                                                     \
    *smin = INFINITY;                                                                                        \
    for (int64_t k = k0; k < k1;) {                                                                          \
      const int n = peri_next_intact(w->neighbor, w->broken, &k, k1, intact);                                \
      double a, b, c;                                                                                        \
      candidate |= lps_node_sums(w, i, intact, n, THERMAL, INFLUENCE, UNIFORM, &a, &b, &c);                  \
      *we_x += a;                                                                                            \
      *w_xx += b;                                                                                            \
      *smin = peri_min(*smin, c);                                                                            \
    }                                                                                                        \
    return candidate;                                                                                        \
  }
/* "uniform": every node has the same volume (a grid), so the loop does not gather it */
LPS_SUMS_VARIANT(lps_sums_uniform, false, PERI_INFLUENCE_CONSTANT, true)
LPS_SUMS_VARIANT(lps_sums_plain, false, PERI_INFLUENCE_CONSTANT, false)
LPS_SUMS_VARIANT(lps_sums_thermal, true, PERI_INFLUENCE_CONSTANT, false)
LPS_SUMS_VARIANT(lps_sums_inverse, false, PERI_INFLUENCE_INVERSE, false)
LPS_SUMS_VARIANT(lps_sums_inverse_thermal, true, PERI_INFLUENCE_INVERSE, false)
LPS_SUMS_VARIANT(lps_sums_gaussian, false, PERI_INFLUENCE_GAUSSIAN, false)
LPS_SUMS_VARIANT(lps_sums_gaussian_thermal, true, PERI_INFLUENCE_GAUSSIAN, false)

static long lps_dilatation(peri_sim *s) {
  peri_update_s0_bound(s);
  const bool thermal = s->thermal_strain != NULL;
  lps_sums_fn sums = thermal ? lps_sums_thermal : peri_uniform_volume(&s->p) ? lps_sums_uniform : lps_sums_plain;
  if (s->family.influence == PERI_INFLUENCE_INVERSE) sums = thermal ? lps_sums_inverse_thermal : lps_sums_inverse;
  if (s->family.influence == PERI_INFLUENCE_GAUSSIAN) sums = thermal ? lps_sums_gaussian_thermal : lps_sums_gaussian;
  peri_particles *p = &s->p;
  const peri_bonds *b = &s->bonds;
  const peri_bond_view w = peri_bond_view_of(s);
  const bool track_smin = s->s0_node != NULL, breaking = s->breaking;
  long n_broken = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : n_broken)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const int64_t k0 = b->offset[i], k1 = b->offset[i + 1];
    double we_x, w_xx, smin;
    const long candidates = sums(&w, i, k0, k1, &we_x, &w_xx, &smin);
    if (breaking && candidates > 0) {
      const long nb = peri_break_family(s, i);
      if (nb > 0) {
        n_broken += nb;
        double unused;
        sums(&w, i, k0, k1, &we_x, &w_xx, &unused);
      }
    }
    const peri_material *mat = &s->materials[p->material[i]];
    const double m = p->wvol[i];
    const double theta = mat->n_theta * we_x / m;
    const double P = we_x - theta * w_xx / 3.0;
    const double alpha = mat->alpha_m / m;
    const double eth_i = thermal ? s->thermal_strain[i] : 0.0;
    p->theta[i] = theta;
    p->pstate[i] = P;
    p->coef[2 * i] = mat->n_theta * (mat->K_theta * theta - alpha * P / 3.0) / m - alpha * (eth_i + theta / 3.0);
    p->coef[2 * i + 1] = alpha;
    if (track_smin) p->smin[i] = smin;
  }
  return n_broken;
}

/* Scalar force state t_ij of node i's half of the bond with extension e, length L. */
static inline double lps_half(const peri_material *mat, double theta, double P, double m,
                              double omega, double L, double e) {
  const double alpha = mat->alpha_m / m;
  return mat->n_theta * (mat->K_theta * theta - alpha * P / 3.0) * omega * L / m +
         alpha * omega * (e - theta * L / 3.0);
}

/* Pass 2 for node i: f_i = sum_j (t_ij + t_ji) M_ij beta V_j over the intact bonds to nbr[]. */
static inline __attribute__((always_inline)) void lps_node_force(const peri_bond_view *w, int32_t i, const int32_t *restrict nbr,
                                                                 int64_t count, peri_influence influence, bool uniform,
                                                                 double f[3]) {
  const double *restrict x = w->x, *restrict u = w->u, *restrict V = w->V, *restrict coef = w->coef;
  const peri_family_eval fam = w->fam;
  const double xi0 = x[3 * i], xi1 = x[3 * i + 1], xi2 = x[3 * i + 2];
  const double ui0 = u[3 * i], ui1 = u[3 * i + 1], ui2 = u[3 * i + 2];
  const double Di = coef[2 * i], Bi = coef[2 * i + 1];
  double fx = 0.0, fy = 0.0, fz = 0.0;
#pragma omp simd reduction(+ : fx, fy, fz)
  for (int64_t a = 0; a < count; ++a) {
    const int32_t j = nbr[a];
    const double x0 = x[3 * j] - xi0, x1 = x[3 * j + 1] - xi1, x2 = x[3 * j + 2] - xi2;
    const double y0 = x0 + (u[3 * j] - ui0), y1 = x1 + (u[3 * j + 1] - ui1), y2 = x2 + (u[3 * j + 2] - ui2);
    const double r0 = sqrt(x0 * x0 + x1 * x1 + x2 * x2);
    const double r = sqrt(y0 * y0 + y1 * y1 + y2 * y2);
    const double t = peri_eval_omega(&fam, influence, r0) * (r0 * (Di + coef[2 * j]) + (r - r0) * (Bi + coef[2 * j + 1]));
    const double scale = t * peri_eval_beta(&fam, r0) * (uniform ? V[i] : V[j]) / r;
    const double g = r > 0.0 ? scale : 0.0;
    fx += g * y0;
    fy += g * y1;
    fz += g * y2;
  }
  f[0] = fx;
  f[1] = fy;
  f[2] = fz;
}

typedef void (*lps_force_fn)(const peri_bond_view *, int32_t, int64_t, int64_t, double *);
#define LPS_FORCE_VARIANT(NAME, INFLUENCE, UNIFORM)                                                 \
  static void NAME(const peri_bond_view *w, int32_t i, int64_t k0, int64_t k1, double *f) {                \
    if (!memchr(w->broken + k0, 1, (size_t)(k1 - k0))) {                                             \
      lps_node_force(w, i, w->neighbor + k0, k1 - k0, INFLUENCE, UNIFORM, f);                        \
      return;                                                                                        \
    }                                                                                                \
    int32_t intact[PERI_INTACT_CHUNK];                                                               \
    double sum[3] = {0.0, 0.0, 0.0};                                                                 \
    for (int64_t k = k0; k < k1;) {                                                                  \
      const int n = peri_next_intact(w->neighbor, w->broken, &k, k1, intact);                        \
      double fc[3];                                                                                  \
      lps_node_force(w, i, intact, n, INFLUENCE, UNIFORM, fc);                                       \
      for (int d = 0; d < 3; ++d) sum[d] += fc[d];                                                   \
    }                                                                                                \
    for (int d = 0; d < 3; ++d) f[d] = sum[d];                                                       \
  }
LPS_FORCE_VARIANT(lps_force_uniform, PERI_INFLUENCE_CONSTANT, true)
LPS_FORCE_VARIANT(lps_force_constant, PERI_INFLUENCE_CONSTANT, false)
LPS_FORCE_VARIANT(lps_force_inverse, PERI_INFLUENCE_INVERSE, false)
LPS_FORCE_VARIANT(lps_force_gaussian, PERI_INFLUENCE_GAUSSIAN, false)

static long lps_force(peri_sim *s) {
  long n_broken = lps_dilatation(s);
  if (s->s0_node) peri_update_lammps_s0(s);
  peri_sim_exchange(s, s->p.coef, 2); /* the force pass reads D_j and B_j of ghosts (docs/parallel.md) */
  peri_particles *p = &s->p;
  const peri_bonds *b = &s->bonds;
  const peri_bond_view w = peri_bond_view_of(s);
  lps_force_fn node = s->family.influence == PERI_INFLUENCE_INVERSE    ? lps_force_inverse
                      : s->family.influence == PERI_INFLUENCE_GAUSSIAN ? lps_force_gaussian
                      : peri_uniform_volume(p)                         ? lps_force_uniform
                                                                       : lps_force_constant;
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) node(&w, i, b->offset[i], b->offset[i + 1], &p->f[3 * (size_t)i]);
  return n_broken;
}

/* sum_j omega (e^d)^2 beta V_j over node i's intact bonds, e^d = e - alpha_T dT_i |xi| - theta_i |xi|/3. */
static inline __attribute__((always_inline)) double lps_node_energy(const peri_bond_view *w, int32_t i,
                                                                    const int32_t *restrict nbr, int64_t count,
                                                                    double theta, double eth_i, peri_influence influence) {
  const double *restrict x = w->x, *restrict u = w->u, *restrict V = w->V;
  const peri_family_eval fam = w->fam;
  const double xi0 = x[3 * i], xi1 = x[3 * i + 1], xi2 = x[3 * i + 2];
  const double ui0 = u[3 * i], ui1 = u[3 * i + 1], ui2 = u[3 * i + 2];
  const double shift = eth_i + theta / 3.0;
  double sum = 0.0;
#pragma omp simd reduction(+ : sum)
  for (int64_t a = 0; a < count; ++a) {
    const int32_t j = nbr[a];
    const double x0 = x[3 * j] - xi0, x1 = x[3 * j + 1] - xi1, x2 = x[3 * j + 2] - xi2;
    const double y0 = x0 + (u[3 * j] - ui0), y1 = x1 + (u[3 * j + 1] - ui1), y2 = x2 + (u[3 * j + 2] - ui2);
    const double r0 = sqrt(x0 * x0 + x1 * x1 + x2 * x2);
    const double ed = sqrt(y0 * y0 + y1 * y1 + y2 * y2) - r0 - shift * r0;
    const double e = peri_eval_omega(&fam, influence, r0) * ed * ed * peri_eval_beta(&fam, r0) * V[j];
    sum += e;
  }
  return sum;
}

typedef double (*lps_energy_fn)(const peri_bond_view *, int32_t, int64_t, int64_t, double, double);
#define LPS_ENERGY_VARIANT(NAME, INFLUENCE)                                                            \
  static double NAME(const peri_bond_view *w, int32_t i, int64_t k0, int64_t k1, double theta, double eth_i) { \
    if (!memchr(w->broken + k0, 1, (size_t)(k1 - k0)))                                                 \
      return lps_node_energy(w, i, w->neighbor + k0, k1 - k0, theta, eth_i, INFLUENCE);                \
    int32_t intact[PERI_INTACT_CHUNK];                                                                 \
    double sum = 0.0;                                                                                  \
    for (int64_t k = k0; k < k1;) {                                                                    \
      const int n = peri_next_intact(w->neighbor, w->broken, &k, k1, intact);                          \
      sum += lps_node_energy(w, i, intact, n, theta, eth_i, INFLUENCE);                                \
    }                                                                                                  \
    return sum;                                                                                        \
  }
LPS_ENERGY_VARIANT(lps_energy_constant, PERI_INFLUENCE_CONSTANT)
LPS_ENERGY_VARIANT(lps_energy_inverse, PERI_INFLUENCE_INVERSE)
LPS_ENERGY_VARIANT(lps_energy_gaussian, PERI_INFLUENCE_GAUSSIAN)

/* W_i = K_theta theta_i^2/2 + (alpha_i/2) sum_j w (e^d)^2 W_ij. Not on the time-step path. */
static void lps_energy(peri_sim *s, double *W) {
  peri_particles *p = &s->p;
  const peri_bonds *b = &s->bonds;
  bool breaking = s->breaking;
  s->breaking = false;
  lps_dilatation(s);
  s->breaking = breaking;
  const peri_bond_view w = peri_bond_view_of(s);
  lps_energy_fn node = s->family.influence == PERI_INFLUENCE_INVERSE    ? lps_energy_inverse
                       : s->family.influence == PERI_INFLUENCE_GAUSSIAN ? lps_energy_gaussian
                                                                        : lps_energy_constant;
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const peri_material *mat = &s->materials[p->material[i]];
    const double theta = p->theta[i];
    const double eth_i = s->thermal_strain ? s->thermal_strain[i] : 0.0;
    const double sum = node(&w, i, b->offset[i], b->offset[i + 1], theta, eth_i);
    W[i] = 0.5 * mat->K_theta * theta * theta + 0.5 * (mat->alpha_m / p->wvol[i]) * sum;
  }
}

static double lps_pair_force(const peri_sim *s, int32_t i, int64_t k, double r) {
  const peri_particles *p = &s->p;
  const peri_bonds *b = &s->bonds;
  const int32_t j = b->neighbor[k];
  const double L = peri_bond_length(p->x, i, j), e = r - L, omega = peri_bonds_omega(b, L);
  const double eth_i = s->thermal_strain ? s->thermal_strain[i] : 0.0;
  const double eth_j = s->thermal_strain ? s->thermal_strain[j] : 0.0;
  return lps_half(&s->materials[p->material[i]], p->theta[i], p->pstate[i], p->wvol[i], omega, L,
                  e - eth_i * L) +
         lps_half(&s->materials[p->material[j]], p->theta[j], p->pstate[j], p->wvol[j], omega, L,
                  e - eth_j * L);
}

const peri_model_ops peri_model_lps = {
    .name = "lps",
    .description = "ordinary state-based linear peridynamic solid (any Poisson ratio)",
    .fixed_poisson = 0,
    .init = lps_init,
    .force = lps_force,
    .energy = lps_energy,
    .pair_force = lps_pair_force,
    .tangent = peri_lps_tangent, .tangent_reach = 2, /* src/model/lps_tangent.c */
};
