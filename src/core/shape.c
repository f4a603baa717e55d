/* Geometric shapes: point containment and bounds. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/shape.h"
#include "peri/error.h"

static double segment_distance(const double *p, const double *a, const double *b) {
  double ex = b[0] - a[0], ey = b[1] - a[1];
  double px = p[0] - a[0], py = p[1] - a[1];
  double l2 = ex * ex + ey * ey;
  double t = l2 > 0 ? (px * ex + py * ey) / l2 : 0.0;
  if (t < 0) t = 0;
  if (t > 1) t = 1;
  double dx = px - t * ex, dy = py - t * ey;
  return sqrt(dx * dx + dy * dy);
}

static bool polygon_contains(const peri_shape *s, const double x[3], double tol) {
  int n = s->n_vertices;
  const double *v = s->vertices;
  bool inside = false;
  for (int i = 0, j = n - 1; i < n; j = i++) {
    const double *a = v + 2 * i, *b = v + 2 * j;
    /* Points on (or within tol of) an edge are inside, whatever the ray test says. */
    if (segment_distance(x, a, b) <= tol) return true;
    if ((a[1] > x[1]) != (b[1] > x[1])) {
      double xc = a[0] + (x[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
      if (x[0] < xc) inside = !inside;
    }
  }
  return inside;
}

bool peri_shape_contains(const peri_shape *s, int dim, const double x[3], double tol) {
  switch (s->kind) {
  case PERI_SHAPE_BOX:
    for (int d = 0; d < dim; d++)
      if (x[d] < s->min[d] - tol || x[d] > s->max[d] + tol) return false;
    return true;
  case PERI_SHAPE_SPHERE: {
    double r2 = 0;
    for (int d = 0; d < dim; d++) r2 += (x[d] - s->center[d]) * (x[d] - s->center[d]);
    double r = s->radius + tol;
    return r2 <= r * r;
  }
  case PERI_SHAPE_CYLINDER: {
    int a = s->axis;
    double t = x[a] - s->center[a];
    if (t < -tol || t > s->length + tol) return false;
    double r2 = 0;
    for (int d = 0; d < 3; d++)
      if (d != a) r2 += (x[d] - s->center[d]) * (x[d] - s->center[d]);
    /* The outer radius varies linearly from radius at the base to top_radius at the far
     * end: a cylinder when they are equal, a truncated cone otherwise. */
    double along = t < 0 ? 0 : (t > s->length ? s->length : t);
    double ro = s->radius + (s->top_radius - s->radius) * (along / s->length) + tol;
    if (r2 > ro * ro) return false;
    if (s->inner_radius > 0) {
      double ri = s->inner_radius - tol;
      if (ri > 0 && r2 < ri * ri) return false;
    }
    return true;
  }
  case PERI_SHAPE_POLYGON: return polygon_contains(s, x, tol);
  case PERI_SHAPE_ALL: return true;
  }
  return false;
}

bool peri_shape_bounds(const peri_shape *s, int dim, double lo[3], double hi[3]) {
  for (int d = 0; d < 3; d++) lo[d] = hi[d] = 0.0;
  switch (s->kind) {
  case PERI_SHAPE_BOX:
    for (int d = 0; d < dim; d++) {
      lo[d] = s->min[d];
      hi[d] = s->max[d];
    }
    return true;
  case PERI_SHAPE_SPHERE:
    for (int d = 0; d < dim; d++) {
      lo[d] = s->center[d] - s->radius;
      hi[d] = s->center[d] + s->radius;
    }
    return true;
  case PERI_SHAPE_CYLINDER:
    for (int d = 0; d < 3; d++) {
      if (d == s->axis) {
        lo[d] = s->center[d];
        hi[d] = s->center[d] + s->length;
      } else {
        double r = fmax(s->radius, s->top_radius);
        lo[d] = s->center[d] - r;
        hi[d] = s->center[d] + r;
      }
    }
    return true;
  case PERI_SHAPE_POLYGON:
    if (s->n_vertices <= 0) return false;
    lo[0] = hi[0] = s->vertices[0];
    lo[1] = hi[1] = s->vertices[1];
    for (int i = 1; i < s->n_vertices; i++)
      for (int d = 0; d < 2; d++) {
        double c = s->vertices[2 * i + d];
        if (c < lo[d]) lo[d] = c;
        if (c > hi[d]) hi[d] = c;
      }
    return true;
  case PERI_SHAPE_ALL:
    for (int d = 0; d < dim; d++) {
      lo[d] = -HUGE_VAL;
      hi[d] = HUGE_VAL;
    }
    return false;
  }
  return false;
}

void peri_shape_free(peri_shape *s) {
  free(s->vertices);
  s->vertices = NULL;
  s->n_vertices = 0;
}
