/* Tangent stiffness of the LPS model (src/model/lps.c), analytic and exact for the discrete
 * force, in the current configuration. Analytic rather than by differencing the force per
 * family: the LPS half-state is affine in two quantities only, so the exact derivative is
 * short, costs no force evaluations and carries no truncation error (which would spoil
 * Newton's quadratic convergence near the solution).
 *
 * With the extension e_ij = r_ij - L_ij - eth_i L_ij (r = |y_j - y_i|), the weight
 * w_ij = omega L beta V_j and S_i = sum_j w_ij e_ij over intact bonds, lps.c has
 *   theta_i = n_theta S_i / m_i,   P_i = S_i - theta_i sum_j w_ij L_ij / 3 = q_i S_i,
 * so i's half of the pair force is (docs/model_reference.md 3.3)
 *   t_ij = alpha_i omega e_ij + omega L g_i S_i,
 *   g_i  = n_theta^2 K_theta / m_i^2 - n_theta alpha_i (q_i + 1) / (3 m_i),  alpha_i = alpha_m / m_i.
 * The force f_i = sum_j (t_ij + t_ji) beta V_j n_ij (n_ij = (y_j - y_i)/r_ij) then has
 *   d f_i / d u = sum_j beta V_j [ n_ij (x) dT_ij + T_ij (I - n_ij n_ij^T)/r_ij d r_ij ],
 * with d r_ij = n_ij.(du_j - du_i), dS_i = sum_k w_ik n_ik.(du_k - du_i). Collected by the
 * column they multiply, the blocks of row i are
 *   pair      (i,j) += beta V_j [(alpha_i + alpha_j) omega n n^T + (T_ij/r)(I - n n^T)], (i,i) -= same
 *   own S_i   (i,k) += g_i s_i (x) w_ik n_ik,   (i,i) -= g_i s_i (x) s_i,   s_i = sum_k w_ik n_ik
 *   S_j       (i,k) += g_j w_ij n_ij (x) w_jk n_jk for k in the family of j (k = i included),
 *             (i,j) -= g_j w_ij n_ij (x) s_j
 * so row i reaches the neighbours of its neighbours (2 delta). V_i K_ij is symmetric (the
 * force derives from an energy).
 *
 * On MPI ranks only owned nodes have families. Row i of an owned node needs, of a ghost
 * neighbour j, the scalars alpha_j, g_j, S_j (exchanged) for the pair term, and j's family
 * for the S_j terms: those are added by the rank that owns j instead, in a pass over the
 * ghosts i of that rank, each row gathered from i's owned neighbours j (rows of ghosts, which
 * PETSc sends to their owners). Each pair (i, j) is counted once: by the row pass when j is
 * owned here, by the ghost pass of j's owner when i is a ghost there. In a single process
 * there are no ghosts and no ghost pass: the rows are exactly those of the serial code. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/sim.h"
#include "bond_kernel.h"

/* Per-node quantities of the current state. */
typedef struct node_state {
  double S;      /* sum_j w_ij e_ij */
  double svec[3]; /* s_i = sum_j w_ij n_ij */
  double g;      /* coefficient of S_i in t_ij / (omega L) */
  double alpha;  /* alpha_m / m_i */
} node_state;

/* The blocks of one row, accumulated by column through a marker array. */
typedef struct row_blocks {
  int32_t *slot; /* [n] position of column j in this row, -1 when absent */
  int32_t *cols;
  double *blk;   /* 9 per column */
  int32_t count, capacity;
} row_blocks;

static double *block_of(row_blocks *rb, int32_t j) {
  if (rb->slot[j] < 0) {
    if (rb->count == rb->capacity) {
      rb->capacity = rb->capacity ? 2 * rb->capacity : 256;
      rb->cols = peri_realloc(rb->cols, sizeof(int32_t) * (size_t)rb->capacity);
      rb->blk = peri_realloc(rb->blk, sizeof(double) * 9 * (size_t)rb->capacity);
    }
    rb->slot[j] = rb->count;
    rb->cols[rb->count] = j;
    memset(&rb->blk[9 * (size_t)rb->count], 0, sizeof(double) * 9);
    rb->count++;
  }
  return &rb->blk[9 * (size_t)rb->slot[j]];
}

/* blk += a (u v^T) */
static void add_outer(double *blk, double a, const double u[3], const double v[3]) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) blk[3 * r + c] += a * u[r] * v[c];
}

/* Node states, and per bond w_ij n_ij (zero when broken or of zero length). */
static void compute_states(const peri_sim *s, node_state *st, double *wn) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const double *eth = s->state.thermal_strain;
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const peri_material *mat = &s->mat.materials[p->material[i]];
    const double eth_i = eth ? eth[i] : 0.0;
    double S = 0.0, wxx = 0.0, sv[3] = {0.0, 0.0, 0.0};
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      double *wnk = &wn[3 * (size_t)k];
      wnk[0] = wnk[1] = wnk[2] = 0.0;
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double dy[3];
      const double L = peri_bond_length(p->x, i, j);
      const double r = peri_deformed_bond(p->x, p->u, i, j, dy);
      const double w = peri_bonds_omega(b, L) * L * peri_bonds_beta(b, L) * p->volume[j];
      S += w * (r - L - eth_i * L);
      wxx += w * L;
      if (r > 0.0)
        for (int d = 0; d < 3; ++d) wnk[d] = w * dy[d] / r, sv[d] += wnk[d];
    }
    const double m = p->wvol[i], nt = mat->n_theta;
    /* P_i = q_i S_i; the peer force state (docs/models.md 3.5) has the intact family's q (its
     * force is the gradient of the Madenci-Oterkus energy, so the tangent stays symmetric) */
    const double alpha = mat->alpha_m / m, q = 1.0 - nt * (mat->peer_force_state ? m : wxx) / (3.0 * m);
    st[i].S = S;
    for (int d = 0; d < 3; ++d) st[i].svec[d] = sv[d];
    st[i].alpha = alpha;
    st[i].g = nt * nt * mat->K_theta / (m * m) - nt * alpha * (q + 1.0) / (3.0 * m);
  }
}

/* The blocks of row i into rb. */
static void row(const peri_sim *s, const node_state *st, const double *wn, int32_t i, row_blocks *rb) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const double *eth = s->state.thermal_strain;
  const int dim = s->disc.geom.dim;
  const node_state *si = &st[i];
  add_outer(block_of(rb, i), -si->g, si->svec, si->svec);
  for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
    if (b->broken[k]) continue;
    const int32_t j = b->neighbor[k];
    double dy[3], n[3];
    const double r = peri_deformed_bond(p->x, p->u, i, j, dy);
    if (r <= 0.0) continue;
    for (int d = 0; d < 3; ++d) n[d] = dy[d] / r;
    const node_state *sj = &st[j];
    const double L = peri_bond_length(p->x, i, j), omega = peri_bonds_omega(b, L);
    const double bV = peri_bonds_beta(b, L) * p->volume[j], w_ij = omega * L * bV;
    const double e_i = r - L - (eth ? eth[i] : 0.0) * L, e_j = r - L - (eth ? eth[j] : 0.0) * L;
    const double T = si->alpha * omega * e_i + omega * L * si->g * si->S + sj->alpha * omega * e_j +
                     omega * L * sj->g * sj->S;
    /* pair term */
    double pair[9];
    const double axial = bV * (si->alpha + sj->alpha) * omega, geometric = bV * T / r;
    for (int r1 = 0; r1 < 3; ++r1)
      for (int c1 = 0; c1 < 3; ++c1)
        pair[3 * r1 + c1] = axial * n[r1] * n[c1] + geometric * ((r1 == c1) - n[r1] * n[c1]);
    double *dij = block_of(rb, j);
    double *dii = block_of(rb, i); /* after block_of(j), which may move the storage */
    for (int e = 0; e < 9; ++e) dij[e] += pair[e], dii[e] -= pair[e];
    /* own dilatation: d S_i / d u_j = w_ij n_ij */
    add_outer(dij, si->g * w_ij, si->svec, n);
    /* the neighbour's dilatation: d S_j / d u_k = w_jk n_jk, d S_j / d u_j = -s_j; a ghost
     * j has no family here: its owner adds these (ghost_row) */
    if (j >= p->n_owned) continue;
    const double coef = sj->g * w_ij;
    add_outer(dij, -coef, n, sj->svec);
    /* the hot loop (neighbours of neighbours): only the dim x dim part is nonzero */
    double a[3];
    for (int d = 0; d < 3; ++d) a[d] = coef * n[d];
    for (int64_t l = b->offset[j]; l < b->offset[j + 1]; ++l) {
      const double *wnl = &wn[3 * (size_t)l];
      if (b->broken[l]) continue;
      double *blk = block_of(rb, b->neighbor[l]);
      for (int r1 = 0; r1 < dim; ++r1)
        for (int c1 = 0; c1 < dim; ++c1) blk[3 * r1 + c1] += a[r1] * wnl[c1];
    }
  }
}

/* alpha, g and S of the ghosts from their owners (the pair term of row i reads them). */
static void exchange_states(const peri_sim *s, node_state *st) {
  const peri_particles *p = &s->disc.p;
  double *field = peri_malloc(sizeof(double) * 3 * (size_t)p->n);
  for (int32_t i = 0; i < p->n_owned; ++i) {
    field[3 * (size_t)i] = st[i].alpha;
    field[3 * (size_t)i + 1] = st[i].g;
    field[3 * (size_t)i + 2] = st[i].S;
  }
  /* the exchange writes only this scratch field's ghost slots; the simulation is unchanged */
  peri_sim_exchange((peri_sim *)s, field, 3);
  for (int32_t i = p->n_owned; i < p->n; ++i) {
    st[i].alpha = field[3 * (size_t)i];
    st[i].g = field[3 * (size_t)i + 1];
    st[i].S = field[3 * (size_t)i + 2];
  }
  free(field);
}

/* The owned centres j bonded (intact) to each ghost: ghost g = i - n_owned has the centres
 * centre[start[g] .. start[g+1]-1], ascending. */
typedef struct ghost_bonds {
  int64_t *start;
  int32_t *centre;
} ghost_bonds;

static ghost_bonds find_ghost_bonds(const peri_sim *s) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const int32_t n_ghosts = p->n - p->n_owned;
  ghost_bonds gb = {.start = peri_calloc((size_t)n_ghosts + 1, sizeof(int64_t))};
  for (int32_t j = 0; j < p->n_owned; ++j)
    for (int64_t l = b->offset[j]; l < b->offset[j + 1]; ++l)
      if (!b->broken[l] && b->neighbor[l] >= p->n_owned) gb.start[b->neighbor[l] - p->n_owned + 1]++;
  for (int32_t g = 0; g < n_ghosts; ++g) gb.start[g + 1] += gb.start[g];
  int64_t *next = peri_malloc(sizeof(int64_t) * ((size_t)n_ghosts + 1));
  memcpy(next, gb.start, sizeof(int64_t) * ((size_t)n_ghosts + 1));
  gb.centre = peri_malloc(sizeof(int32_t) * (size_t)(gb.start[n_ghosts] > 0 ? gb.start[n_ghosts] : 1));
  for (int32_t j = 0; j < p->n_owned; ++j)
    for (int64_t l = b->offset[j]; l < b->offset[j + 1]; ++l) {
      const int32_t i = b->neighbor[l];
      if (b->broken[l] || i < p->n_owned) continue;
      gb.centre[next[i - p->n_owned]++] = j;
    }
  free(next);
  return gb;
}

/* The S_j terms of the row of ghost i from its owned neighbours j, into rb:
 * (i,j) -= g_j w_ij n_ij (x) s_j and (i,k) += g_j w_ij n_ij (x) w_jk n_jk for the intact k of
 * j's family. The centres in ascending order: the sums do not depend on the threads. */
static void ghost_row(const peri_sim *s, const node_state *st, const double *wn, const ghost_bonds *gb, int32_t i,
                      row_blocks *rb) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const int dim = s->disc.geom.dim;
  const int32_t g = i - p->n_owned;
  for (int64_t at = gb->start[g]; at < gb->start[g + 1]; ++at) {
    const int32_t j = gb->centre[at];
    const node_state *sj = &st[j];
    double dy[3], n[3];
    const double r = peri_deformed_bond(p->x, p->u, i, j, dy); /* y_j - y_i */
    if (r <= 0.0) continue;
    for (int d = 0; d < 3; ++d) n[d] = dy[d] / r;
    const double L = peri_bond_length(p->x, i, j);
    const double coef = sj->g * peri_bonds_omega(b, L) * L * peri_bonds_beta(b, L) * p->volume[j];
    add_outer(block_of(rb, j), -coef, n, sj->svec);
    double a[3];
    for (int d = 0; d < 3; ++d) a[d] = coef * n[d];
    for (int64_t m = b->offset[j]; m < b->offset[j + 1]; ++m) {
      if (b->broken[m]) continue;
      const double *wnm = &wn[3 * (size_t)m];
      double *blk = block_of(rb, b->neighbor[m]);
      for (int r1 = 0; r1 < dim; ++r1)
        for (int c1 = 0; c1 < dim; ++c1) blk[3 * r1 + c1] += a[r1] * wnm[c1];
    }
  }
}

/* A thread's row buffer over the n local nodes. */
static row_blocks row_blocks_new(int32_t n) {
  row_blocks rb = {.slot = peri_malloc(sizeof(int32_t) * (size_t)(n > 0 ? n : 1))};
  for (int32_t i = 0; i < n; ++i) rb.slot[i] = -1;
  return rb;
}

/* Hands the gathered row i to add() (one row at a time) and empties the buffer. */
static void emit_row(row_blocks *rb, int32_t i, peri_tangent_add_fn add, void *ctx) {
  if (rb->count > 0) {
#pragma omp critical(peri_lps_tangent_add)
    add(ctx, i, rb->count, rb->cols, rb->blk);
  }
  for (int32_t c = 0; c < rb->count; ++c) rb->slot[rb->cols[c]] = -1;
  rb->count = 0;
}

static void row_blocks_free(row_blocks *rb) {
  free(rb->slot);
  free(rb->cols);
  free(rb->blk);
}

void peri_lps_tangent(const peri_sim *s, peri_tangent_add_fn add, void *ctx) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  node_state *st = peri_calloc((size_t)(p->n > 0 ? p->n : 1), sizeof(node_state));
  double *wn = peri_malloc(sizeof(double) * 3 * (size_t)(b->n_bonds > 0 ? b->n_bonds : 1));
  compute_states(s, st, wn);
  if (s->par.exchange) exchange_states(s, st); /* on every rank: the exchange is collective */
  /* Rows of owned nodes in parallel, each gathered in its thread's buffer; add() is called
   * for one row at a time, once per row, so the sums do not depend on the threads. */
#pragma omp parallel
  {
    row_blocks rb = row_blocks_new(p->n);
#pragma omp for schedule(dynamic, 64)
    for (int32_t i = 0; i < p->n_owned; ++i) {
      row(s, st, wn, i, &rb);
      emit_row(&rb, i, add, ctx);
    }
    row_blocks_free(&rb);
  }
  if (p->n > p->n_owned) {
    /* Rows of ghosts (the S_j terms of their owned neighbours j), each gathered whole and
     * added once, like the rows above: their owner adds one such part per rank. */
    ghost_bonds gb = find_ghost_bonds(s);
#pragma omp parallel
    {
      row_blocks rb = row_blocks_new(p->n);
#pragma omp for schedule(dynamic, 16)
      for (int32_t i = p->n_owned; i < p->n; ++i) {
        ghost_row(s, st, wn, &gb, i, &rb);
        emit_row(&rb, i, add, ctx);
      }
      row_blocks_free(&rb);
    }
    free(gb.start);
    free(gb.centre);
  }
  free(wn);
  free(st);
}
