/* The per-body sums of history.csv (include/peri/bodies.h, docs/contact.md "Bodies"). Every
 * body's sums run in the fixed blocks of the global node order (peri_sum_blocks), all bodies
 * in one pass over the nodes and one exchange, so they do not depend on the thread or rank
 * count; the penetration front is a largest value, taken over the ranks. */
#include <math.h>
#include <stdlib.h>
#include "peri/bodies.h"
#include "peri/comm.h"
#include "peri/damage_index.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/sim.h"

/* the sums of a body: mass, momentum (3), kinetic energy, damaged mass, detached mass */
enum { BODY_SUMS = 7 };

void peri_body_sums_now(const peri_sim *s, peri_body_sums *out) {
  const peri_bodies *bodies = s->bodies;
  const peri_particles *p = &s->disc.p;
  const int count = bodies->count, ncomp = BODY_SUMS * count;
  const int32_t n = p->n_owned;
  double *phi = peri_malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
  peri_damage_index(s, phi);
  /* every body's sums over each fixed block of nodes, in node order, in one pass */
  const int64_t n_blocks = peri_sum_blocks_owned(s);
  double *block = peri_calloc((size_t)(n_blocks > 0 ? n_blocks : 1) * (size_t)ncomp, sizeof(double));
#pragma omp parallel for schedule(static)
  for (int64_t k = 0; k < n_blocks; ++k) {
    const int32_t i1 = (int32_t)((k + 1) * PERI_SUM_BLOCK < n ? (k + 1) * PERI_SUM_BLOCK : n);
    for (int32_t i = (int32_t)(k * PERI_SUM_BLOCK); i < i1; ++i) {
      const int32_t b = bodies->label[i];
      if (b == PERI_NO_BODY) continue;
      double *t = &block[(size_t)k * (size_t)ncomp + (size_t)(BODY_SUMS * b)];
      const double m = s->mat.materials[p->material[i]].density * p->volume[i];
      const double *v = &p->v[3 * (size_t)i];
      t[0] += m;
      for (int d = 0; d < 3; ++d) t[1 + d] += m * v[d];
      t[4] += 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      if (phi[i] > 0.0) t[5] += m;
      if (phi[i] >= 1.0) t[6] += m; /* every bond broken: the node has left its body */
    }
  }
  double *sum = peri_malloc(sizeof(double) * (size_t)ncomp);
  peri_sum_blocks(s, block, ncomp, sum);
  free(block);
  for (int b = 0; b < count; ++b) {
    const double *t = &sum[BODY_SUMS * b];
    peri_body_sums *o = &out[b];
    o->mass = t[0];
    for (int d = 0; d < 3; ++d) o->momentum[d] = t[1 + d];
    o->kinetic_energy = t[4];
    o->damaged_mass = t[5];
    o->detached_mass = t[6];
    o->penetration = NAN; /* (not asked) */
    const peri_penetration *pen = &bodies->penetration[b];
    if (!pen->on) continue;
    /* the front of the body's attached nodes, and of all its nodes for a body turned to debris
     * (debris ahead of the body is not the body's front while it has one) */
    double front = -INFINITY, debris_front = -INFINITY;
    for (int32_t i = 0; i < n; ++i) {
      if (bodies->label[i] != b) continue;
      double along = 0.0;
      for (int d = 0; d < 3; ++d) along += (p->x[3 * (size_t)i + d] + p->u[3 * (size_t)i + d]) * pen->direction[d];
      if (phi[i] < 1.0) front = fmax(front, along - pen->face);
      debris_front = fmax(debris_front, along - pen->face);
    }
    if (s->par.dd) front = peri_comm_max(front), debris_front = peri_comm_max(debris_front);
    o->penetration = front > -INFINITY ? front : debris_front; /* every node detached: the debris' front */
  }
  free(sum);
  free(phi);
}

void peri_bodies_localize(peri_sim *s) {
  const peri_decomposition *d = s->par.dd;
  if (!s->bodies || !d) return;
  /* the owned nodes' and the ghosts' labels, from the global ones every rank built */
  const int32_t n = s->disc.p.n;
  int32_t *label = peri_malloc(sizeof(int32_t) * (size_t)(n > 0 ? n : 1));
  for (int32_t i = 0; i < n; ++i) label[i] = s->bodies->label[d->global_id[i]];
  free(s->bodies->label);
  s->bodies->label = label;
}

void peri_bodies_free(peri_bodies *b) {
  if (!b) return;
  free(b->region);
  free(b->label);
  free(b->penetration);
  free(b);
}
