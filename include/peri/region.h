/* Named node sets: defined by shapes, or given as node lists (mesh sets, node set files,
 * blocks, materials) and their unions, intersections and differences. */
#ifndef PERI_REGION_H
#define PERI_REGION_H
#include "peri/particles.h"
#include "peri/shape.h"

typedef struct peri_region {
  char *name;
  peri_shape shape;
  int32_t count;
  int32_t *nodes; /* ascending owned node indices */
} peri_region;

/* Collects the owned nodes inside the shape (tolerance tol). */
void peri_region_collect(peri_region *r, const peri_particles *p, double tol);
void peri_region_free(peri_region *r);

/* Region booleans on ascending node lists: out receives a | b, a & b or a - b (ascending,
 * without repeats; room for na + nb entries) and the function returns its count. */
typedef enum { PERI_REGION_UNION, PERI_REGION_INTERSECTION, PERI_REGION_DIFFERENCE } peri_region_op;
int32_t peri_region_combine(peri_region_op op, const int32_t *a, int32_t na, const int32_t *b, int32_t nb,
                            int32_t *out);
/* Sets the region's nodes to a copy of an ascending list (a region given by nodes, not a shape). */
void peri_region_set_nodes(peri_region *r, const int32_t *nodes, int32_t count);

#endif
