/* Quasi-static crack growth in the coupled model with adaptive FEM->PD switching
 * (002_b20c318388227af9.txt §2.7, MODELS.md 12.4 and 14.5). Only bonds with a PD end break
 * (FEM rows hold no bonds); after each breakage every FEM node within r delta of a PD node
 * that lost a bond becomes a PD node: r = 1 is the seed's "switching scheme 1", r = 2 its
 * "scheme 2". Switching is one-way. The rows of the coupled stiffness are computed from the
 * node types and the intact bonds whenever they are assembled (coupling.c), and a switch
 * changes only the rows of the switched nodes: the elements stay, and an element whose
 * corners are all PD enters no row. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/comm.h"
#include "peri/coupling.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/sim.h"
#include "lattice_mesh.h"

/* The lattice offsets o != 0 with |o| dx <= r delta. */
static void switch_offsets(peri_coupling *c, int dim, double dx, double reach) {
  const int R = (int)floor(reach / dx + 1e-9);
  const int side = 2 * R + 1;
  const int total = dim == 1 ? side : dim == 2 ? side * side : side * side * side;
  c->switch_offset = peri_malloc(sizeof(int32_t) * 3 * (size_t)total);
  c->n_switch_offsets = 0;
  const double limit = (reach / dx) * (reach / dx) * (1.0 + 1e-9); /* nodes at exactly r delta switch */
  for (int k = dim < 3 ? 0 : -R; k <= (dim < 3 ? 0 : R); ++k)
    for (int b = dim < 2 ? 0 : -R; b <= (dim < 2 ? 0 : R); ++b)
      for (int a = -R; a <= R; ++a) {
        if ((a == 0 && b == 0 && k == 0) || (double)(a * a + b * b + k * k) > limit) continue;
        int32_t *o = &c->switch_offset[3 * (size_t)c->n_switch_offsets++];
        o[0] = a, o[1] = b, o[2] = k;
      }
}

/* The message for a node that may not switch: it lies near the coarse part of a graded mesh
 * (id: its node number in the built, global order). */
static void cannot_switch(const double x[3], int64_t id, char *why, size_t n) {
  snprintf(why, n, "node %lld at (%g, %g, %g) should become a PD node, but its horizon reaches the coarse part of "
           "the graded mesh: widen coupling.graded_mesh.fine along the crack's path", (long long)id, x[0], x[1], x[2]);
}

/* The lattice cells (as doubles, exact below 2^53) of the nodes with lost[i] set, of every
 * rank: the ranks own consecutive runs of the global node order, so the list is in that order
 * on any number of ranks. Returns the count; *cells is freed by the caller. */
static int64_t lost_cells(const peri_sim *s, const uint8_t *lost, double **cells) {
  const peri_coupling *c = s->coupling;
  int64_t mine = 0;
  for (int32_t i = 0; i < c->n_nodes; ++i) mine += lost[i] != 0;
  double *own = peri_malloc(sizeof(double) * 3 * (size_t)(mine > 0 ? mine : 1));
  int64_t k = 0;
  for (int32_t i = 0; i < c->n_nodes; ++i) {
    if (!lost[i]) continue;
    for (int d = 0; d < 3; ++d) own[3 * k + d] = (double)c->lattice->cell[3 * (size_t)i + d];
    ++k;
  }
  if (!s->par.dd) {
    *cells = own;
    return mine;
  }
  const int size = s->par.dd->size;
  int64_t *ones = peri_malloc(sizeof(int64_t) * (size_t)size), *counts = peri_malloc(sizeof(int64_t) * (size_t)size);
  double *each = peri_malloc(sizeof(double) * (size_t)size), count = 3.0 * (double)mine;
  for (int r = 0; r < size; ++r) ones[r] = 1;
  peri_comm_allgather_doubles(&count, 1, ones, each);
  int64_t total = 0;
  for (int r = 0; r < size; ++r) counts[r] = (int64_t)each[r], total += counts[r];
  *cells = peri_malloc(sizeof(double) * (size_t)(total > 0 ? total : 1));
  peri_comm_allgather_doubles(own, 3 * mine, counts, *cells);
  free(own), free(ones), free(counts), free(each);
  return total / 3;
}

/* Makes PD every FEM node within r delta of a node with lost[i] set (a node with lost[i] set
 * included); returns how many, or -1 with a message in why when one of them may not be PD
 * (graded meshes). On MPI ranks every rank switches the nodes it holds (owned and ghosts)
 * about the lost nodes of all ranks, so the ghosts' types follow their owners'; the count and
 * the node named in the message are those of one process. */
static int64_t switch_around(peri_sim *s, const uint8_t *lost, char *why, size_t n) {
  peri_coupling *c = s->coupling;
  const peri_lattice *l = c->lattice;
  double *cells = NULL;
  const int64_t n_lost = lost_cells(s, lost, &cells);
  int64_t switched = 0, first_bad = INT64_MAX; /* the position of the first node that may not switch */
  int32_t bad = -1;
  for (int64_t a = 0; a < n_lost; ++a)
    for (int32_t q = -1; q < c->n_switch_offsets; ++q) {
      int64_t k[3];
      for (int d = 0; d < 3; ++d) k[d] = (int64_t)cells[3 * a + d] + (q >= 0 ? c->switch_offset[3 * (size_t)q + d] : 0);
      const int32_t j = peri_lattice_node(l, k);
      if (j < 0 || c->node_type[j]) continue;
      if (c->fem_only && c->fem_only[j]) {
        const int64_t at = a * ((int64_t)c->n_switch_offsets + 1) + q + 1;
        if (j < c->n_nodes && at < first_bad) first_bad = at, bad = j; /* its owner names it */
        continue;
      }
      c->node_type[j] = 1;
      switched += j < c->n_nodes;
    }
  free(cells);
  double report[5] = {bad >= 0 ? (double)first_bad : -1.0, 0, 0, 0, 0};
  if (bad >= 0) {
    report[1] = s->par.dd ? (double)s->par.dd->global_id[bad] : (double)bad;
    for (int d = 0; d < 3; ++d) report[2 + d] = s->disc.p.x[3 * (size_t)bad + d];
  }
  if (s->par.dd) { /* the first over all ranks, and the global count */
    const int size = s->par.dd->size;
    int64_t *fives = peri_malloc(sizeof(int64_t) * (size_t)size);
    double *all = peri_malloc(sizeof(double) * 5 * (size_t)size);
    for (int r = 0; r < size; ++r) fives[r] = 5;
    peri_comm_allgather_doubles(report, 5, fives, all);
    report[0] = -1.0;
    for (int r = 0; r < size; ++r)
      if (all[5 * r] >= 0.0 && (report[0] < 0.0 || all[5 * r] < report[0])) memcpy(report, &all[5 * r], sizeof report);
    free(fives), free(all);
    switched = peri_comm_sum_long((long)switched);
  }
  if (report[0] >= 0.0) {
    cannot_switch(&report[2], (int64_t)report[1], why, n);
    return -1;
  }
  c->n_pd += (int32_t)switched;
  return switched;
}

/* A point of a pre-crack lies in the body when it lies in the cell (side dx) of a node. */
static bool in_body(const peri_particles *p, int dim, double dx, const double e[3]) {
  for (int32_t j = 0; j < p->n_owned; ++j) {
    bool in = true;
    for (int d = 0; d < dim && in; ++d) in = fabs(e[d] - p->x[3 * (size_t)j + d]) <= 0.5 * dx * (1.0 + 1e-9);
    if (in) return true;
  }
  return false;
}

/* The distance from x to the segment a-b. */
static double segment_distance(const double x[3], const double a[3], const double b[3]) {
  double ab[3], ax[3], t = 0.0, len2 = 0.0, dist2 = 0.0;
  for (int d = 0; d < 3; ++d) ab[d] = b[d] - a[d], ax[d] = x[d] - a[d], t += ab[d] * ax[d], len2 += ab[d] * ab[d];
  t = len2 > 0.0 ? fmin(fmax(t / len2, 0.0), 1.0) : 0.0;
  for (int d = 0; d < 3; ++d) dist2 += (ax[d] - t * ab[d]) * (ax[d] - t * ab[d]);
  return sqrt(dist2);
}

/* Marks the nodes within reach of the pre-cracks' fronts in the body: the ends of a segment
 * (2D) that lie in the body, the parts of a rectangle's edges (3D) that do (sampled every
 * dx/2 along each edge: consecutive samples in the body bound a piece of the front). */
static void mark_fronts(const peri_sim *s, double reach, uint8_t *mark) {
  const peri_particles *p = &s->disc.p;
  const int dim = s->disc.geom.dim;
  const double dx = s->disc.geom.spacing, limit = reach * (1.0 + 1e-9);
  for (int c = 0; c < s->cond.n_precracks; ++c) {
    const peri_precrack *pc = &s->cond.precracks[c];
    double corner[4][3];
    int corners = 2;
    for (int d = 0; d < 3; ++d) {
      corner[0][d] = pc->a[d];
      if (pc->dim == 2) corner[1][d] = pc->b[d];
      else {
        corner[1][d] = pc->a[d] + pc->e1[d], corner[2][d] = pc->a[d] + pc->e1[d] + pc->e2[d];
        corner[3][d] = pc->a[d] + pc->e2[d];
        corners = 4;
      }
    }
    if (corners == 2) { /* a segment: its ends */
      for (int e = 0; e < 2; ++e) {
        if (!in_body(p, dim, dx, corner[e])) continue;
        for (int32_t i = 0; i < p->n_owned; ++i)
          if (segment_distance(&p->x[3 * (size_t)i], corner[e], corner[e]) <= limit) mark[i] = 1;
      }
      continue;
    }
    for (int e = 0; e < 4; ++e) { /* a rectangle: its edges */
      const double *P = corner[e], *Q = corner[(e + 1) % 4];
      const double length = segment_distance(P, Q, Q);
      const int samples = (int)ceil(length / (0.5 * dx)) + 1;
      double prev[3];
      bool prev_in = false;
      for (int k = 0; k < samples; ++k) {
        double at[3];
        const double t = samples > 1 ? (double)k / (samples - 1) : 0.0;
        for (int d = 0; d < 3; ++d) at[d] = P[d] + t * (Q[d] - P[d]);
        const bool in = in_body(p, dim, dx, at);
        if (in)
          for (int32_t i = 0; i < p->n_owned; ++i)
            if (segment_distance(&p->x[3 * (size_t)i], prev_in ? prev : at, at) <= limit) mark[i] = 1;
        memcpy(prev, at, sizeof prev);
        prev_in = in;
      }
    }
  }
}

int peri_coupling_set_switching(peri_sim *s, double radius, char *why, size_t n) {
  peri_coupling *c = s->coupling;
  const peri_bonds *b = &s->disc.bonds;
  c->switch_radius = radius;
  if (radius > 0.0) switch_offsets(c, s->disc.geom.dim, s->disc.geom.spacing, radius * s->disc.geom.horizon);
  /* the initial PD patch: the nodes that a pre-crack cut (elements cannot hold a crack), and
   * every node within r delta of a pre-crack's front in the body. Not r delta about every cut
   * node: an interface that meets a free face under stress along it is out of balance even
   * for a uniform strain (docs/coupling.md, "The causes, measured"), and the flanks of a notch
   * from a face would put such interfaces on that face beside the notch. */
  uint8_t *patch = peri_calloc((size_t)(c->n_nodes > 0 ? c->n_nodes : 1), 1);
  for (int32_t i = 0; i < c->n_nodes; ++i)
    for (int64_t k = b->offset[i]; k < b->offset[i + 1] && !patch[i]; ++k) patch[i] = b->broken[k] != 0;
  if (radius > 0.0) mark_fronts(s, radius * s->disc.geom.horizon, patch);
  int32_t switched = 0;
  for (int32_t i = 0; i < c->n_nodes && switched >= 0; ++i) {
    if (!patch[i] || c->node_type[i]) continue;
    if (c->fem_only && c->fem_only[i]) cannot_switch(&s->disc.p.x[3 * (size_t)i], i, why, n), switched = -1;
    else c->node_type[i] = 1, ++switched;
  }
  if (switched > 0) c->n_pd += switched;
  free(patch);
  return switched < 0 ? PERI_ERR_INPUT : PERI_OK;
}

long peri_coupling_break(peri_sim *s) {
  peri_coupling *c = s->coupling;
  const peri_particles *p = &s->disc.p;
  peri_bonds *b = &s->disc.bonds;
  const int dim = s->disc.geom.dim, nm = s->mat.n_materials;
  const int32_t *type = c->node_type;
  uint8_t *lost = peri_calloc((size_t)(c->n_nodes > 0 ? c->n_nodes : 1), 1);
  long broken = 0;
  /* The linearised stretch is the same double from both ends (xi and u_j - u_i change sign
   * exactly), so each node decides its own bonds and both directions of a bond break
   * together: no write outside node i's bonds, the same result on any number of threads. */
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : broken)
  for (int32_t i = 0; i < c->n_nodes; ++i) {
    if (p->flags[i] & PERI_NODE_NO_FAIL) continue;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      if (b->broken[k] || !(type[i] || type[j]) || (p->flags[j] & PERI_NODE_NO_FAIL)) continue;
      double xi[3], stretch = 0.0;
      const double L = peri_bond_xi(p->x, i, j, xi);
      for (int d = 0; d < dim; ++d) stretch += xi[d] * (p->u[3 * (size_t)j + d] - p->u[3 * (size_t)i + d]);
      stretch /= L * L;
      if (stretch >= s->mat.pair_s0[p->material[i] * nm + p->material[j]]) {
        b->broken[k] = 1;
        lost[i] = 1;
        ++broken;
      }
    }
  }
  if (broken) ++b->broken_edits;
  /* on MPI ranks the switching is collective: every rank takes it when a bond broke anywhere */
  if (s->par.dd ? peri_comm_sum_long(broken) > 0 : broken > 0) {
    /* the PD nodes that lost a bond (an FEM end lies within delta of its PD end, so it
     * switches with the rest) */
    for (int32_t i = 0; i < c->n_nodes; ++i) lost[i] = lost[i] && type[i];
    char why[512];
    if (c->switch_radius > 0.0 && switch_around(s, lost, why, sizeof why) < 0) {
      peri_error("coupling: %s", why);
      broken = -1;
    }
  }
  free(lost);
  peri_coupling_force(s);
  return broken;
}
