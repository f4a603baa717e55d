/* Named node sets defined by shapes. */
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

#endif
