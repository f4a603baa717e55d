/* The deviatoric state-based sublayer rule of LPS in 3D (docs/plasticity.md section 8): the
 * overlay of Besseling on Mitchell's ordinary state-based plasticity (Mitchell 2011,
 * SAND2011-3166). Every node keeps, for each directed bond of its family and each sublayer k,
 * a plastic deviatoric stretch s^dp_k (the deviatoric plastic extension e^dp_k over |xi|), in
 * the per-bond, per-sublayer storage of the bond rule (s->state.plastic_stretch). The
 * deviatoric force state of node i is
 *   t^d_ij = alpha_i omega (e^d_ij - |xi| sum_k W_k s^dp_k,ij),   e^d = e - (theta_i/3) |xi|
 * with theta_i the elastic dilatation of the total extension (the bulk term stays elastic).
 * Sublayer k of node i is elastic-perfectly plastic on the deviatoric energy of its own force
 * state over the family,
 *   S_k = sum_j omega beta V_j |xi|^2 (s^d_ij - s^dp_k,ij)^2  <=  (3 mu / alpha_m) m_i e_yk^2,
 * the von Mises (distortion energy) criterion: in the continuum under a homogeneous
 * deviatoric strain eps^d, S = (2/15) m eps^d : eps^d, and at the uniaxial deviatoric yield
 * strain e_y (axial e_y, lateral -e_y/2) eps^d : eps^d = 3 e_y^2 / 2, so with alpha_m = 15 mu
 * the bound is m e_y^2 / 5. With omega = 1 it is Mitchell's ||t^d||^2 / 2 <= psi_0,
 * psi_0 = 25 sigma_y^2 / (8 pi delta^5). A sublayer beyond it returns radially: its elastic
 * deviatoric stretches s^d - s^dp_k are scaled by sqrt(bound / S_k) on every bond of the
 * family at once, the closest point in the energy norm (associated flow). All bonds of a node
 * therefore yield together.
 *
 * Each end of a bond keeps its own state. The pair force t_ij + t_ji needs the other end's
 * plastic term alpha_j sum_k W_k s^dp_k,ji: j's return mapping writes it where i's force pass
 * reads it in family order, s->state.plastic_reverse_term at the reverse bond's index
 * s->state.plastic_reverse[k] (each entry has one writer). On MPI ranks a bond into a ghost
 * has no local reverse (index -1): the ghost's owner sends the term through the bond halo
 * (src/parallel/bond_halo.c) after the return. No periodic images (a bond to an image has
 * no reverse). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/bond_halo.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/plasticity.h"
#include "bond_kernel.h"
#include "node_blocks.h"
#include "plastic_bonds.h"

bool peri_deviatoric_rule(const peri_sim *s) {
  for (int m = 0; m < s->mat.n_materials; ++m)
    if (s->mat.materials[m].sublayers && s->mat.materials[m].sublayers->deviatoric) return true;
  return false;
}

int peri_deviatoric_init(peri_sim *s) {
  const peri_bonds *b = &s->disc.bonds;
  const peri_particles *p = &s->disc.p;
  int64_t *reverse = peri_malloc(sizeof(int64_t) * (size_t)(b->n_bonds > 0 ? b->n_bonds : 1));
  int32_t missing = -1;
#pragma omp parallel for schedule(static) reduction(max : missing)
  for (int32_t i = 0; i < p->n_owned; ++i)
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      reverse[k] = j < p->n_owned ? peri_bonds_find(b, j, i) : -1;
      if (reverse[k] < 0) missing = i > missing ? i : missing;
    }
  if (missing >= 0) {
    free(reverse);
    peri_error("plasticity.yield_rule deviatoric: node %d at (%g, %g, %g) has a neighbour that is not a node of the "
               "body (a periodic image): the rule reads both ends' state of each bond",
               missing, p->x[3 * missing], p->x[3 * missing + 1], p->x[3 * missing + 2]);
    return PERI_ERR_INPUT;
  }
  s->state.plastic_reverse = reverse;
  s->state.plastic_reverse_term = peri_calloc((size_t)(b->n_bonds > 0 ? b->n_bonds : 1), sizeof(double));
  return PERI_OK;
}

/* The sublayers of node i's material, or NULL for an elastic one. */
static const peri_sublayers *node_layers(const peri_sim *s, int32_t i) {
  return s->mat.materials[s->disc.p.material[i]].sublayers;
}

/* Node i's deviatoric stretches s^d = (r - |xi|)/|xi| - eth_i - theta_i/3 and weights
 * omega beta V_j |xi|^2 of its bonds into sd[] and wt[] (0 for a broken bond), in family order. */
static void deviatoric_stretches(const peri_sim *s, const peri_bond_view *w, int32_t i, double *restrict sd,
                                 double *restrict wt) {
  const peri_bonds *b = &s->disc.bonds;
  const peri_influence influence = b->family.influence;
  const double shift = (w->eth ? w->eth[i] : 0.0) + s->disc.p.theta[i] / 3.0;
  const int64_t k0 = b->offset[i], n = b->offset[i + 1] - k0;
  const int32_t *restrict nbr = b->neighbor + k0;
  const uint8_t *restrict broken = b->broken + k0;
  const double xi0 = w->x0[i], xi1 = w->x1[i], xi2 = w->x2[i], ui0 = w->u0[i], ui1 = w->u1[i], ui2 = w->u2[i];
#pragma omp simd
  for (int64_t a = 0; a < n; ++a) {
    const int32_t j = nbr[a];
    const double x0 = w->x0[j] - xi0, x1 = w->x1[j] - xi1, x2 = w->x2[j] - xi2;
    const double d0 = x0 + (w->u0[j] - ui0), d1 = x1 + (w->u1[j] - ui1), d2 = x2 + (w->u2[j] - ui2);
    const double r0 = sqrt(x0 * x0 + x1 * x1 + x2 * x2), r = sqrt(d0 * d0 + d1 * d1 + d2 * d2);
    const double on = broken[a] ? 0.0 : 1.0;
    sd[a] = on * ((r - r0) / r0 - shift);
    wt[a] = on * peri_eval_omega(&w->fam, influence, r0) * peri_eval_beta(&w->fam, r0) * w->V[j] * r0 * r0;
  }
}

/* A radial return is taken only beyond the bound by this relative margin: the state it leaves
 * sits on the bound to round-off, and a second evaluation at the same displacement (the
 * breaking order, the energy) must change nothing. */
#define RETURN_MARGIN 1e-10
/* The screen of pass 1's sum (whose lengths come from other arithmetic) keeps this margin. */
#define SCREEN_MARGIN 1e-6

/* sum_l W_l s^dp_l of the bond whose state starts at sp, W those of the node's material. */
static inline double mean_plastic(const peri_sublayers *sl, const double *sp) {
  double plastic = 0.0;
  if (sl)
    for (int l = 0; l < sl->n; ++l) plastic += sl->weight[l] * sp[l];
  return plastic;
}

/* Node i's plastic terms alpha_i sum_l W_l s^dp_l,ij into the reverse bonds' entries. */
static void write_reverse_terms(peri_sim *s, int32_t i) {
  const peri_bonds *b = &s->disc.bonds;
  const peri_sublayers *sl = node_layers(s, i);
  const int L = s->state.plastic_layers;
  const double alpha = s->disc.p.coef[(size_t)s->disc.p.n + (size_t)i];
  const double *sp = s->state.plastic_stretch;
  for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k)
    if (s->state.plastic_reverse[k] >= 0) /* (-1: a ghost's, sent by the bond halo) */
      s->state.plastic_reverse_term[s->state.plastic_reverse[k]] = alpha * mean_plastic(sl, sp + k * L);
}

/* The bond halo's values: node i's term alpha_i sum_l W_l s^dp_l,ij of each listed bond i -> j. */
static void pack_plastic_terms(const void *context, const int64_t *bonds, int64_t n, double *out) {
  const peri_sim *s = context;
  const peri_bonds *b = &s->disc.bonds;
  const int L = s->state.plastic_layers;
  for (int64_t a = 0; a < n; ++a) {
    const int64_t k = bonds[a];
    int32_t lo = 0, hi = b->n_nodes - 1; /* the node whose family holds bond k */
    while (lo < hi) {
      const int32_t mid = lo + (hi - lo + 1) / 2;
      if (b->offset[mid] <= k) lo = mid;
      else hi = mid - 1;
    }
    out[a] = s->disc.p.coef[(size_t)s->disc.p.n + (size_t)lo] * mean_plastic(node_layers(s, lo), s->state.plastic_stretch + k * L);
  }
}

/* The return mapping of node i's sublayers (from the committed state in quasi-static load
 * steps, else in place). Returns whether a plastic stretch of the node (or a committed one)
 * is nonzero. */
static bool node_return(peri_sim *s, const peri_bond_view *w, int32_t i, double elastic, double *sd, double *wt) {
  const peri_sublayers *sl = node_layers(s, i);
  if (!sl) return false;
  const peri_bonds *b = &s->disc.bonds;
  const peri_material *mat = &s->mat.materials[s->disc.p.material[i]];
  const int L = s->state.plastic_layers, n = sl->n;
  const int64_t k0 = b->offset[i], nb = b->offset[i + 1] - k0;
  double *out = s->state.plastic_stretch + k0 * L;
  const bool committed = s->state.plastic_committed != NULL;
  const double *base = committed ? s->state.plastic_committed + k0 * L : out;
  /* the bound of sublayer k is (3 mu / alpha_m) m_i e_yk^2 */
  const double scale = 3.0 * mat->mu / mat->alpha_m * s->disc.p.wvol[i];
  /* every plastic stretch 0 and the elastic deviatoric energy of pass 1 below the first
   * yield (with a margin for that sum's rounding; nearer, the exact sums below decide) */
  if (!s->state.plastic_nodes[i] && elastic <= scale * sl->yield[0] * sl->yield[0] * (1.0 - SCREEN_MARGIN)) return false;
  deviatoric_stretches(s, w, i, sd, wt);
  double S[PERI_MAX_SUBLAYERS] = {0}, factor[PERI_MAX_SUBLAYERS];
  for (int64_t a = 0; a < nb; ++a)
    for (int k = 0; k < n; ++k) {
      const double e = sd[a] - base[a * L + k];
      S[k] = fma(wt[a], e * e, S[k]);
    }
  bool flow = committed;
  for (int k = 0; k < n; ++k) {
    const double bound = scale * sl->yield[k] * sl->yield[k];
    factor[k] = S[k] > bound * (1.0 + RETURN_MARGIN) ? sqrt(bound / S[k]) : 1.0;
    flow |= factor[k] < 1.0;
  }
  bool yielded = false;
  if (flow) {
    for (int64_t a = 0; a < nb; ++a) {
      if (b->broken[k0 + a]) { /* a broken bond keeps its state */
        for (int k = 0; k < n; ++k) out[a * L + k] = base[a * L + k];
        continue;
      }
      for (int k = 0; k < n; ++k)
        out[a * L + k] = factor[k] < 1.0 ? sd[a] - factor[k] * (sd[a] - base[a * L + k]) : base[a * L + k];
    }
  }
  for (int64_t a = 0; a < nb * L && !yielded; ++a) yielded = out[a] != 0.0 || (committed && base[a] != 0.0);
  return yielded;
}

static int64_t longest_family(const peri_bonds *b, int32_t n) {
  int64_t longest = 1;
  for (int32_t i = 0; i < n; ++i)
    if (b->offset[i + 1] - b->offset[i] > longest) longest = b->offset[i + 1] - b->offset[i];
  return longest;
}

void peri_deviatoric_return(peri_sim *s, const double *elastic) {
  if (!s->state.plastic_nodes) peri_plastic_flag_nodes(s);
  const peri_particles *p = &s->disc.p;
  const peri_bond_view w = peri_bond_view_of(s, s->disc.node_blocks->soa);
  const int64_t longest = longest_family(&s->disc.bonds, p->n_owned);
  uint8_t *yielded = s->state.plastic_nodes;
#pragma omp parallel
  {
    double *sd = peri_malloc(sizeof(double) * 2 * (size_t)longest), *wt = sd + longest;
#pragma omp for schedule(static)
    for (int32_t i = 0; i < p->n_owned; ++i) {
      const bool before = yielded[i];
      yielded[i] = node_return(s, &w, i, elastic[i], sd, wt);
      /* a node with a plastic state, or that had one (quasi-static iterations), refreshes its
       * terms on the other ends; the others' stay 0 */
      if (before || yielded[i]) write_reverse_terms(s, i);
    }
    free(sd);
  }
  if (s->par.dd) peri_bond_halo_exchange(s->par.dd->bond_halo, pack_plastic_terms, s, s->state.plastic_reverse_term);
}

double peri_deviatoric_pair_plastic(const peri_sim *s, int32_t i, int64_t k) {
  const peri_particles *p = &s->disc.p;
  return p->coef[(size_t)p->n + (size_t)i] * mean_plastic(node_layers(s, i), s->state.plastic_stretch + k * s->state.plastic_layers) +
         s->state.plastic_reverse_term[k];
}

void peri_deviatoric_force(peri_sim *s) {
  peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const peri_bond_view w = peri_bond_view_of(s, s->disc.node_blocks->soa);
  const uint8_t *yielded = s->state.plastic_nodes;
  const peri_influence influence = b->family.influence;
  const int L = s->state.plastic_layers;
  const double *reverse_term = s->state.plastic_reverse_term;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const int64_t k0 = b->offset[i], k1 = b->offset[i + 1];
    /* no plastic stretch at i and no plastic term from the other ends (whose yielded flags a
     * ghost does not have): the plastic part is 0, the elastic force */
    bool near = yielded[i];
    for (int64_t k = k0; k < k1 && !near; ++k) near = reverse_term[k] != 0.0;
    if (!near) continue;
    const peri_sublayers *sl = node_layers(s, i);
    const double alpha = p->coef[(size_t)p->n + (size_t)i];
    const double *sp = s->state.plastic_stretch;
    double f0 = 0.0, f1 = 0.0, f2 = 0.0;
    for (int64_t k = k0; k < k1; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      const double x0 = w.x0[j] - w.x0[i], x1 = w.x1[j] - w.x1[i], x2 = w.x2[j] - w.x2[i];
      const double d0 = x0 + (w.u0[j] - w.u0[i]), d1 = x1 + (w.u1[j] - w.u1[i]), d2 = x2 + (w.u2[j] - w.u2[i]);
      const double r0 = sqrt(x0 * x0 + x1 * x1 + x2 * x2), r = sqrt(d0 * d0 + d1 * d1 + d2 * d2);
      /* t_ij + t_ji loses omega |xi| (alpha_i sum W s^dp_ij + alpha_j sum W s^dp_ji) */
      const double plastic = alpha * mean_plastic(sl, sp + k * L) + reverse_term[k];
      const double g = -peri_eval_omega(&w.fam, influence, r0) * r0 * plastic * peri_eval_beta(&w.fam, r0) * w.V[j] / r;
      if (r > 0.0) f0 = fma(g, d0, f0), f1 = fma(g, d1, f1), f2 = fma(g, d2, f2);
    }
    p->f[3 * (size_t)i] += f0, p->f[3 * (size_t)i + 1] += f1, p->f[3 * (size_t)i + 2] += f2;
  }
}

/* Bond i-j's deformed length, and its reference length in *r0 (xi + (u_j - u_i), as the energy's
 * two passes over the family both need). */
static inline double bond_lengths(const peri_particles *p, int32_t i, int32_t j, double *r0) {
  double xi[3], dy[3];
  *r0 = peri_bond_xi(p->x, i, j, xi);
  for (int d = 0; d < 3; ++d) dy[d] = xi[d] + p->u[3 * j + d] - p->u[3 * i + d];
  return sqrt(dy[0] * dy[0] + dy[1] * dy[1] + dy[2] * dy[2]);
}

void peri_deviatoric_energy(peri_sim *s, double *W) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const double *eth = s->state.thermal_strain;
  const int L = s->state.plastic_layers;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const peri_material *mat = &s->mat.materials[p->material[i]];
    const peri_sublayers *sl = mat->sublayers;
    const double eth_i = eth ? eth[i] : 0.0, m = p->wvol[i];
    double wq = 0.0; /* sum omega |xi| beta V (e - eth_i |xi|): the dilatation of the total extension */
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double r0;
      const double r = bond_lengths(p, i, j, &r0);
      wq += peri_bonds_omega(b, r0) * r0 * peri_bonds_beta(b, r0) * p->volume[j] * (r - r0 - eth_i * r0);
    }
    const double theta = mat->n_theta * wq / m;
    /* each sublayer's deviatoric energy at its elastic deviatoric stretches, weighted */
    double deviatoric = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double r0;
      const double r = bond_lengths(p, i, j, &r0);
      const double sd = (r - r0) / r0 - eth_i - theta / 3.0;
      double e2 = sd * sd;
      if (sl) {
        const double *sp = s->state.plastic_stretch + k * L;
        e2 = 0.0;
        for (int l = 0; l < sl->n; ++l) e2 += sl->weight[l] * (sd - sp[l]) * (sd - sp[l]);
      }
      deviatoric += peri_bonds_omega(b, r0) * peri_bonds_beta(b, r0) * p->volume[j] * r0 * r0 * e2;
    }
    W[i] = 0.5 * mat->K_theta * theta * theta + 0.5 * (mat->alpha_m / m) * deviatoric;
  }
}
