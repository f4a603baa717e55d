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
#include "peri/constants.h"
#include "peri/error.h"
#include "peri/plasticity.h"
#include <stdlib.h>
#include "bond_chunk.h"
#include "bond_kernel.h"
#include "node_blocks.h"
#include "peri/tensor_plasticity.h"
#include "plastic_bonds.h"

/* The sublayers of bond i-j: those of the common material; between two materials the ones
 * of the material that yields first (a symmetric choice); NULL when neither is plastic. */
static const peri_sublayers *bond_layers(const peri_sim *s, int32_t i, int32_t j) {
  const peri_particles *p = &s->disc.p;
  const peri_sublayers *a = s->mat.materials[p->material[i]].sublayers, *b = s->mat.materials[p->material[j]].sublayers;
  if (s->state.plastic_reverse) return a; /* the deviatoric rule: node i's state of the bond */
  if (a == b || !b) return a;
  if (!a) return b;
  return a->yield[0] <= b->yield[0] ? a : b;
}

int peri_plastic_init(peri_sim *s) {
  int layers = 0;
  bool deviatoric = false;
  for (int m = 0; m < s->mat.n_materials; ++m) {
    const peri_sublayers *sl = s->mat.materials[m].sublayers;
    if (sl && sl->n > layers) layers = sl->n;
    deviatoric = deviatoric || (sl && sl->deviatoric);
    if (sl && sl->tensor) return PERI_OK; /* (the tensor rule keeps no state per bond) */
  }
  if (layers == 0) return PERI_OK;
  const size_t n = (size_t)s->disc.bonds.n_bonds * (size_t)layers;
  /* (the deviatoric rule moves a state at rest into its slots at its first return: left to
   * calloc, the rows' pages are not touched before they are freed, and never take memory) */
  s->state.plastic_stretch = deviatoric ? peri_calloc(n > 0 ? n : 1, sizeof(double))
                                          : peri_calloc_aligned(n > 0 ? n : 1, sizeof(double));
  s->state.plastic_layers = layers;
  return PERI_OK;
}

const double *peri_plastic_row(const peri_sim *s, const double *state, int64_t k, double *row) {
  return peri_plastic_row_inline(s, state, k, row);
}

void peri_plastic_first_layer_flags(const peri_sim *s, int32_t i, uint8_t *yielded) {
  const int64_t k0 = s->disc.bonds.offset[i], n = s->disc.bonds.offset[i + 1] - k0;
  const double *restrict state = s->state.plastic_stretch;
  const int L = s->state.plastic_layers;
  const struct peri_plastic_slots *t = &s->state.plastic_slots;
  if (!t->state_in_slots) {
    for (int64_t a = 0; a < n; ++a) yielded[a] = state[(k0 + a) * L] != 0.0;
    return;
  }
  const int64_t *restrict slot = t->bond_slot + k0;
  for (int64_t a = 0; a < n; ++a) yielded[a] = state[peri_plastic_layer_index(slot[a], 0, L, t->block_slots)] != 0.0;
}

/* The doubles of the plastic state (its slots', when it is kept in them). */
static size_t plastic_state_doubles(const peri_sim *s) {
  const int64_t slots = s->state.plastic_slots.n_slots;
  return (size_t)s->state.plastic_layers *
         (size_t)(s->state.plastic_slots.state_in_slots ? (slots + 7) & ~(int64_t)7 : s->disc.bonds.n_bonds);
}

double peri_plastic_bond_stretch(const peri_sim *s, int32_t i, int64_t k) {
  if (!s->state.plastic_stretch) return 0.0;
  const peri_sublayers *sl = bond_layers(s, i, s->disc.bonds.neighbor[k]);
  if (!sl) return 0.0;
  double row[PERI_MAX_SUBLAYERS];
  const double *sp = peri_plastic_row(s, s->state.plastic_stretch, k, row);
  double plastic = 0.0;
  for (int l = 0; l < sl->n; ++l) plastic += sl->weight[l] * sp[l];
  return plastic;
}

void peri_plastic_commit(peri_sim *s) {
  peri_tensor_commit(s);
  if (s->state.plastic_committed)
    memcpy(s->state.plastic_committed, s->state.plastic_stretch, sizeof(double) * plastic_state_doubles(s));
}

/* The micromodulus of the bond work of material m: PMB's own, or for LPS that of the PMB
 * material of the same E (its bond work is then the bond-based one, as in the calibration of
 * peri_critical_bond_work). */
static double bond_micromodulus(const peri_sim *s, int m) {
  const peri_material *mat = &s->mat.materials[m];
  return mat->micromodulus > 0.0 ? mat->micromodulus : peri_pmb_micromodulus(&s->disc.geom, mat->E, mat->K);
}

/* The yielded flags (s->state.plastic_nodes) from the plastic state, after the state was set
 * from outside the loops (start, a checkpoint, a decomposition), and the longest bond. */
void peri_plastic_flag_nodes(peri_sim *s) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const int L = s->state.plastic_layers;
  uint8_t *flags = peri_calloc((size_t)(p->n > 0 ? p->n : 1), 1);
  double reach = 0.0;
#pragma omp parallel for schedule(static) reduction(max : reach)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    bool yielded = false;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      double row[PERI_MAX_SUBLAYERS], committed_row[PERI_MAX_SUBLAYERS];
      const double *sp = peri_plastic_row(s, s->state.plastic_stretch, k, row),
                   *cp = s->state.plastic_committed ? peri_plastic_row(s, s->state.plastic_committed, k, committed_row)
                                                    : NULL;
      for (int l = 0; l < L; ++l) yielded |= sp[l] != 0.0 || (cp && cp[l] != 0.0);
    }
    flags[i] = yielded;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k)
      reach = fmax(reach, peri_bond_length(p->x, i, b->neighbor[k]));
  }
  s->state.plastic_nodes = flags;
  s->state.plastic_reach = reach;
}

peri_plastic_pass peri_plastic_pass_begin(peri_sim *s) {
  if (!s->state.plastic_nodes) peri_plastic_flag_nodes(s);
  const int nm = s->mat.n_materials, L = s->state.plastic_layers;
  peri_plastic_pass t = {L,
                         nm,
                         peri_malloc(sizeof(double) * (size_t)(nm * nm * L)),
                         peri_malloc(sizeof(double) * (size_t)(nm * nm * L)),
                         peri_malloc(sizeof(double) * (size_t)(nm * nm)),
                         false,
                         peri_malloc(sizeof(double) * (size_t)(nm * nm)),
                         peri_malloc(sizeof(double) * (size_t)(nm * nm)),
                         false,
                         peri_calloc((size_t)(nm * nm), sizeof(double)),
                         peri_calloc((size_t)(nm * nm), sizeof(double)),
                         false,
                         NULL};
  const peri_particles *p = &s->disc.p;
  for (int a = 0; a < nm; ++a)
    for (int b = 0; b < nm; ++b) {
      const peri_sublayers *A = s->mat.materials[a].sublayers, *B = s->mat.materials[b].sublayers;
      const peri_sublayers *sl = A == B || !B ? A : !A ? B : A->yield[0] <= B->yield[0] ? A : B;
      /* the smaller of the two ends' (a symmetric choice) */
      const double ca = A ? A->critical_plastic_stretch : INFINITY, cb = B ? B->critical_plastic_stretch : INFINITY;
      t.critical[a * nm + b] = fmin(ca, cb);
      t.ductile |= isfinite(t.critical[a * nm + b]);
      const double wa = A ? A->critical_bond_work : INFINITY, wb = B ? B->critical_bond_work : INFINITY;
      t.work[a * nm + b] = fmin(wa, wb);
      t.energetic |= isfinite(t.work[a * nm + b]);
      t.c[a * nm + b] = 0.5 * (bond_micromodulus(s, a) + bond_micromodulus(s, b));
      if (sl && sl->rate_d > 0.0) {
        t.rate_d[a * nm + b] = sl->rate_d, t.rate_inv_p[a * nm + b] = 1.0 / sl->rate_p;
        t.rate = true;
      }
      for (int l = 0; l < L; ++l) {
        const bool real = sl && l < sl->n;
        t.W[(a * nm + b) * L + l] = real ? sl->weight[l] : 0.0;
        t.Y[(a * nm + b) * L + l] = real ? sl->yield[l] : INFINITY;
      }
    }
  /* the screen of each material: the smallest first yield stretch of its pairs, and for a
   * critical bond work the smallest stretch at which an elastic bond reaches it, s^2 =
   * 2 w_c / (c omega |xi|), with omega |xi| at most the longest bond (1 for omega = 1/|xi|) */
  const double omega_xi = s->disc.family.influence == PERI_INFLUENCE_INVERSE ? 1.0 : s->state.plastic_reach;
  double *yield_screen = peri_malloc(sizeof(double) * (size_t)nm);
  for (int a = 0; a < nm; ++a) {
    double screen = INFINITY;
    for (int b = 0; b < nm; ++b) {
      screen = fmin(screen, t.Y[(a * nm + b) * L]);
      if (isfinite(t.work[a * nm + b])) screen = fmin(screen, sqrt(2.0 * t.work[a * nm + b] / (t.c[a * nm + b] * omega_xi)));
    }
    yield_screen[a] = screen;
  }
  t.screen = peri_malloc(sizeof(double) * (size_t)(p->n > 0 ? p->n : 1));
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n; ++i) t.screen[i] = fmin(p->s0_bound[i], yield_screen[p->material[i]]);
  free(yield_screen);
  /* the stretch rates read the ghosts' velocities (the explicit solver updates the owned
   * nodes' only) */
  if (t.rate) peri_sim_exchange(s, s->disc.p.v, 3);
  return t;
}

void peri_plastic_pass_end(peri_plastic_pass *t) {
  free(t->W), free(t->Y), free(t->critical), free(t->work), free(t->c), free(t->screen);
  free(t->rate_d), free(t->rate_inv_p);
}

/* Node i's bonds a chunk at a time: the deformed vectors, stretches and the margin over the
 * breaking screen (a vector loop), the exact breaking test of the candidates (scalar, rare),
 * then the return mapping of every intact bond, branch-free (clamping the committed plastic
 * stretch of each layer to [s - s_y, s + s_y]), and `use` with each bond's elastic stretch.
 * Fills the chunk arrays of the caller. */
#define PLASTIC_CHUNK 256
struct peri_plastic_chunk {
  int n;
  int64_t k0;
  int32_t j[PLASTIC_CHUNK];
  double y0[PLASTIC_CHUNK], y1[PLASTIC_CHUNK], y2[PLASTIC_CHUNK], r[PLASTIC_CHUNK], r0[PLASTIC_CHUNK],
      s[PLASTIC_CHUNK], se[PLASTIC_CHUNK], intact[PLASTIC_CHUNK];
  double scale[PLASTIC_CHUNK]; /* of the yield stretches (Cowper-Symonds; else 1) */
};
typedef struct peri_plastic_chunk plastic_chunk;

plastic_chunk *peri_plastic_chunk_new(void) { return peri_malloc(sizeof(plastic_chunk)); }

/* The return mapping of the chunk's bonds (L layers each, from the committed state or in
 * place) and their elastic stretches s - sum_l W_l s^p_l into c->se. Returns whether a
 * plastic stretch of the chunk (or a committed one) is nonzero. */
static inline __attribute__((always_inline)) bool plastic_return_chunk(peri_sim *s, const peri_plastic_pass *pl, int32_t i,
                                                                       int64_t k0, int n, plastic_chunk *c,
                                                                       const int L) {
  const int nm = pl->nm;
  const int32_t *restrict material = s->disc.p.material;
  const int row = material[i] * nm;
  double *restrict out = s->state.plastic_stretch + k0 * L;
  const bool committed = s->state.plastic_committed != NULL;
  const double *base = committed ? s->state.plastic_committed + k0 * L : out;
  const double *restrict cs = c->s, *restrict on = c->intact, *restrict ys = c->scale;
  const int32_t *restrict cj = c->j;
  double *restrict se = c->se;
  if (nm == 1) { /* one material: the layers' weights and yield stretches are the node's */
    const double *restrict W = pl->W, *restrict Y = pl->Y;
    double magnitude = 0.0; /* (a sum of magnitudes: 0 only when every stretch is) */
    /* branch-free, so that it is a vector loop: the intact test as take v + (1 - take) b
     * (exact for take 0 or 1), every layer stored (masked stores where it changes cost more) */
#pragma omp simd reduction(+ : magnitude)
    for (int a = 0; a < n; ++a) {
      const double st = cs[a], take = on[a];
      double plastic = 0.0;
      for (int l = 0; l < L; ++l) {
        const double b = base[a * L + l], y = Y[l] * ys[a];
        /* clamp to [s - s_y, s + s_y]: the return mapping of an elastic-perfectly-plastic layer */
        const double v = take * peri_min(peri_max(b, st - y), st + y) + (1.0 - take) * b;
        out[a * L + l] = v;
        magnitude += fabs(v) + (committed ? fabs(b) : 0.0);
        plastic += W[l] * v;
      }
      se[a] = st - plastic;
    }
    return magnitude != 0.0;
  }
  bool yielded = false;
  for (int a = 0; a < n; ++a) {
    const int pair = (row + material[cj[a]]) * L;
    const double *restrict W = pl->W + pair, *restrict Y = pl->Y + pair;
    const double st = cs[a];
    double plastic = 0.0;
    for (int l = 0; l < L; ++l) {
      const double b = base[a * L + l];
      /* clamp to [s - s_y, s + s_y]: the return mapping of an elastic-perfectly-plastic layer */
      const double y = Y[l] * ys[a];
      const double v = on[a] != 0.0 ? peri_min(peri_max(b, st - y), st + y) : b;
      /* stored only when it changes (mapping in place, most bonds are elastic in a step: no
       * write traffic) or when mapping from the committed state */
      if (v != b || committed) out[a * L + l] = v;
      yielded |= v != 0.0 || (committed && b != 0.0);
      plastic += W[l] * v;
    }
    se[a] = st - plastic;
  }
  return yielded;
}

static inline __attribute__((always_inline)) void plastic_chunk_map(peri_sim *s, const peri_bond_view *w,
                                                                    const peri_plastic_pass *pl, int32_t i, int64_t k0,
                                                                    int n, bool breaking, bool thermal,
                                                                    plastic_chunk *c, long *broken, double *smin,
                                                                    bool *any_yielded) {
  const int32_t *restrict nbr = w->neighbor + k0;
  const uint8_t *restrict flag = w->broken + k0;
  const double *restrict X0 = w->x0, *restrict X1 = w->x1, *restrict X2 = w->x2, *restrict U0 = w->u0,
                         *restrict U1 = w->u1, *restrict U2 = w->u2, *restrict eth = w->eth, *restrict bound = w->s0_bound;
  const double xi0 = X0[i], xi1 = X1[i], xi2 = X2[i], ui0 = U0[i], ui1 = U1[i], ui2 = U2[i];
  const double eth_i = thermal ? eth[i] : 0.0, bound_i = bound[i];
  double excess[PLASTIC_CHUNK], low = *smin;
  c->n = n, c->k0 = k0;
  /* the 1-byte flags as doubles first: read in the vector loop they would force 64-lane
   * vectors and a scalar tail (bond_kernel.h) */
  if (memchr(flag, 1, (size_t)n))
    for (int a = 0; a < n; ++a) c->intact[a] = flag[a] ? 0.0 : 1.0;
  else
    for (int a = 0; a < n; ++a) c->intact[a] = 1.0;
  const double *restrict intact = c->intact;
  int32_t *restrict cj = c->j;
  double *restrict cy0 = c->y0, *restrict cy1 = c->y1, *restrict cy2 = c->y2, *restrict cr = c->r,
                   *restrict cr0 = c->r0, *restrict cs = c->s;
#pragma omp simd reduction(min : low)
  for (int a = 0; a < n; ++a) {
    const int32_t j = nbr[a];
    const double x0 = X0[j] - xi0, x1 = X1[j] - xi1, x2 = X2[j] - xi2;
    const double d0 = x0 + (U0[j] - ui0), d1 = x1 + (U1[j] - ui1), d2 = x2 + (U2[j] - ui2);
    const double r0 = sqrt(x0 * x0 + x1 * x1 + x2 * x2), r = sqrt(d0 * d0 + d1 * d1 + d2 * d2);
    const double st = (r - r0) / r0 - (thermal ? 0.5 * (eth_i + eth[j]) : 0.0);
    cj[a] = j, cy0[a] = d0, cy1[a] = d1, cy2[a] = d2, cr[a] = r, cr0[a] = r0, cs[a] = st;
    const double on = intact[a];
    excess[a] = on * (st - peri_min(bound_i, bound[j])) - (1.0 - on);
    low = peri_min(low, on != 0.0 ? st : INFINITY);
  }
  *smin = low;
  if (breaking)
    for (int a = 0; a < n; ++a)
      if (excess[a] > 0.0 && c->s[a] > peri_bond_s0(s, i, c->j[a])) {
        s->disc.bonds.broken[k0 + a] = 1;
        c->intact[a] = 0.0;
        ++*broken;
      }
  /* Cowper-Symonds: the yield stretches of a bond scale by 1 + (|ds/dt| / d)^(1/p), with
   * ds/dt = (y_j - y_i).(v_j - v_i) / (|y_j - y_i| |xi|), the rate of the stretch at the
   * step's velocities (in the explicit solver's force evaluation the mid-step ones: the
   * stretch's change over the step divided by the time step, to first order) */
  if (pl->rate) {
    const double *v = s->disc.p.v;
    const int32_t *material = s->disc.p.material;
    const double *d = pl->rate_d + material[i] * pl->nm, *inv_p = pl->rate_inv_p + material[i] * pl->nm;
    for (int a = 0; a < n; ++a) {
      const int32_t j = c->j[a];
      const double rate = (c->y0[a] * (v[3 * j] - v[3 * i]) + c->y1[a] * (v[3 * j + 1] - v[3 * i + 1]) +
                           c->y2[a] * (v[3 * j + 2] - v[3 * i + 2])) /
                          (c->r[a] * c->r0[a]);
      const double dm = d[material[j]];
      c->scale[a] = dm > 0.0 && c->r[a] > 0.0 ? 1.0 + pow(fabs(rate) / dm, inv_p[material[j]]) : 1.0;
    }
  } else {
    for (int a = 0; a < n; ++a) c->scale[a] = 1.0;
  }
  /* a constant layer count for the common ones, so the layers of a bond are one short vector */
  bool yielded;
  switch (pl->layers) {
  case 1: yielded = plastic_return_chunk(s, pl, i, k0, n, c, 1); break;
  case 2: yielded = plastic_return_chunk(s, pl, i, k0, n, c, 2); break;
  case 3: yielded = plastic_return_chunk(s, pl, i, k0, n, c, 3); break;
  case 4: yielded = plastic_return_chunk(s, pl, i, k0, n, c, 4); break;
  default: yielded = plastic_return_chunk(s, pl, i, k0, n, c, pl->layers); break;
  }
  *any_yielded |= yielded;
  /* ductile failure: a bond whose plastic stretch passes the critical one breaks now (both
   * ends see the same plastic stretch; no-fail nodes never break) */
  if (breaking && pl->ductile && !(s->disc.p.flags[i] & PERI_NODE_NO_FAIL)) {
    const int32_t *material = s->disc.p.material;
    const double *critical = pl->critical + material[i] * pl->nm;
    for (int a = 0; a < n; ++a)
      if (c->intact[a] != 0.0 && fabs(c->s[a] - c->se[a]) > critical[material[c->j[a]]] &&
          !(s->disc.p.flags[c->j[a]] & PERI_NODE_NO_FAIL)) {
        s->disc.bonds.broken[k0 + a] = 1;
        c->intact[a] = 0.0;
        ++*broken;
      }
  }
  /* energy failure: a bond whose work (stored and dissipated) reaches the critical one breaks
   * now (the same on both ends: the work is symmetric in i and j) */
  if (breaking && pl->energetic && !(s->disc.p.flags[i] & PERI_NODE_NO_FAIL)) {
    const int32_t *material = s->disc.p.material;
    const int row = material[i] * pl->nm, L = pl->layers;
    const double *sp = s->state.plastic_stretch + k0 * L;
    for (int a = 0; a < n; ++a) {
      const int pair = row + material[c->j[a]];
      if (c->intact[a] == 0.0 || !isfinite(pl->work[pair]) || (s->disc.p.flags[c->j[a]] & PERI_NODE_NO_FAIL)) continue;
      const double *W = pl->W + pair * L, *Y = pl->Y + pair * L, st = c->s[a];
      double phi = 0.0; /* sum_l W_l ((s - s^p_l)^2 / 2 + s_yl |s^p_l|) over the real layers */
      for (int l = 0; l < L; ++l)
        if (W[l] != 0.0) phi += W[l] * (0.5 * (st - sp[a * L + l]) * (st - sp[a * L + l]) + Y[l] * fabs(sp[a * L + l]));
      const double r0 = c->r0[a];
      if (pl->c[pair] * peri_eval_omega(&w->fam, s->disc.bonds.family.influence, r0) * r0 * phi >= pl->work[pair]) {
        s->disc.bonds.broken[k0 + a] = 1;
        c->intact[a] = 0.0;
        ++*broken;
      }
    }
  }
}

long peri_plastic_pmb_node(peri_sim *s, const peri_bond_view *w, const peri_plastic_pass *pl, int32_t i,
                           plastic_chunk *c, double f[3], double *smin_out) {
  const peri_bonds *b = &s->disc.bonds;
  const bool breaking = s->solver.breaking, thermal = s->state.thermal_strain != NULL;
  const peri_influence influence = b->family.influence;
  const double ci = w->coef[i];
  double f0 = 0.0, f1 = 0.0, f2 = 0.0, smin = INFINITY;
  long n_broken = 0;
  bool yielded = false;
  for (int64_t k0 = b->offset[i]; k0 < b->offset[i + 1]; k0 += PLASTIC_CHUNK) {
    const int n = (int)(b->offset[i + 1] - k0 < PLASTIC_CHUNK ? b->offset[i + 1] - k0 : PLASTIC_CHUNK);
    if (thermal) plastic_chunk_map(s, w, pl, i, k0, n, breaking, true, c, &n_broken, &smin, &yielded);
    else plastic_chunk_map(s, w, pl, i, k0, n, breaking, false, c, &n_broken, &smin, &yielded);
    double g[PLASTIC_CHUNK];
#pragma omp simd
    for (int a = 0; a < n; ++a) {
      const int32_t j = c->j[a];
      const double r0 = c->r0[a];
      const double scale = 0.5 * (ci + w->coef[j]) * c->se[a] * peri_eval_omega(&w->fam, influence, r0) *
                           peri_eval_beta(&w->fam, r0) * w->V[j] / c->r[a];
      g[a] = c->intact[a] != 0.0 && c->r[a] > 0.0 ? scale : 0.0;
    }
    for (int a = 0; a < n; ++a) { /* in family order */
      f0 = fma(g[a], c->y0[a], f0);
      f1 = fma(g[a], c->y1[a], f1);
      f2 = fma(g[a], c->y2[a], f2);
    }
  }
  f[0] = f0, f[1] = f1, f[2] = f2;
  *smin_out = smin;
  s->state.plastic_nodes[i] = yielded; /* (the node's own flag, written by its thread) */
  return n_broken;
}

/* Whether node i has no plastic state: its flag (s->state.plastic_nodes, written from its own
 * bonds' state whenever the loops map it, and built from the state when NULL) is 0, so every
 * plastic stretch of its bonds is 0 and the energies need not read them (the same numbers). */
static inline bool node_at_rest(const peri_sim *s, int32_t i) {
  return s->state.plastic_nodes && !s->state.plastic_nodes[i];
}

/* The mechanical stretch s = (r - |xi|)/|xi| - (eth_i + eth_j)/2 of a chunk's bonds, by a
 * vector loop (the numbers the energies took bond by bond). */
static void chunk_stretches(const peri_sim *s, int32_t i, int64_t k0, int n, const peri_bond_chunk *c,
                            double *restrict stretch) {
  const double *restrict eth = s->state.thermal_strain;
  const int32_t *restrict nbr = s->disc.bonds.neighbor + k0;
  if (eth) {
#pragma omp simd
    for (int a = 0; a < n; ++a) stretch[a] = (c->r[a] - c->L[a]) / c->L[a] - 0.5 * (eth[i] + eth[nbr[a]]);
  } else {
#pragma omp simd
    for (int a = 0; a < n; ++a) stretch[a] = (c->r[a] - c->L[a]) / c->L[a];
  }
}

/* The elastic parts of the micropotentials of a chunk of node i's bonds, sum_l W_l (s - s^p_l)^2
 * / 2 each, when every bond has the sublayers sl (one material): a vector loop, the state not
 * read where the node has none (rest), each value by peri_sublayer_energy's operations. */
static inline __attribute__((always_inline)) void uniform_energies(const peri_sublayers *restrict sl,
                                                                   const double *restrict stretch,
                                                                   const double *restrict rows, bool rest, int n,
                                                                   const int L, double *restrict e2) {
  const int nl = sl->n;
  const double *restrict weight = sl->weight;
  if (rest) {
#pragma omp simd
    for (int a = 0; a < n; ++a) {
      double e = 0.0;
      for (int l = 0; l < nl; ++l) e += 0.5 * weight[l] * stretch[a] * stretch[a];
      e2[a] = e;
    }
  } else {
#pragma omp simd
    for (int a = 0; a < n; ++a) {
      double e = 0.0;
      for (int l = 0; l < nl; ++l) e += 0.5 * weight[l] * (stretch[a] - rows[a * L + l]) * (stretch[a] - rows[a * L + l]);
      e2[a] = e;
    }
  }
}

void peri_plastic_pmb_energy(peri_sim *s, double *W) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  /* one material: every bond has its sublayers and micromodulus */
  const peri_sublayers *uniform = s->mat.n_materials == 1 ? s->mat.materials[0].sublayers : NULL;
#pragma omp parallel
  {
    peri_bond_chunk *c = peri_malloc(sizeof *c);
    double stretch[PERI_BOND_CHUNK], e2[PERI_BOND_CHUNK];
    const double *state = s->state.plastic_stretch;
    const int L = s->state.plastic_layers;
    static const double at_rest[PERI_MAX_SUBLAYERS]; /* the rows of a node without a plastic state */
#pragma omp for schedule(static)
    for (int32_t i = 0; i < p->n_owned; ++i) {
      const double ci = s->mat.materials[p->material[i]].micromodulus;
      const bool rest = node_at_rest(s, i);
      double sum = 0.0;
      for (int64_t k0 = b->offset[i]; k0 < b->offset[i + 1]; k0 += PERI_BOND_CHUNK) {
        const int nk = peri_bond_chunk_size(b, i, k0);
        peri_bond_chunk_fill(s, i, k0, nk, c);
        chunk_stretches(s, i, k0, nk, c, stretch);
        if (uniform) {
          if (L == 4) uniform_energies(uniform, stretch, state + k0 * L, rest, nk, 4, e2);
          else uniform_energies(uniform, stretch, state + k0 * L, rest, nk, L, e2);
        }
        for (int a = 0; a < nk; ++a) {
          const int64_t k = k0 + a;
          if (b->broken[k]) continue;
          const int32_t j = b->neighbor[k];
          if (!uniform) {
            const peri_sublayers *sl = bond_layers(s, i, j);
            /* per bond sum_k W_k c (s - s^p_k)^2 |xi| / 2 (the elastic part of the micropotential) */
            e2[a] = sl ? peri_sublayer_energy(sl, stretch[a], rest ? at_rest : state + k * L)
                       : 0.5 * stretch[a] * stretch[a];
          }
          const double cm = 0.5 * (ci + s->mat.materials[p->material[j]].micromodulus);
          sum += cm * e2[a] * c->omega[a] * c->L[a] * c->beta[a] * p->volume[j];
        }
      }
      W[i] = 0.5 * sum;
    }
    free(c);
  }
}

long peri_plastic_lps_node_sums(peri_sim *s, const peri_bond_view *w, const peri_plastic_pass *pl, int32_t i,
                                plastic_chunk *c, double sums[2], double *smin_out) {
  const peri_bonds *b = &s->disc.bonds;
  const double *eth = s->state.thermal_strain;
  const bool breaking = s->solver.breaking, thermal = eth != NULL;
  const peri_influence influence = b->family.influence;
  const double eth_i = thermal ? eth[i] : 0.0;
  double we_x = 0.0, w_xx = 0.0, smin = INFINITY;
  long n_broken = 0;
  bool yielded = false;
  for (int64_t k0 = b->offset[i]; k0 < b->offset[i + 1]; k0 += PLASTIC_CHUNK) {
    const int nk = (int)(b->offset[i + 1] - k0 < PLASTIC_CHUNK ? b->offset[i + 1] - k0 : PLASTIC_CHUNK);
    if (thermal) plastic_chunk_map(s, w, pl, i, k0, nk, breaking, true, c, &n_broken, &smin, &yielded);
    else plastic_chunk_map(s, w, pl, i, k0, nk, breaking, false, c, &n_broken, &smin, &yielded);
    double q[PLASTIC_CHUNK], x[PLASTIC_CHUNK];
#pragma omp simd
    for (int a = 0; a < nk; ++a) {
      const double r0 = c->r0[a];
      /* w = omega |xi| beta V_j (0 for a broken bond); q = e^e - alpha_T dT_i |xi| with the
       * elastic extension e^e = (s - s^p) |xi| + the bond's thermal extension */
      const double wt =
          c->intact[a] * peri_eval_omega(&w->fam, influence, r0) * r0 * peri_eval_beta(&w->fam, r0) * w->V[c->j[a]];
      const double plastic = c->s[a] - c->se[a];
      q[a] = wt * (c->r[a] - r0 - (plastic + eth_i) * r0);
      x[a] = wt * r0;
    }
    for (int a = 0; a < nk; ++a) we_x += q[a], w_xx += x[a]; /* in family order */
  }
  sums[0] = we_x, sums[1] = w_xx;
  *smin_out = smin;
  s->state.plastic_nodes[i] = yielded; /* (the node's own flag, written by its thread) */
  return n_broken;
}

#ifdef PERI_BOND_V8
/* sum_l W_l s^p_l of n bonds of L layers each (the padding layers have W = 0) into plastic[]. */
static inline __attribute__((always_inline)) void plastic_sums(const double *restrict sp, const double *restrict W,
                                                               int n, const int L, double *restrict plastic) {
#pragma omp simd
  for (int a = 0; a < n; ++a) {
    double sum = 0.0;
    for (int l = 0; l < L; ++l) sum += W[l] * sp[a * L + l];
    plastic[a] = sum;
  }
}

/* Node i's force over bonds k0 .. k0+n-1 of its family (constant or inverse influence), with
 * plastic[] their plastic stretches sum_l W_l s^p_l and on[] their intact flags as doubles
 * (arrays of PLASTIC_CHUNK): the bond values by the eight-lane lengths of the elastic kernels
 * (bond_kernel.h: reciprocal square roots, no square root or division), their sums in family
 * order into f. */
static void lps_plastic_force_chunk_v8(const peri_bond_view *w, int32_t i, int64_t k0, int n, bool inverse,
                                       const double *restrict plastic, const double *restrict on, double f[3]) {
  const int32_t *restrict nbr = w->neighbor + k0;
  const double *D = w->coef, *B = w->coef + w->n;
  const peri_v8d c[3] = {v8_set1_pd(w->x0[i]), v8_set1_pd(w->x1[i]), v8_set1_pd(w->x2[i])},
                 cu[3] = {v8_set1_pd(w->u0[i]), v8_set1_pd(w->u1[i]), v8_set1_pd(w->u2[i])};
  const peri_v8d Di = v8_set1_pd(D[i]), Bi = v8_set1_pd(B[i]), zero = v8_setzero_pd();
  double g[PLASTIC_CHUNK], y0[PLASTIC_CHUNK], y1[PLASTIC_CHUNK], y2[PLASTIC_CHUNK];
  for (int a = 0; a < n; a += 8) {
    const peri_m8 m = peri_first_lanes(n - a);
    const peri_v8i j = v8_maskz_loadu_epi32(m, nbr + a);
    const peri_v8d xj[3] = {v8_mask_i32gather_pd(m, j, w->x0), v8_mask_i32gather_pd(m, j, w->x1),
                            v8_mask_i32gather_pd(m, j, w->x2)};
    const peri_v8d uj[3] = {v8_mask_i32gather_pd(m, j, w->u0), v8_mask_i32gather_pd(m, j, w->u1),
                            v8_mask_i32gather_pd(m, j, w->u2)};
    peri_v8d y[3], r0, inv_r0, r, inv_r;
    peri_bond_lengths_v8(xj, uj, c, cu, y, &r0, &inv_r0, &r, &inv_r);
    const peri_v8d d0 = y[0], d1 = y[1], d2 = y[2];
    const peri_v8d r_sq = v8_fmadd_pd(d2, d2, v8_fmadd_pd(d1, d1, v8_mul_pd(d0, d0)));
    /* t_ij + t_ji = omega (|xi| (D_i + D_j) + e^e (B_i + B_j)), e^e = r - |xi| - s^p |xi| */
    const peri_v8d e = v8_fnmadd_pd(v8_loadu_pd(plastic + a), r0, v8_sub_pd(r, r0));
    const peri_v8d t = v8_fmadd_pd(r0, v8_add_pd(Di, v8_mask_i32gather_pd(m, j, D)),
                                   v8_mul_pd(e, v8_add_pd(Bi, v8_mask_i32gather_pd(m, j, B))));
    const peri_v8d bv = v8_mul_pd(v8_mul_pd(peri_beta_v8(&w->fam, r0), v8_mask_i32gather_pd(m, j, w->V)),
                                  v8_loadu_pd(on + a));
    peri_v8d gv = v8_mul_pd(v8_mul_pd(t, bv), inv_r);
    if (inverse) gv = v8_mul_pd(gv, inv_r0); /* omega = 1/|xi| */
    /* coincident ends have no direction and give no force */
    gv = v8_maskz_mov_pd(v8_cmp_pd_mask(r_sq, zero, _CMP_GT_OQ), gv);
    v8_mask_storeu_pd(g + a, m, gv);
    v8_mask_storeu_pd(y0 + a, m, d0);
    v8_mask_storeu_pd(y1 + a, m, d1);
    v8_mask_storeu_pd(y2 + a, m, d2);
  }
  for (int a = 0; a < n; ++a) {
    f[0] = fma(g[a], y0[a], f[0]);
    f[1] = fma(g[a], y1[a], f[1]);
    f[2] = fma(g[a], y2[a], f[2]);
  }
}
#endif

void peri_plastic_lps_node_force(const peri_sim *s, const peri_bond_view *w, const peri_plastic_pass *pl, int32_t i,
                                 double f[3]) {
  const peri_bonds *b = &s->disc.bonds;
  const int L = pl->layers;
  const int32_t *material = s->disc.p.material;
  const int row = material[i] * pl->nm;
  const double *D = w->coef, *B = w->coef + w->n;
  const peri_influence influence = b->family.influence;
#ifdef PERI_BOND_V8
  if (influence != PERI_INFLUENCE_GAUSSIAN) { /* (exp has no eight-lane function) */
    double plastic[PLASTIC_CHUNK], on[PLASTIC_CHUNK];
    f[0] = f[1] = f[2] = 0.0;
    for (int64_t k0 = b->offset[i]; k0 < b->offset[i + 1]; k0 += PLASTIC_CHUNK) {
      const int n = (int)(b->offset[i + 1] - k0 < PLASTIC_CHUNK ? b->offset[i + 1] - k0 : PLASTIC_CHUNK);
      const double *restrict sp = s->state.plastic_stretch + k0 * L;
      for (int a = 0; a < n; ++a) on[a] = b->broken[k0 + a] ? 0.0 : 1.0;
      if (pl->nm == 1) {
        switch (L) { /* (constant layer counts for the common ones: a vector loop over the bonds) */
        case 1: plastic_sums(sp, pl->W, n, 1, plastic); break;
        case 2: plastic_sums(sp, pl->W, n, 2, plastic); break;
        case 3: plastic_sums(sp, pl->W, n, 3, plastic); break;
        case 4: plastic_sums(sp, pl->W, n, 4, plastic); break;
        default: plastic_sums(sp, pl->W, n, L, plastic); break;
        }
      } else {
        for (int a = 0; a < n; ++a) plastic_sums(sp + a * L, pl->W + (row + material[b->neighbor[k0 + a]]) * L, 1, L, plastic + a);
      }
      lps_plastic_force_chunk_v8(w, i, k0, n, influence == PERI_INFLUENCE_INVERSE, plastic, on, f);
    }
    return;
  }
#endif
  double f0 = 0.0, f1 = 0.0, f2 = 0.0;
  for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
    if (b->broken[k]) continue;
    const int32_t j = b->neighbor[k];
    const double x0 = w->x0[j] - w->x0[i], x1 = w->x1[j] - w->x1[i], x2 = w->x2[j] - w->x2[i];
    const double d0 = x0 + (w->u0[j] - w->u0[i]), d1 = x1 + (w->u1[j] - w->u1[i]), d2 = x2 + (w->u2[j] - w->u2[i]);
    const double r0 = sqrt(x0 * x0 + x1 * x1 + x2 * x2), r = sqrt(d0 * d0 + d1 * d1 + d2 * d2);
    const double *W = pl->W + (row + material[j]) * L, *sp = s->state.plastic_stretch + k * L;
    double plastic = 0.0; /* sum_l W_l s^p_l (the padding layers have W = 0) */
    for (int l = 0; l < L; ++l) plastic += W[l] * sp[l];
    /* t_ij + t_ji = omega (|xi| (D_i + D_j) + e^e (B_i + B_j)), e^e = r - |xi| - s^p |xi| */
    const double t = peri_eval_omega(&w->fam, influence, r0) * (r0 * (D[i] + D[j]) + (r - r0 - plastic * r0) * (B[i] + B[j]));
    const double g = r > 0.0 ? t * peri_eval_beta(&w->fam, r0) * w->V[j] / r : 0.0;
    f0 = fma(g, d0, f0), f1 = fma(g, d1, f1), f2 = fma(g, d2, f2);
  }
  f[0] = f0, f[1] = f1, f[2] = f2;
}

long peri_plastic_mo_node_sums(peri_sim *s, const peri_bond_view *w, const peri_plastic_pass *pl, int32_t i,
                               plastic_chunk *c, double *sum) {
  const peri_bonds *b = &s->disc.bonds;
  const double *eth = s->state.thermal_strain;
  const bool breaking = s->solver.breaking, thermal = eth != NULL;
  const double eth_i = thermal ? eth[i] : 0.0;
  double total = 0.0, smin = INFINITY;
  long n_broken = 0;
  bool yielded = false;
  for (int64_t k0 = b->offset[i]; k0 < b->offset[i + 1]; k0 += PLASTIC_CHUNK) {
    const int nk = (int)(b->offset[i + 1] - k0 < PLASTIC_CHUNK ? b->offset[i + 1] - k0 : PLASTIC_CHUNK);
    if (thermal) plastic_chunk_map(s, w, pl, i, k0, nk, breaking, true, c, &n_broken, &smin, &yielded);
    else plastic_chunk_map(s, w, pl, i, k0, nk, breaking, false, c, &n_broken, &smin, &yielded);
    double term[PLASTIC_CHUNK];
#pragma omp simd
    for (int a = 0; a < nk; ++a) {
      const int32_t j = c->j[a];
      const double r0 = c->r0[a], r = c->r[a];
      const double x_dot_y = (w->x0[j] - w->x0[i]) * c->y0[a] + (w->x1[j] - w->x1[i]) * c->y1[a] +
                             (w->x2[j] - w->x2[i]) * c->y2[a];
      const double cosine = r > 0.0 ? x_dot_y / (r * r0) : 0.0;
      /* (s^e L - eth_i) beta V_j (0 for a broken bond), s^e = (r - |xi|)/|xi| - s^p */
      const double se = (r - r0) / r0 - (c->s[a] - c->se[a]);
      term[a] = c->intact[a] * (se * cosine - eth_i) * peri_eval_beta(&w->fam, r0) * w->V[j];
    }
    for (int a = 0; a < nk; ++a) total += term[a]; /* in family order */
  }
  *sum = total;
  s->state.plastic_nodes[i] = yielded; /* (the node's own flag, written by its thread) */
  return n_broken;
}

void peri_plastic_mo_node_force(const peri_sim *s, const peri_bond_view *w, const peri_plastic_pass *pl, int32_t i,
                                double f[3]) {
  const peri_bonds *b = &s->disc.bonds;
  const int L = pl->layers;
  const int32_t *material = s->disc.p.material;
  const int row = material[i] * pl->nm;
  const size_t n = (size_t)w->n;
  const double *A = w->coef, *B = w->coef + n, *C = w->coef + 2 * n;
  double f0 = 0.0, f1 = 0.0, f2 = 0.0;
  for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
    if (b->broken[k]) continue;
    const int32_t j = b->neighbor[k];
    const double x0 = w->x0[j] - w->x0[i], x1 = w->x1[j] - w->x1[i], x2 = w->x2[j] - w->x2[i];
    const double d0 = x0 + (w->u0[j] - w->u0[i]), d1 = x1 + (w->u1[j] - w->u1[i]), d2 = x2 + (w->u2[j] - w->u2[i]);
    const double r0 = sqrt(x0 * x0 + x1 * x1 + x2 * x2), r = sqrt(d0 * d0 + d1 * d1 + d2 * d2);
    if (!(r > 0.0)) continue;
    const double *W = pl->W + (row + material[j]) * L, *sp = s->state.plastic_stretch + k * L;
    double plastic = 0.0; /* sum_l W_l s^p_l (the padding layers have W = 0) */
    for (int l = 0; l < L; ++l) plastic += W[l] * sp[l];
    /* t_ij + t_ji = (A_i + A_j) L/|xi| + (B_i + B_j) s^e - (C_i + C_j) (src/model/osb_mo.c) */
    const double cos_r0 = (x0 * d0 + x1 * d1 + x2 * d2) / (r * r0 * r0);
    const double t = (A[i] + A[j]) * cos_r0 + (B[i] + B[j]) * ((r - r0) / r0 - plastic) - (C[i] + C[j]);
    const double g = t * peri_eval_beta(&w->fam, r0) * w->V[j] / r;
    f0 = fma(g, d0, f0), f1 = fma(g, d1, f1), f2 = fma(g, d2, f2);
  }
  f[0] = f0, f[1] = f1, f[2] = f2;
}

void peri_plastic_lps_energy(peri_sim *s, double *W) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const double *eth = s->state.thermal_strain;
#pragma omp parallel
  {
    peri_bond_chunk *c = peri_malloc(sizeof *c);
#pragma omp for schedule(static)
    for (int32_t i = 0; i < p->n_owned; ++i) {
      const double eth_i = eth ? eth[i] : 0.0;
      const bool rest = node_at_rest(s, i);
      double wq = 0.0, wx = 0.0, q2 = 0.0; /* sum w q, sum w |xi|, sum omega beta V q^2 */
      for (int64_t k0 = b->offset[i]; k0 < b->offset[i + 1]; k0 += PERI_BOND_CHUNK) {
        const int nk = peri_bond_chunk_size(b, i, k0);
        peri_bond_chunk_fill(s, i, k0, nk, c);
        for (int a = 0; a < nk; ++a) {
          const int64_t k = k0 + a;
          if (b->broken[k]) continue;
          const double r = c->r[a], r0 = c->L[a];
          const double q = r - r0 - ((rest ? 0.0 : peri_plastic_bond_stretch(s, i, k)) + eth_i) * r0;
          const double obv = c->omega[a] * c->beta[a] * p->volume[b->neighbor[k]];
          wq += obv * r0 * q, wx += obv * r0 * r0, q2 += obv * q * q;
        }
      }
      const peri_material *mat = &s->mat.materials[p->material[i]];
      const double m = p->wvol[i], theta = mat->n_theta * wq / m;
      const double deviatoric = q2 - (2.0 * theta / 3.0) * wq + (theta * theta / 9.0) * wx;
      W[i] = mat->peer_force_state ? peri_lps_peer_energy(mat, theta, mat->alpha_m / m, q2)
                                   : 0.5 * mat->K_theta * theta * theta + 0.5 * (mat->alpha_m / m) * deviatoric;
    }
    free(c);
  }
}

void peri_plastic_dissipation(const peri_sim *s, double *D, const uint8_t *wanted) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const bool lps = !strcmp(s->mat.model->name, "lps"); /* (by name: the model table calls this file) */
  const bool mo = !strcmp(s->mat.model->name, "osb_mo");
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const peri_material *mi = &s->mat.materials[p->material[i]];
    double sum = 0.0;
    /* (a node without a plastic state has dissipated nothing: its bonds are not read) */
    const int64_t end = (wanted && !wanted[i]) || node_at_rest(s, i) ? b->offset[i] : b->offset[i + 1];
    for (int64_t k = b->offset[i]; k < end; ++k) {
      const int32_t j = b->neighbor[k];
      const peri_sublayers *sl = bond_layers(s, i, j);
      if (!sl) continue;
      double row[PERI_MAX_SUBLAYERS];
      const double *sp = peri_plastic_row(s, s->state.plastic_stretch, k, row);
      double work = 0.0; /* sum_l W_l s_yl |s^p_l| */
      for (int l = 0; l < sl->n; ++l) work += sl->weight[l] * sl->yield[l] * fabs(sp[l]);
      if (work == 0.0) continue;
      const double r0 = peri_bond_length(p->x, i, j);
      /* k_ij: node i's energy holds k_ij s^2 / 2 of this bond */
      /* (osb_mo: b_i omega e^2 with omega = delta/|xi|, b_i = (alpha m)/(2 m_i), src/model/osb_mo.c) */
      const double stiffness = mo    ? (mi->alpha_m / p->wvol[i]) * s->disc.geom.horizon * r0
                               : lps ? (mi->alpha_m / p->wvol[i]) * r0 * r0
                                     : 0.25 * (mi->micromodulus + s->mat.materials[p->material[j]].micromodulus) * r0;
      sum += stiffness * peri_bonds_omega(b, r0) * peri_bonds_beta(b, r0) * p->volume[j] * work;
    }
    D[i] = sum;
  }
}
