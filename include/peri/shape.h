/* Geometric shapes used to fill the domain, remove material and define regions. */
#ifndef PERI_SHAPE_H
#define PERI_SHAPE_H
#include <stdbool.h>

typedef enum {
  PERI_SHAPE_BOX,      /* min[3], max[3]: box (3D), rectangle (2D), interval (1D) */
  PERI_SHAPE_SPHERE,   /* center[3], radius: sphere (3D), disk/circle (2D) */
  PERI_SHAPE_CYLINDER, /* center[3] (of the base), axis (0,1,2), radius, inner_radius,
                          length along the axis from center; top_radius at the far end
                          (a truncated cone when it differs from radius) */
  PERI_SHAPE_POLYGON,  /* 2D: vertices (x,y) */
  PERI_SHAPE_ALL,      /* every point */
} peri_shape_kind;

typedef struct peri_shape {
  peri_shape_kind kind;
  double min[3], max[3];
  double center[3];
  double radius, inner_radius, length;
  double top_radius; /* cylinder: outer radius at center + length (= radius when not given) */
  int axis;
  int n_vertices;
  double *vertices; /* [2*n_vertices] */
} peri_shape;

/* Whether point x (3 components) lies inside (boundary inclusive, tolerance tol). */
bool peri_shape_contains(const peri_shape *s, int dim, const double x[3], double tol);
/* Axis-aligned bounding box; false for PERI_SHAPE_ALL. */
bool peri_shape_bounds(const peri_shape *s, int dim, double lo[3], double hi[3]);
void peri_shape_free(peri_shape *s);

#endif
