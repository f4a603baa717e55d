/* The per-body sums of history.csv (include/peri/bodies.h, docs/contact.md "Bodies"). Bodies
 * run in one process (deck check), so each body's nodes are summed in node order, one pass
 * over the nodes: the sums do not depend on the thread count. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/bodies.h"
#include "peri/damage_index.h"
#include "peri/error.h"
#include "peri/sim.h"

void peri_body_sums_now(const peri_sim *s, peri_body_sums *out) {
  const peri_bodies *bodies = s->bodies;
  const peri_particles *p = &s->disc.p;
  memset(out, 0, sizeof *out * (size_t)bodies->count);
  /* the front of each body's attached nodes, and of all its nodes for a body turned to debris */
  double *debris_front = peri_malloc(sizeof(double) * (size_t)bodies->count);
  for (int b = 0; b < bodies->count; ++b) out[b].penetration = debris_front[b] = -INFINITY;
  const int32_t n = p->n_owned;
  double *phi = peri_malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
  peri_damage_index(s, phi);
  for (int32_t i = 0; i < n; ++i) {
    const int32_t b = bodies->label[i];
    if (b == PERI_NO_BODY) continue;
    peri_body_sums *o = &out[b];
    const double m = s->mat.materials[p->material[i]].density * p->volume[i];
    const double *v = &p->v[3 * (size_t)i];
    o->mass += m;
    for (int d = 0; d < 3; ++d) o->momentum[d] += m * v[d];
    o->kinetic_energy += 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (phi[i] > 0.0) o->damaged_mass += m;
    if (phi[i] >= 1.0) o->detached_mass += m; /* every bond broken: the node has left its body */
    const peri_penetration *pen = &bodies->penetration[b];
    if (pen->on) { /* debris ahead of the body is not the body's front while it has one */
      double along = 0.0;
      for (int d = 0; d < 3; ++d) along += (p->x[3 * (size_t)i + d] + p->u[3 * (size_t)i + d]) * pen->direction[d];
      if (phi[i] < 1.0) o->penetration = fmax(o->penetration, along - pen->face);
      debris_front[b] = fmax(debris_front[b], along - pen->face);
    }
  }
  free(phi);
  for (int b = 0; b < bodies->count; ++b)
    if (out[b].penetration == -INFINITY) /* every node detached: the debris' front; not asked: NaN */
      out[b].penetration = bodies->penetration[b].on ? debris_front[b] : NAN;
  free(debris_front);
}

void peri_bodies_free(peri_bodies *b) {
  if (!b) return;
  free(b->region);
  free(b->label);
  free(b->penetration);
  free(b);
}
