/* Sublayer plasticity in the bond loops (model reference 16.2, docs/plasticity.md). Every
 * directed bond stores the plastic stretch of each sublayer; both ends of a bond compute
 * the same stretch bit for bit (the deformed vector from j is the exact negative of that
 * from i), so the two copies stay equal without any exchange, and each thread writes only
 * its own nodes' bonds. The return mapping runs at every force evaluation; it is idempotent
 * at a fixed stretch, so a second evaluation at the same displacement (the LAMMPS breaking
 * order, the energy) changes nothing. Quasi-static solvers map from the state of the last
 * accepted load step (s->state.plastic_committed), committed by peri_plastic_commit, so the
 * iterations of a solve, whose stretches overshoot on the way, leave no plastic trace: the
 * load step is a backward-Euler step of the flow.
 *
 * The force is the elastic one at the elastic stretch s^e = s - sum_k W_k s^p_k: PMB
 * f = c s^e omega beta V M; LPS with the elastic extension e^e = s^e |xi| in both the
 * dilatation sum and the deviatoric term (yield enters theta: a bond's plastic flow takes
 * part in the volume change its node sees). */
#include <math.h>
#include <string.h>
#include "peri/error.h"
#include "peri/plasticity.h"
#include "bond_kernel.h"
#include "plastic_bonds.h"

/* The sublayers of bond i-j: those of the common material; between two materials the ones
 * of the material that yields first (a symmetric choice); NULL when neither is plastic. */
static const peri_sublayers *bond_layers(const peri_sim *s, int32_t i, int32_t j) {
  const peri_particles *p = &s->disc.p;
  const peri_sublayers *a = s->mat.materials[p->material[i]].sublayers, *b = s->mat.materials[p->material[j]].sublayers;
  if (a == b || !b) return a;
  if (!a) return b;
  return a->yield[0] <= b->yield[0] ? a : b;
}

int peri_plastic_init(peri_sim *s) {
  int layers = 0;
  for (int m = 0; m < s->mat.n_materials; ++m)
    if (s->mat.materials[m].sublayers && s->mat.materials[m].sublayers->n > layers)
      layers = s->mat.materials[m].sublayers->n;
  if (layers == 0) return PERI_OK;
  if (s->disc.surface_correction != 0) {
    peri_error("plasticity: discretization.surface_correction is not available with plastic materials");
    return PERI_ERR_INPUT;
  }
  const size_t n = (size_t)s->disc.bonds.n_bonds * (size_t)layers;
  s->state.plastic_stretch = peri_calloc(n > 0 ? n : 1, sizeof(double));
  s->state.plastic_layers = layers;
  return PERI_OK;
}

double peri_plastic_bond_stretch(const peri_sim *s, int32_t i, int64_t k) {
  if (!s->state.plastic_stretch) return 0.0;
  const peri_sublayers *sl = bond_layers(s, i, s->disc.bonds.neighbor[k]);
  if (!sl) return 0.0;
  const double *sp = s->state.plastic_stretch + k * s->state.plastic_layers;
  double plastic = 0.0;
  for (int l = 0; l < sl->n; ++l) plastic += sl->weight[l] * sp[l];
  return plastic;
}

/* Bond k of node i at the current displacement: the deformed vector, its length and
 * reference length, and the mechanical stretch. */
typedef struct bond_state {
  double dy[3], r, r0, s;
} bond_state;

static inline bond_state bond_at(const peri_sim *s, int32_t i, int32_t j) {
  const peri_particles *p = &s->disc.p;
  bond_state st;
  st.r = peri_deformed_bond(p->x, p->u, i, j, st.dy);
  st.r0 = peri_bond_length(p->x, i, j);
  st.s = (st.r - st.r0) / st.r0 - peri_bond_thermal_stretch(s->state.thermal_strain, i, j);
  return st;
}

/* The breaking test and the return mapping of node i's intact bond k: 1 when it breaks
 * now, else 0 with the plastic part of its stretch in *plastic. */
static inline int break_or_return(peri_sim *s, int32_t i, int64_t k, int32_t j, double stretch, bool breaking,
                                  double *plastic) {
  if (breaking && stretch > peri_bond_s0(s, i, j)) {
    s->disc.bonds.broken[k] = 1;
    return 1;
  }
  const peri_sublayers *sl = bond_layers(s, i, j);
  const int64_t at = k * s->state.plastic_layers;
  const double *base = s->state.plastic_committed ? s->state.plastic_committed + at : s->state.plastic_stretch + at;
  *plastic = sl ? peri_sublayer_return_from(sl, 1.0, stretch, base, s->state.plastic_stretch + at) : 0.0;
  return 0;
}

void peri_plastic_commit(peri_sim *s) {
  if (s->state.plastic_committed)
    memcpy(s->state.plastic_committed, s->state.plastic_stretch,
           sizeof(double) * (size_t)s->state.plastic_layers * (size_t)s->disc.bonds.n_bonds);
}

long peri_plastic_pmb_force(peri_sim *s, bool update_s0) {
  peri_particles *p = &s->disc.p;
  peri_bonds *b = &s->disc.bonds;
  const bool breaking = s->solver.breaking, track_smin = s->mat.s0_node != NULL;
  long n_broken = 0;
#pragma omp parallel for schedule(static) reduction(+ : n_broken)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const double ci = s->mat.materials[p->material[i]].micromodulus;
    double f[3] = {0.0, 0.0, 0.0}, smin = INFINITY;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      const bond_state st = bond_at(s, i, j);
      smin = fmin(smin, st.s);
      double plastic = 0.0;
      if (break_or_return(s, i, k, j, st.s, breaking, &plastic)) {
        ++n_broken;
        continue;
      }
      const double c = 0.5 * (ci + s->mat.materials[p->material[j]].micromodulus);
      const double g = st.r > 0.0 ? c * (st.s - plastic) * peri_bonds_omega(b, st.r0) * peri_bonds_beta(b, st.r0) *
                                        p->volume[j] / st.r
                                  : 0.0;
      for (int d = 0; d < 3; ++d) f[d] += g * st.dy[d];
    }
    for (int d = 0; d < 3; ++d) p->f[3 * (size_t)i + d] = f[d];
    if (track_smin) p->smin[i] = smin;
  }
  if (n_broken > 0) ++b->broken_edits; /* the elastic loops' copies of the flags follow */
  if (track_smin && update_s0) peri_update_lammps_s0(s);
  return n_broken;
}

void peri_plastic_pmb_energy(peri_sim *s, double *W) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const double ci = s->mat.materials[p->material[i]].micromodulus;
    double sum = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      const bond_state st = bond_at(s, i, j);
      const peri_sublayers *sl = bond_layers(s, i, j);
      /* per bond sum_k W_k c (s - s^p_k)^2 |xi| / 2 (the elastic part of the micropotential) */
      const double e2 = sl ? peri_sublayer_energy(sl, st.s, s->state.plastic_stretch + k * s->state.plastic_layers)
                           : 0.5 * st.s * st.s;
      const double c = 0.5 * (ci + s->mat.materials[p->material[j]].micromodulus);
      sum += c * e2 * peri_bonds_omega(b, st.r0) * st.r0 * peri_bonds_beta(b, st.r0) * p->volume[j];
    }
    W[i] = 0.5 * sum;
  }
}

/* LPS pass 1: breaking, return mapping, dilatation theta, P and the force pass's per-node
 * coefficients D (coef[0 .. n-1]) and B = alpha (coef[n .. 2n-1]) as in src/model/lps.c, with
 * the elastic extension e^e = (s - s^p) |xi| in place of e. */
static long lps_plastic_dilatation(peri_sim *s) {
  peri_particles *p = &s->disc.p;
  peri_bonds *b = &s->disc.bonds;
  const double *eth = s->state.thermal_strain;
  const bool breaking = s->solver.breaking, track_smin = s->mat.s0_node != NULL;
  const size_t n = (size_t)p->n;
  long n_broken = 0;
#pragma omp parallel for schedule(static) reduction(+ : n_broken)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const double eth_i = eth ? eth[i] : 0.0;
    double we_x = 0.0, w_xx = 0.0, smin = INFINITY;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      const bond_state st = bond_at(s, i, j);
      smin = fmin(smin, st.s);
      double plastic = 0.0;
      if (break_or_return(s, i, k, j, st.s, breaking, &plastic)) {
        ++n_broken;
        continue;
      }
      const double w = peri_bonds_omega(b, st.r0) * st.r0 * peri_bonds_beta(b, st.r0) * p->volume[j];
      we_x += w * (st.r - st.r0 - (plastic + eth_i) * st.r0);
      w_xx += w * st.r0;
    }
    const peri_material *mat = &s->mat.materials[p->material[i]];
    const double m = p->wvol[i];
    const double theta = mat->n_theta * we_x / m;
    const double P = we_x - theta * (mat->peer_force_state ? m : w_xx) / 3.0;
    const double alpha = mat->alpha_m / m;
    p->theta[i] = theta;
    p->pstate[i] = P;
    p->coef[i] = mat->n_theta * (mat->K_theta * theta - alpha * P / 3.0) / m - alpha * (eth_i + theta / 3.0);
    p->coef[n + (size_t)i] = alpha;
    if (track_smin) p->smin[i] = smin;
  }
  if (n_broken > 0) ++b->broken_edits;
  return n_broken;
}

long peri_plastic_lps_force(peri_sim *s, bool update_s0) {
  const long broken = lps_plastic_dilatation(s);
  if (s->mat.s0_node && update_s0) peri_update_lammps_s0(s);
  peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const size_t n = (size_t)p->n;
  peri_sim_exchange(s, p->coef, 1);
  peri_sim_exchange(s, p->coef + n, 1);
  const double *D = p->coef, *B = p->coef + n;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double f[3] = {0.0, 0.0, 0.0};
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      const bond_state st = bond_at(s, i, j);
      const double e_elastic = st.r - st.r0 - peri_plastic_bond_stretch(s, i, k) * st.r0;
      /* t_ij + t_ji = omega (|xi| (D_i + D_j) + e^e (B_i + B_j)) */
      const double t = peri_bonds_omega(b, st.r0) * (st.r0 * (D[i] + D[j]) + e_elastic * (B[i] + B[j]));
      const double g = st.r > 0.0 ? t * peri_bonds_beta(b, st.r0) * p->volume[j] / st.r : 0.0;
      for (int d = 0; d < 3; ++d) f[d] += g * st.dy[d];
    }
    for (int d = 0; d < 3; ++d) p->f[3 * (size_t)i + d] = f[d];
  }
  return broken;
}

void peri_plastic_lps_energy(peri_sim *s, double *W) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const double *eth = s->state.thermal_strain;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const double eth_i = eth ? eth[i] : 0.0;
    double wq = 0.0, wx = 0.0, q2 = 0.0; /* sum w q, sum w |xi|, sum omega beta V q^2 */
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      const bond_state st = bond_at(s, i, j);
      const double q = st.r - st.r0 - (peri_plastic_bond_stretch(s, i, k) + eth_i) * st.r0;
      const double obv = peri_bonds_omega(b, st.r0) * peri_bonds_beta(b, st.r0) * p->volume[j];
      wq += obv * st.r0 * q, wx += obv * st.r0 * st.r0, q2 += obv * q * q;
    }
    const peri_material *mat = &s->mat.materials[p->material[i]];
    const double m = p->wvol[i], theta = mat->n_theta * wq / m;
    const double deviatoric = q2 - (2.0 * theta / 3.0) * wq + (theta * theta / 9.0) * wx;
    W[i] = mat->peer_force_state ? peri_lps_peer_energy(mat, theta, mat->alpha_m / m, q2)
                                 : 0.5 * mat->K_theta * theta * theta + 0.5 * (mat->alpha_m / m) * deviatoric;
  }
}
