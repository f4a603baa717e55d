/* Madenci-Oterkus ordinary state-based model `osb_mo` (Ebrahimi 2020 §2.2 eqs. 2.21-2.26,
 * Table 2.1; docs/models.md 3.6), with its own influence function omega = delta/|xi| (eq. 2.22):
 *   theta_i = d_i delta sum_j (s_ij L_ij - eth_i) beta V_j + n eth_i                      (eq. 2.23)
 *   t_ij    = 2 delta [d_i (L_ij/|xi|) (a1 theta_i - a2 dT_i/2) + b_i (s_ij - eth_i)]       (eq. 2.25)
 *   W_i     = a1 theta_i^2 - a2 theta_i dT_i + a3 dT_i^2 + b_i sum_j omega (e - eth_i |xi|)^2 beta V_j
 *   f_i     = sum_j (t_ij + t_ji) M_ij beta V_j                                           (eq. 2.30)
 * with L_ij the cosine between y_j - y_i and x_j - x_i (eq. 2.26) and eth = alpha_T dT. The
 * thermal constants of Table 2.1 (the 2D ones erratum-corrected, MODELS.md 3.5) are a2 dT =
 * 2 n a1 eth and a3 dT^2 = n^2 a1 eth^2, so with the mechanical dilatation theta^m = theta - n eth
 *   a1 theta - a2 dT/2 = a1 theta^m,   W_i = a1 (theta^m_i)^2 + b_i sum_j omega (e - eth_i |xi|)^2 beta V_j.
 * Per node, d_i = n/(delta V^H_i) and b_i = (alpha m)/(2 m_i), with the horizon volume V^H_i =
 * sum_j beta V_j (p->pstate) and the weighted volume m_i = delta sum_j |xi| beta V_j (p->wvol)
 * over the reference family (discretization.weighted_volume: discrete), or the full-horizon
 * integrals (analytic: Table 2.1's d and b). The discrete sums make theta exactly n times the
 * family-average stretch and W exact for a dilatation on any symmetric family. Each end uses
 * its own material (half-bond rule). The force pass reads three numbers per neighbour:
 *   A_i = 2 delta d_i a1 theta^m_i,  B_i = 2 delta b_i,  C_i = B_i eth_i,
 *   t_ij + t_ji = (A_i + A_j) L_ij/|xi| + (B_i + B_j) s_ij - (C_i + C_j).
 * Sublayer plasticity (docs/plasticity.md) enters through the elastic stretch s^e = s - sum_k
 * W_k s^p_k in both the dilatation sum and the b-term (MODELS.md 16.2). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/constants.h"
#include "peri/error.h"
#include "peri/model.h"
#include "peri/plasticity.h"
#include "bond_kernel.h"
#include "node_blocks.h"
#include "plastic_bonds.h"

/* The full-horizon volume and weighted volume of omega = delta/|xi| (MODELS.md 3.6):
 * 4 pi delta^3/3 and pi delta^5 (3D), pi h delta^2 and 2 pi h delta^4/3 (2D), 2 A delta and
 * A delta^3 (1D). */
static void mo_analytic_volumes(const peri_geometry *g, double *VH, double *m) {
  const double d = g->horizon;
  if (g->dim == 3) *VH = 4.0 * M_PI * d * d * d / 3.0, *m = M_PI * pow(d, 5);
  else if (g->dim == 2) *VH = M_PI * g->thickness * d * d, *m = 2.0 * M_PI * g->thickness * pow(d, 4) / 3.0;
  else *VH = 2.0 * g->cross_section * d, *m = g->cross_section * d * d * d;
}

static int mo_init(peri_sim *s) {
  if (s->disc.family.influence != PERI_INFLUENCE_CONSTANT) {
    peri_error("the osb_mo model has its own influence function delta/|xi| (Ebrahimi 2020 eq. 2.22)");
    return PERI_ERR_INPUT;
  }
  if (peri_plastic_init(s) != PERI_OK) return PERI_ERR_INPUT; /* sublayer plasticity (docs/plasticity.md) */
  peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const double delta = s->disc.geom.horizon;
  for (int m = 0; m < s->mat.n_materials; ++m) {
    peri_material *mat = &s->mat.materials[m];
    peri_mo_constants(&s->disc.geom, mat->K, mat->mu, &mat->n_theta, &mat->K_theta, &mat->alpha_m);
    mat->c_stable = peri_stable_micromodulus(
        &s->disc.geom, peri_pwave_modulus(&s->disc.geom, mat->E, mat->nu, mat->K, mat->mu));
  }
  p->theta = peri_calloc(p->n, sizeof(double));
  p->pstate = peri_calloc(p->n, sizeof(double)); /* V^H_i */
  p->wvol = peri_calloc(p->n, sizeof(double));   /* m_i */
  p->coef = peri_calloc(3 * (size_t)p->n, sizeof(double));
  if (s->disc.analytic_weighted_volume) {
    double VH, m;
    mo_analytic_volumes(&s->disc.geom, &VH, &m);
    for (int32_t i = 0; i < p->n; ++i) p->pstate[i] = VH, p->wvol[i] = m;
    return PERI_OK;
  }
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double VH = 0.0, m = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      const double r0 = peri_bond_length(p->x, i, j), bv = peri_bonds_beta(b, r0) * p->volume[j];
      VH += bv, m += r0 * bv;
    }
    p->pstate[i] = VH, p->wvol[i] = delta * m;
  }
  for (int32_t i = 0; i < p->n_owned; ++i)
    if (!(p->pstate[i] > 0.0)) {
      peri_error("node %d at (%g, %g, %g) has no bonds: the osb_mo model needs a family "
                 "(increase the horizon or check the geometry)",
                 i, p->x[3 * i], p->x[3 * i + 1], p->x[3 * i + 2]);
      return PERI_ERR_INPUT;
    }
  return PERI_OK;
}

/* A node's sums: the dilatation sum or the force, whether a bond passes the breaking screen. */
typedef struct mo_sums {
  double sum[3];
  bool candidate;
} mo_sums;

/* Node i over its intact bonds in family order: pass 1 (`force` false) the sum
 * sum_j (s L - eth_i) beta V_j and the breaking screen; pass 2 the force density. The bond
 * values come from a vector loop, their sums in order (so a node's result depends on neither
 * threads nor ranks). */
static inline __attribute__((always_inline)) mo_sums mo_node(const peri_bond_view *w, int32_t i, bool force,
                                                             bool thermal) {
  const size_t n = (size_t)w->n;
  const double *restrict X0 = w->x0, *restrict X1 = w->x1, *restrict X2 = w->x2, *restrict U0 = w->u0,
                         *restrict U1 = w->u1, *restrict U2 = w->u2, *restrict V = w->V, *restrict A = w->coef,
                         *restrict B = w->coef + n, *restrict C = w->coef + 2 * n, *restrict eth = w->eth,
                         *restrict bound = w->s0_bound;
  const peri_family_eval fam = w->fam;
  const double xi0 = X0[i], xi1 = X1[i], xi2 = X2[i], ui0 = U0[i], ui1 = U1[i], ui2 = U2[i];
  const double eth_i = thermal ? eth[i] : 0.0, bound_i = force ? 0.0 : bound[i];
  const double Ai = force ? A[i] : 0.0, Bi = force ? B[i] : 0.0, Ci = force ? C[i] : 0.0;
  const int64_t k0 = w->offset[i], k1 = w->offset[i + 1];
  const bool damaged = memchr(w->broken + k0, 1, (size_t)(k1 - k0)) != NULL;
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, excess = -INFINITY;
  int32_t intact[PERI_INTACT_CHUNK];
  double g[PERI_INTACT_CHUNK], v0[PERI_INTACT_CHUNK], v1[PERI_INTACT_CHUNK], v2[PERI_INTACT_CHUNK];
  for (int64_t k = k0; k < k1;) {
    int count;
    const int32_t *restrict nbr = peri_next_chunk(w, damaged, &k, k1, intact, &count);
#pragma omp simd reduction(max : excess)
    for (int a = 0; a < count; ++a) {
      const int32_t j = nbr[a];
      const double x0 = X0[j] - xi0, x1 = X1[j] - xi1, x2 = X2[j] - xi2;
      const double y0 = x0 + (U0[j] - ui0), y1 = x1 + (U1[j] - ui1), y2 = x2 + (U2[j] - ui2);
      const double r0 = peri_length3(x0, x1, x2), r = peri_length3(y0, y1, y2);
      const double inv_r0 = 1.0 / r0, inv_r = r > 0.0 ? 1.0 / r : 0.0;
      /* L/|xi| = (x.y)/(|y| |xi|^2) (0 for a bond of zero length, which carries no force) */
      const double cos_r0 = fma(x2, y2, fma(x1, y1, x0 * y0)) * inv_r * inv_r0 * inv_r0;
      const double bv = peri_eval_beta(&fam, r0) * V[j];
      if (force) {
        const double pair = (Ai + A[j]) * cos_r0 + (Bi + B[j]) * (r - r0) * inv_r0 - (Ci + C[j]);
        g[a] = pair * bv * inv_r;
        v0[a] = y0, v1[a] = y1, v2[a] = y2;
      } else {
        g[a] = ((r - r0) * cos_r0 - eth_i) * bv; /* (s L - eth_i) beta V, s L = (r - |xi|) L/|xi| */
        /* the mechanical stretch against the screening bound (symmetric in i and j) */
        const double st = (r - r0) * inv_r0 - (thermal ? 0.5 * (eth_i + eth[j]) : 0.0);
        excess = peri_max(excess, st - (peri_min(bound_i, bound[j]) - PERI_S0_SCREEN_MARGIN));
      }
    }
    if (force) {
      for (int a = 0; a < count; ++a) {
        s0 = fma(g[a], v0[a], s0);
        s1 = fma(g[a], v1[a], s1);
        s2 = fma(g[a], v2[a], s2);
      }
    } else {
      for (int a = 0; a < count; ++a) s0 += g[a];
    }
  }
  const mo_sums r = {{s0, s1, s2}, excess > 0.0};
  return r;
}

/* The specialisations the passes call (constants fixed inside functions of their own, so
 * that they reach the vector loop through the outlined OpenMP regions). */
static mo_sums mo_dilatation_node(const peri_bond_view *w, int32_t i) { return mo_node(w, i, false, false); }
static mo_sums mo_dilatation_thermal_node(const peri_bond_view *w, int32_t i) { return mo_node(w, i, false, true); }
static mo_sums mo_force_node(const peri_bond_view *w, int32_t i) { return mo_node(w, i, true, false); }

/* Node i's dilatation and its three coefficients of the force pass from the pass-1 sum. */
static inline void mo_node_coefficients(peri_sim *s, int32_t i, double sum) {
  peri_particles *p = &s->disc.p;
  const size_t n = (size_t)p->n;
  const peri_material *mat = &s->mat.materials[p->material[i]];
  const double eth_i = s->state.thermal_strain ? s->state.thermal_strain[i] : 0.0;
  const double theta_m = mat->n_theta * sum / p->pstate[i]; /* d_i delta sum, d_i = n/(delta V^H_i) */
  p->theta[i] = theta_m + mat->n_theta * eth_i;
  /* A_i = 2 delta d_i a1 theta^m = n K_theta theta^m / V^H (K_theta = 2 a1); B_i = 2 delta b_i */
  p->coef[i] = mat->n_theta * mat->K_theta * theta_m / p->pstate[i];
  p->coef[n + (size_t)i] = s->disc.geom.horizon * mat->alpha_m / p->wvol[i];
  p->coef[2 * n + (size_t)i] = p->coef[n + (size_t)i] * eth_i;
}

static void mo_exchange_coefficients(peri_sim *s) {
  const size_t n = (size_t)s->disc.p.n;
  for (int part = 0; part < 3; ++part) peri_sim_exchange(s, s->disc.p.coef + part * n, 1);
}

/* The elastic force pass: pass 1 breaks the bonds beyond their critical stretch (the exact
 * test of node_blocks.c, on the nodes the screen flags) and sets the coefficients; pass 2
 * sums the forces. */
static long mo_force_pass(peri_sim *s, bool update_s0) {
  (void)update_s0; /* (no LAMMPS-form critical stretch: refused at set-up) */
  peri_update_s0_bound(s);
  peri_node_blocks *items = peri_node_blocks_refresh(s);
  peri_particles *p = &s->disc.p;
  const bool breaking = s->solver.breaking;
  mo_sums (*const dilatation)(const peri_bond_view *, int32_t) =
      s->state.thermal_strain ? mo_dilatation_thermal_node : mo_dilatation_node;
  const peri_bond_view w = peri_bond_view_of(s, items->soa);
  long n_broken = 0;
#pragma omp parallel reduction(+ : n_broken)
  PERI_FOR_EACH_ITEM(items, item) {
    for (int32_t i = items->first[item]; i < items->first[item + 1]; ++i) {
      mo_sums r = dilatation(&w, i);
      if (breaking && r.candidate) {
        const long broken_here = peri_node_blocks_break_family(s, items, item, i);
        if (broken_here > 0) r = dilatation(&w, i);
        n_broken += broken_here;
      }
      mo_node_coefficients(s, i, r.sum[0]);
    }
  }
  mo_exchange_coefficients(s);
#pragma omp parallel
  PERI_FOR_EACH_ITEM(items, item) {
    for (int32_t i = items->first[item]; i < items->first[item + 1]; ++i) {
      const mo_sums r = mo_force_node(&w, i);
      for (int d = 0; d < 3; ++d) p->f[3 * (size_t)i + d] = r.sum[d];
    }
  }
  return n_broken;
}

/* Sublayer plasticity: every node through the plastic path of plastic_bonds.c (breaking, the
 * return mapping of each bond, the sums at the elastic stretches). */
static long mo_plastic_force_pass(peri_sim *s, bool update_s0) {
  (void)update_s0;
  peri_particles *p = &s->disc.p;
  peri_update_s0_bound(s);
  peri_plastic_pass pass = peri_plastic_pass_begin(s);
  peri_node_blocks *items = peri_node_blocks_refresh(s);
  const peri_bond_view w = peri_bond_view_of(s, items->soa);
  long n_broken = 0;
#pragma omp parallel reduction(+ : n_broken)
  {
    peri_plastic_chunk *scratch = peri_plastic_chunk_new();
    PERI_FOR_EACH_ITEM(items, item) {
      for (int32_t i = items->first[item]; i < items->first[item + 1]; ++i) {
        double sum;
        const long broken_here = peri_plastic_mo_node_sums(s, &w, &pass, i, scratch, &sum);
        if (broken_here > 0) peri_node_blocks_clear_broken(items, &s->disc.bonds, item, i);
        n_broken += broken_here;
        mo_node_coefficients(s, i, sum);
      }
    }
    free(scratch);
  }
  mo_exchange_coefficients(s);
#pragma omp parallel
  PERI_FOR_EACH_ITEM(items, item) {
    for (int32_t i = items->first[item]; i < items->first[item + 1]; ++i)
      peri_plastic_mo_node_force(s, &w, &pass, i, &p->f[3 * (size_t)i]);
  }
  peri_plastic_pass_end(&pass);
  return n_broken;
}

static long mo_force(peri_sim *s) {
  return peri_force_in_breaking_order(s, s->state.plastic_stretch ? mo_plastic_force_pass : mo_force_pass);
}

/* W_i = a1 (theta^m_i)^2 + b_i delta sum_j (e^e - eth_i |xi|)^2/|xi| beta V_j over the intact
 * bonds as they are (e^e the elastic extension), theta^m_i from node i's own bonds. Not on the
 * time-step path. */
static void mo_energy(peri_sim *s, double *W) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const double *eth = s->state.thermal_strain, delta = s->disc.geom.horizon;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const double eth_i = eth ? eth[i] : 0.0;
    double sum = 0.0, q2 = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double y[3];
      const double r = peri_deformed_bond(p->x, p->u, i, j, y), r0 = peri_bond_length(p->x, i, j);
      double x_dot_y = 0.0;
      for (int c = 0; c < 3; ++c) x_dot_y += (p->x[3 * j + c] - p->x[3 * i + c]) * y[c];
      const double cosine = r > 0.0 ? x_dot_y / (r * r0) : 0.0;
      const double se = (r - r0) / r0 - peri_plastic_bond_stretch(s, i, k); /* the elastic stretch */
      const double bv = peri_bonds_beta(b, r0) * p->volume[j];
      sum += (se * cosine - eth_i) * bv;
      q2 += (se - eth_i) * (se - eth_i) * r0 * bv; /* omega e^2 with omega = delta/|xi|, over delta */
    }
    const peri_material *mat = &s->mat.materials[p->material[i]];
    const double theta_m = mat->n_theta * sum / p->pstate[i];
    W[i] = 0.5 * mat->K_theta * theta_m * theta_m + 0.5 * (mat->alpha_m / p->wvol[i]) * delta * q2;
  }
}

/* (t_ij + t_ji) of bond k of node i at the state of the last force pass (its coefficients,
 * exchanged for ghosts by the force pass). */
static double mo_pair_force(const peri_sim *s, int32_t i, int64_t k, double r) {
  const peri_particles *p = &s->disc.p;
  const int32_t j = s->disc.bonds.neighbor[k];
  const size_t n = (size_t)p->n;
  double y[3], x_dot_y = 0.0;
  peri_deformed_bond(p->x, p->u, i, j, y);
  for (int c = 0; c < 3; ++c) x_dot_y += (p->x[3 * j + c] - p->x[3 * i + c]) * y[c];
  const double r0 = peri_bond_length(p->x, i, j);
  const double cos_r0 = r > 0.0 ? x_dot_y / (r * r0 * r0) : 0.0;
  const double se = (r - r0) / r0 - peri_plastic_bond_stretch(s, i, k);
  return (p->coef[i] + p->coef[j]) * cos_r0 + (p->coef[n + (size_t)i] + p->coef[n + (size_t)j]) * se -
         (p->coef[2 * n + (size_t)i] + p->coef[2 * n + (size_t)j]);
}

const peri_model_ops peri_model_osb_mo = {
    .name = "osb_mo",
    .description = "Madenci-Oterkus ordinary state-based model, omega = delta/|xi| (any Poisson ratio)",
    .fixed_poisson = 0,
    .init = mo_init,
    .force = mo_force,
    .energy = mo_energy,
    .pair_force = mo_pair_force,
    .own_force = NULL,
    .tangent = NULL, /* (the implicit solver refuses it at set-up) */
    .tangent_reach = 2,
};
