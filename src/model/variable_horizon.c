/* PMB and LPS with a horizon per node (docs/variable_horizon.md, docs/model_reference.md 15).
 * Node i's force state has its own horizon delta_i: T_i<xi> = t_i(xi) M with the partial
 * volume and influence of i's horizon, zero beyond it. A bond i-j exists when |xi| is within
 * max(delta_i, delta_j) (include/peri/bonds.h), and the full peridynamic force is
 *   f_i = sum_j (t_i<xi_ij> + t_j<xi_ji>) M_ij V_j,
 * each end with its own constants, which pass the patch test only where delta is constant:
 * the nodes of the coupling region take the divergence of the partial stress instead
 * (partial_stress.c). Per-node constants:
 *   PMB: t_i = c_i omega beta_i s / 2, c_i = c(delta_i) S(delta_i) / S_i with c(delta) the
 *        micromodulus of docs/model_reference.md 2.3, S(delta) = int |xi| dV over the horizon
 *        and S_i = sum_j omega beta_i |xi| V_j its discrete value (with omega = 1/|xi| this
 *        is the symmetric micromodulus d^2 K (1/V_H,i + 1/V_H,j)/|xi| of section 15.3);
 *   LPS: the model of lps.c with the weighted volume m_i, dilatation and P_i of i's own
 *        horizon (T_delta = delta^-(d+1) Z<xi/delta> follows from m_i ~ delta^(d+2)).
 * This is a per-node path without the node blocks of pmb.c and lps.c: the force states are
 * stored per directed bond, since the partial stress needs them. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/constants.h"
#include "peri/error.h"
#include "peri/horizon_field.h"
#include "peri/model.h"
#include "peri/variable_horizon.h"
#include "bond_kernel.h"
#include "partial_stress.h"

typedef enum { VH_PMB, VH_LPS } vh_kind;

/* omega beta of a bond of reference length r0 in the horizon delta_i */
static inline double vh_weight(const peri_family_params *f, double delta_i, double r0) {
  return peri_partial_volume_factor(f->rule, r0, delta_i, f->spacing) * peri_influence_value(f->influence, r0, delta_i);
}

/* int |xi| dV over a horizon of radius delta (the thickness or cross-section included) */
static double horizon_first_moment(const peri_geometry *g, double delta) {
  const double radial = peri_influence_moment(PERI_INFLUENCE_CONSTANT, g->dim, delta);
  if (g->dim == 3) return 4.0 * M_PI * radial;
  if (g->dim == 2) return 2.0 * M_PI * g->thickness * radial;
  return 2.0 * g->cross_section * radial;
}

/* PMB without a coupling region: the per-bond constants of the one-pass force (vh_pmb_force_fused),
 * from the node constants c_i (both ends' before the pairs are formed). */
static void pmb_bond_constants(peri_sim *s) {
  peri_horizon_field *h = s->disc.horizon_field;
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const size_t nb = (size_t)(b->n_bonds > 0 ? b->n_bonds : 1);
  h->bond_length = peri_malloc(nb * sizeof(double));
  double *state = peri_malloc(nb * sizeof(double)); /* t_i<xi_ij> / e of each directed bond */
  h->bond_pair_state = peri_malloc(nb * sizeof(double));
  h->bond_pair = peri_malloc(nb * sizeof(double));
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i)
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const double r0 = peri_bond_length(p->x, i, b->neighbor[k]);
      h->bond_length[k] = r0;
      state[k] = 0.5 * h->node_constant[i] * vh_weight(&b->family, h->delta[i], r0) / r0;
    }
  /* both ends' states of each bond in the bond's own entry, so that the force and the pair
   * force read no reverse bond (on MPI ranks the reverse of a bond into a ghost is not here) */
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i)
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      h->bond_pair_state[k] = state[k] + state[h->reverse[k]];
      h->bond_pair[k] = h->bond_pair_state[k] * p->volume[b->neighbor[k]];
    }
  free(state);
}

static void vh_pmb_states(peri_sim *s);
static void vh_lps_states(peri_sim *s);

static int vh_init(peri_sim *s, vh_kind kind) {
  peri_horizon_field *h = s->disc.horizon_field;
  peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const peri_family_params *f = &b->family;
  const size_t nb = (size_t)(b->n_bonds > 0 ? b->n_bonds : 1), n = (size_t)(p->n > 0 ? p->n : 1);
  h->state = peri_calloc(nb, sizeof(double));
  h->node_constant = peri_calloc(n, sizeof(double));
  peri_horizon_field_reverse_bonds(h, b);
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const double delta = h->delta[i];
    double sum = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const double r0 = peri_bond_length(p->x, i, b->neighbor[k]);
      sum += vh_weight(f, delta, r0) * r0 * (kind == VH_LPS ? r0 : 1.0) * p->volume[b->neighbor[k]];
    }
    const peri_material *mat = &s->mat.materials[p->material[i]];
    peri_geometry g = s->disc.geom;
    g.horizon = delta;
    if (kind == VH_LPS && s->disc.analytic_weighted_volume) sum = peri_weighted_volume_analytic(&g, f->influence);
    if (!(sum > 0.0)) {
      peri_error("node at (%g, %g, %g) has no bonds within its horizon %g", p->x[3 * i], p->x[3 * i + 1],
                 p->x[3 * i + 2], delta);
      return PERI_ERR_INPUT;
    }
    h->node_constant[i] = kind == VH_PMB ? peri_pmb_micromodulus(&g, mat->E, mat->K) * horizon_first_moment(&g, delta) / sum
                                         : sum;
  }
  /* the stable time step reads one micromodulus per material: the stiffest node's (that of
   * the smallest horizon), a bound for every node */
  peri_geometry smallest = s->disc.geom;
  smallest.horizon = h->min;
  for (int m = 0; m < s->mat.n_materials; ++m) {
    peri_material *mat = &s->mat.materials[m];
    if (kind == VH_LPS) {
      peri_lps_constants(&s->disc.geom, mat->K, mat->mu, &mat->n_theta, &mat->K_theta, &mat->alpha_m);
      mat->c_stable = peri_stable_micromodulus(&smallest, peri_pwave_modulus(&s->disc.geom, mat->E, mat->nu, mat->K, mat->mu));
    } else {
      mat->c_stable = 0.0;
      for (int32_t i = 0; i < p->n_owned; ++i)
        if (p->material[i] == m) mat->c_stable = fmax(mat->c_stable, h->node_constant[i]);
      mat->micromodulus = mat->c_stable;
    }
  }
  if (kind == VH_PMB && h->n_coupled == 0) pmb_bond_constants(s);
  if (kind == VH_LPS) {
    p->theta = peri_calloc(n, sizeof(double));
    p->pstate = peri_calloc(n, sizeof(double));
    p->wvol = peri_calloc(n, sizeof(double));
    memcpy(p->wvol, h->node_constant, sizeof(double) * (size_t)p->n);
  }
  return h->n_coupled > 0 ? peri_partial_stress_prepare(s, kind == VH_LPS ? vh_lps_states : vh_pmb_states) : PERI_OK;
}

static int vh_pmb_init(peri_sim *s) { return vh_init(s, VH_PMB); }
static int vh_lps_init(peri_sim *s) { return vh_init(s, VH_LPS); }

/* Breaks every intact bond beyond its critical stretch (the same decision from both ends);
 * a bond of a coupled node stays intact and is counted in h->ps_would_break, with a warning
 * the first time (cracks belong to the full peridynamic region). */
static long vh_break(peri_sim *s) {
  peri_horizon_field *h = s->disc.horizon_field;
  const peri_particles *p = &s->disc.p;
  peri_bonds *b = &s->disc.bonds;
  long broken = 0, kept = 0;
  int32_t first_kept = -1;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : broken, kept)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double dy[3];
      const double r0 = peri_bond_length(p->x, i, j), r = peri_deformed_bond(p->x, p->u, i, j, dy);
      const double s0 = peri_bond_s0(s, i, j) * fmin(h->s0_scale[i], h->s0_scale[j]);
      if (!((r - r0) / r0 > s0)) continue;
      if (h->coupled[i] || h->coupled[j]) {
        kept++;
#pragma omp critical(vh_first_kept)
        if (first_kept < 0 || i < first_kept) first_kept = i;
        continue;
      }
      b->broken[k] = 1;
      broken++;
    }
  }
  if (kept > 0 && h->ps_would_break == 0) {
    const double *x = p->x + 3 * (size_t)first_kept;
    peri_warning("partial stress: %ld bond directions of the coupling region are beyond their critical stretch "
                 "(first at the node at (%g, %g, %g)); they are kept intact, since cracks may only run where the "
                 "force is full peridynamics (docs/variable_horizon.md)",
                 kept, x[0], x[1], x[2]);
  }
  h->ps_would_break += kept;
  return broken;
}

/* LPS: theta_i and P_i of node i's horizon (lps.c), from the intact bonds */
static void vh_lps_dilatation(peri_sim *s) {
  peri_horizon_field *h = s->disc.horizon_field;
  peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double we_x = 0.0, w_xx = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double dy[3];
      const double r0 = peri_bond_length(p->x, i, j), r = peri_deformed_bond(p->x, p->u, i, j, dy);
      const double w = vh_weight(&b->family, h->delta[i], r0) * r0 * p->volume[j];
      we_x += w * (r - r0);
      w_xx += w * r0;
    }
    const peri_material *mat = &s->mat.materials[p->material[i]];
    const double m = h->node_constant[i], theta = mat->n_theta * we_x / m;
    p->theta[i] = theta;
    p->pstate[i] = we_x - theta * (mat->peer_force_state ? m : w_xx) / 3.0;
  }
}

/* t_i<xi_ij> of node i's bond to j (intact), from i's constants and its dilatation and P_i (LPS) */
static inline double vh_state(const peri_sim *s, vh_kind kind, int32_t i, int32_t j) {
  const peri_horizon_field *h = s->disc.horizon_field;
  const peri_particles *p = &s->disc.p;
  double dy[3];
  const double r0 = peri_bond_length(p->x, i, j), r = peri_deformed_bond(p->x, p->u, i, j, dy);
  const double c = h->node_constant[i], w = vh_weight(&s->disc.bonds.family, h->delta[i], r0), e = r - r0;
  if (kind == VH_PMB) return 0.5 * c * w * e / r0;
  /* lps.c lps_half: n_theta (K_theta theta - alpha P/3) omega L/m + alpha omega e^d */
  const peri_material *mat = &s->mat.materials[p->material[i]];
  const double alpha = mat->alpha_m / c, theta = p->theta[i];
  return w * (mat->n_theta * (mat->K_theta * theta - alpha * p->pstate[i] / 3.0) * r0 / c +
              alpha * (e - theta * r0 / 3.0));
}

/* t_i<xi_ij> of every intact directed bond into h->state (0 for a broken one) */
static void vh_states(peri_sim *s, vh_kind kind) {
  peri_horizon_field *h = s->disc.horizon_field;
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    if (h->local && h->local[i]) { /* a local node has no force state (partial_stress.c) */
      for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) h->state[k] = 0.0;
      continue;
    }
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k)
      h->state[k] = b->broken[k] ? 0.0 : vh_state(s, kind, i, b->neighbor[k]);
  }
}

/* t_j<xi_ji> of bond k = i -> j: the state of its reverse bond, or on MPI ranks (no reverse
 * bonds: j may be a ghost) the same operations from j's constants, horizon, dilatation and P_j
 * (exchanged), which give the same number; both directions of a bond break together. */
static inline double vh_other_state(const peri_sim *s, vh_kind kind, int32_t i, int64_t k) {
  const peri_horizon_field *h = s->disc.horizon_field;
  if (h->reverse) return h->state[h->reverse[k]];
  return s->disc.bonds.broken[k] ? 0.0 : vh_state(s, kind, s->disc.bonds.neighbor[k], i);
}

/* the force states of the current displacement, for the lattice probe of partial_stress.c */
static void vh_pmb_states(peri_sim *s) { vh_states(s, VH_PMB); }
static void vh_lps_states(peri_sim *s) {
  vh_lps_dilatation(s);
  vh_states(s, VH_LPS);
}

/* The critical elongation s0 |xi| of every directed bond for vh_pmb_force_fused, set at its
 * first call (after the deck's no-fail regions): infinite for a bond that never breaks. */
static void pmb_bond_critical(peri_sim *s) {
  peri_horizon_field *h = s->disc.horizon_field;
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  h->bond_critical = peri_malloc((size_t)(b->n_bonds > 0 ? b->n_bonds : 1) * sizeof(double));
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i)
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      h->bond_critical[k] = h->bond_length[k] * peri_bond_s0(s, i, j) * fmin(h->s0_scale[i], h->s0_scale[j]);
    }
}

/* PMB without a coupling region, breaking before the force or not at all: vh_break, vh_states
 * and the force loop of vh_force in one pass over the bonds, with the constants of
 * pmb_bond_constants and pmb_bond_critical. Both directions of a bond see the same stretch and
 * critical stretch, so each end breaks its own direction with the decision of vh_break. The
 * scalar states are not stored: vh_pair_force computes them from the deformed length. The loop
 * stays scalar: vectorised, its gathers of the neighbours' x and u made it 1.4 times slower
 * (measured on examples/graded_notched_beam.yaml; pmb.c avoids them with its node blocks). */
#if defined(__GNUC__) && !defined(__clang__)
#define VH_SCALAR_LOOP __attribute__((optimize("no-tree-vectorize")))
#else
#define VH_SCALAR_LOOP /* (clang has no per-function optimization options) */
#endif
VH_SCALAR_LOOP static long vh_pmb_force_fused(peri_sim *s) {
  peri_horizon_field *h = s->disc.horizon_field;
  peri_particles *p = &s->disc.p;
  peri_bonds *b = &s->disc.bonds;
  if (!h->bond_critical) pmb_bond_critical(s);
  const bool breaking = s->solver.breaking;
  const double *restrict x = p->x, *restrict u = p->u, *restrict length = h->bond_length, *restrict pair = h->bond_pair,
                         *restrict critical = h->bond_critical;
  const int32_t *restrict neighbor = b->neighbor;
  uint8_t *restrict broken_flag = b->broken;
  long broken = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : broken)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const double yi0 = x[3 * (size_t)i] + u[3 * (size_t)i], yi1 = x[3 * (size_t)i + 1] + u[3 * (size_t)i + 1],
                 yi2 = x[3 * (size_t)i + 2] + u[3 * (size_t)i + 2];
    double f0 = 0.0, f1 = 0.0, f2 = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (broken_flag[k]) continue;
      const size_t j = (size_t)neighbor[k];
      const double d0 = x[3 * j] + u[3 * j] - yi0, d1 = x[3 * j + 1] + u[3 * j + 1] - yi1,
                   d2 = x[3 * j + 2] + u[3 * j + 2] - yi2;
      const double r = sqrt(d0 * d0 + d1 * d1 + d2 * d2), e = r - length[k];
      if (breaking && e > critical[k]) {
        broken_flag[k] = 1;
        broken++;
        continue;
      }
      if (!(r > 0.0)) continue;
      const double g = pair[k] * e / r;
      f0 += g * d0, f1 += g * d1, f2 += g * d2;
    }
    p->f[3 * (size_t)i] = f0, p->f[3 * (size_t)i + 1] = f1, p->f[3 * (size_t)i + 2] = f2;
  }
  return broken;
}

static long vh_force(peri_sim *s, vh_kind kind) {
  if (kind == VH_PMB && s->disc.horizon_field->bond_pair && !s->solver.break_after_force && !s->mat.s0_node)
    return vh_pmb_force_fused(s);
  peri_horizon_field *h = s->disc.horizon_field;
  peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const bool breaking = s->solver.breaking, after = s->solver.break_after_force;
  long broken = breaking && !after ? vh_break(s) : 0;
  if (kind == VH_LPS) {
    vh_lps_dilatation(s);
    peri_sim_exchange(s, p->theta, 1); /* (the ghosts' theta and P: their bonds' states here) */
    peri_sim_exchange(s, p->pstate, 1);
  }
  vh_states(s, kind);
  /* the full peridynamic force outside the coupling region */
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    if (h->coupled[i]) continue;
    double f[3] = {0, 0, 0};
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double dy[3];
      const double r = peri_deformed_bond(p->x, p->u, i, j, dy);
      if (!(r > 0.0)) continue;
      const double g = (h->state[k] + vh_other_state(s, kind, i, k)) * p->volume[j] / r;
      for (int a = 0; a < 3; ++a) f[a] += g * dy[a];
    }
    for (int a = 0; a < 3; ++a) p->f[3 * (size_t)i + a] = f[a];
  }
  if (h->n_coupled > 0) peri_partial_stress_force(s);
  if (breaking && after) broken = vh_break(s);
  return broken;
}

static long vh_pmb_force(peri_sim *s) { return vh_force(s, VH_PMB); }
static long vh_lps_force(peri_sim *s) { return vh_force(s, VH_LPS); }

/* W_i: PMB 1/4 sum_j c_i omega beta_i s^2 |xi| V_j (half of each bond's micropotential goes
 * to each end, each end with its own horizon); LPS K_theta theta_i^2/2 + (alpha_m/m_i)/2
 * sum_j omega beta_i (e^d)^2 V_j as in lps.c (the peer form's energy for the peer state). */
static void vh_energy(peri_sim *s, double *W, vh_kind kind) {
  peri_horizon_field *h = s->disc.horizon_field;
  peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  if (kind == VH_LPS) vh_lps_dilatation(s);
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    if (h->local && h->local[i]) { /* 1/2 sigma : eps of its least-squares strain */
      W[i] = peri_partial_stress_local_energy(s, i);
      continue;
    }
    const peri_material *mat = &s->mat.materials[p->material[i]];
    const double c = h->node_constant[i];
    const double theta = kind == VH_LPS ? p->theta[i] : 0.0;
    double sum = 0.0, sum_e2 = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double dy[3];
      const double r0 = peri_bond_length(p->x, i, j), r = peri_deformed_bond(p->x, p->u, i, j, dy);
      const double w = vh_weight(&b->family, h->delta[i], r0) * p->volume[j], e = r - r0;
      if (kind == VH_PMB) {
        sum += 0.25 * c * w * e * e / r0;
      } else {
        const double ed = e - theta * r0 / 3.0;
        sum += w * ed * ed;
        sum_e2 += w * e * e;
      }
    }
    if (kind == VH_PMB) W[i] = sum;
    else
      W[i] = mat->peer_force_state ? peri_lps_peer_energy(mat, theta, mat->alpha_m / c, sum_e2)
                                   : 0.5 * mat->K_theta * theta * theta + 0.5 * (mat->alpha_m / c) * sum;
  }
}

static void vh_pmb_energy(peri_sim *s, double *W) { vh_energy(s, W, VH_PMB); }
static void vh_lps_energy(peri_sim *s, double *W) { vh_energy(s, W, VH_LPS); }

/* t_ij + t_ji at the deformed length r, over the family's partial volume (by which stress
 * recovery multiplies it): each end's partial volume is already in its state. PMB without a
 * coupling region from the per-bond constants (vh_pmb_force_fused stores no states), otherwise
 * the states of the last force evaluation. */
static double vh_pair_force(const peri_sim *s, vh_kind kind, int32_t i, int64_t k, double r) {
  const peri_horizon_field *h = s->disc.horizon_field;
  const peri_bonds *b = &s->disc.bonds;
  const double r0 = peri_bond_length(s->disc.p.x, i, b->neighbor[k]);
  const double beta = peri_bonds_beta(b, r0);
  if (!(beta > 0.0)) return 0.0;
  if (h->bond_pair_state) return b->broken[k] ? 0.0 : h->bond_pair_state[k] * (r - h->bond_length[k]) / beta;
  return (h->state[k] + vh_other_state(s, kind, i, k)) / beta;
}

static double vh_pmb_pair_force(const peri_sim *s, int32_t i, int64_t k, double r) {
  return vh_pair_force(s, VH_PMB, i, k, r);
}
static double vh_lps_pair_force(const peri_sim *s, int32_t i, int64_t k, double r) {
  return vh_pair_force(s, VH_LPS, i, k, r);
}

static const peri_model_ops vh_pmb = {
    .name = "pmb",
    .description = "bond-based PMB with a horizon per node",
    .fixed_poisson = 1,
    .init = vh_pmb_init,
    .force = vh_pmb_force,
    .energy = vh_pmb_energy,
    .pair_force = vh_pmb_pair_force,
};

static const peri_model_ops vh_lps = {
    .name = "lps",
    .description = "ordinary state-based LPS with a horizon per node",
    .fixed_poisson = 0,
    .init = vh_lps_init,
    .force = vh_lps_force,
    .energy = vh_lps_energy,
    .pair_force = vh_lps_pair_force,
};

const peri_model_ops *peri_variable_horizon_model(const peri_model_ops *model) {
  if (model == peri_model_find("pmb")) return &vh_pmb;
  if (model == peri_model_find("lps")) return &vh_lps;
  return NULL;
}
