/* The per-body sums of history.csv (include/peri/bodies.h, docs/contact.md "Bodies"). Each
 * body's sums run in the fixed blocks of the global node order (peri_sum_owned), so they do
 * not depend on the thread or rank count; the penetration front is a largest value, taken
 * over the ranks. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
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
  memset(out, 0, sizeof *out * (size_t)bodies->count);
  const int32_t n = p->n_owned;
  double *phi = peri_malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
  peri_damage_index(s, phi);
  double *terms = peri_malloc(sizeof(double) * BODY_SUMS * (size_t)(n > 0 ? n : 1));
  for (int b = 0; b < bodies->count; ++b) {
    const peri_penetration *pen = &bodies->penetration[b];
#pragma omp parallel for schedule(static)
    for (int32_t i = 0; i < n; ++i) {
      double *t = &terms[BODY_SUMS * (size_t)i];
      if (bodies->label[i] != b) {
        for (int c = 0; c < BODY_SUMS; ++c) t[c] = 0.0;
        continue;
      }
      const double m = s->mat.materials[p->material[i]].density * p->volume[i];
      const double *v = &p->v[3 * (size_t)i];
      t[0] = m;
      for (int d = 0; d < 3; ++d) t[1 + d] = m * v[d];
      t[4] = 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      t[5] = phi[i] > 0.0 ? m : 0.0;
      t[6] = phi[i] >= 1.0 ? m : 0.0; /* every bond broken: the node has left its body */
    }
    /* the front of the body's attached nodes, and of all its nodes for a body turned to debris
     * (debris ahead of the body is not the body's front while it has one) */
    double front = -INFINITY, debris_front = -INFINITY;
    for (int32_t i = 0; pen->on && i < n; ++i) {
      if (bodies->label[i] != b) continue;
      double along = 0.0;
      for (int d = 0; d < 3; ++d) along += (p->x[3 * (size_t)i + d] + p->u[3 * (size_t)i + d]) * pen->direction[d];
      if (phi[i] < 1.0) front = fmax(front, along - pen->face);
      debris_front = fmax(debris_front, along - pen->face);
    }
    double sum[BODY_SUMS];
    peri_sum_owned(s, terms, BODY_SUMS, sum);
    peri_body_sums *o = &out[b];
    o->mass = sum[0];
    for (int d = 0; d < 3; ++d) o->momentum[d] = sum[1 + d];
    o->kinetic_energy = sum[4];
    o->damaged_mass = sum[5];
    o->detached_mass = sum[6];
    o->penetration = NAN; /* (not asked) */
    if (pen->on) {
      if (s->par.dd) front = peri_comm_max(front), debris_front = peri_comm_max(debris_front);
      o->penetration = front > -INFINITY ? front : debris_front; /* every node detached: the debris' front */
    }
  }
  free(terms);
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
