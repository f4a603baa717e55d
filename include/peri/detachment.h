/* A detachment defect (Le 2014 section 3.4.9, its defect (f)): the nodes of one phase that lie
 * along its boundary with another phase, within a thickness of it and inside a region, turn
 * into a void (removed) or another material (docs/microstructures.md section 3). */
#ifndef PERI_DETACHMENT_H
#define PERI_DETACHMENT_H
#include <stdint.h>
#include "peri/shape.h"

typedef struct peri_detachment {
  int32_t phase;      /* the material whose nodes detach */
  int32_t along;      /* the material across the boundary */
  double thickness;   /* a node of `phase` detaches when a node of `along` is this close (m) */
  int32_t material;   /* what the detached nodes become: a material or PERI_PHASE_VOID */
} peri_detachment;

/* Applies d to `count` points of a uniform lattice of spacing dx: point i at lattice index
 * k[3i..3i+2] (position origin + (k + off) dx on the first `dim` axes) with material[i].
 * A point of d->phase inside `within` with a point of d->along at most d->thickness away takes
 * d->material; the neighbours are judged on the materials before the call, so the defect does
 * not grow through its own nodes. Returns how many points changed. */
int64_t peri_detach_points(const peri_detachment *d, const peri_shape *within, int dim, int64_t count,
                           const int64_t *k, int32_t *material, const double origin[3], double dx, double off);

#endif
