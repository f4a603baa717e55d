/* Uniform-grid discretization: nodes at cell centres or lattice points inside the fill
 * shapes and outside the removed shapes. */
#include <math.h>
#include "peri/discretize.h"
#include "peri/error.h"

int64_t peri_grid_generate(peri_particles *p, const peri_grid_params *g) {
  int dim = g->dim;
  peri_particles_init(p, dim);
  if (dim < 1 || dim > 3) {
    peri_error("grid: dimension must be 1, 2 or 3, got %d", dim);
    return -1;
  }
  double dx = g->spacing;
  if (!(dx > 0) || !isfinite(dx)) {
    peri_error("grid: spacing must be a positive number, got %g", dx);
    return -1;
  }
  if (g->n_fill <= 0) {
    peri_error("grid: no shape to fill");
    return -1;
  }
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  for (int s = 0; s < g->n_fill; s++) {
    double slo[3], shi[3];
    if (!peri_shape_bounds(&g->fill[s].shape, dim, slo, shi)) {
      peri_error("grid: fill shape %d is unbounded (shape: all); a grid needs bounded shapes",
                 s + 1);
      return -1;
    }
    for (int d = 0; d < dim; d++) {
      if (s == 0 || slo[d] < lo[d]) lo[d] = slo[d];
      if (s == 0 || shi[d] > hi[d]) hi[d] = shi[d];
    }
  }
  double origin[3] = {0, 0, 0};
  double off = g->placement == PERI_PLACE_CENTERS ? 0.5 : 0.0;
  for (int d = 0; d < dim; d++) {
    if (g->origin_given)
      origin[d] = g->origin[d];
    else if (g->placement == PERI_PLACE_CENTERS)
      origin[d] = lo[d];
  }
  /* Index range covering the bounds, one extra on each side; containment (with the
   * tolerance) decides, so rounding here cannot drop a boundary node. */
  double tol = 1e-9 * dx;
  int64_t kmin[3] = {0, 0, 0}, kmax[3] = {0, 0, 0};
  double total = 1;
  for (int d = 0; d < dim; d++) {
    double a = floor((lo[d] - origin[d]) / dx - off) - 1;
    double b = ceil((hi[d] - origin[d]) / dx - off) + 1;
    total *= b - a + 1;
    if (!isfinite(total) || total > 4.0 * INT32_MAX) {
      peri_error("grid: spacing %g over the fill shapes' bounding box would exceed 2^31 nodes", dx);
      return -1;
    }
    kmin[d] = (int64_t)a;
    kmax[d] = (int64_t)b;
  }
  double vol = pow(dx, dim);
  if (dim == 2 && g->thickness > 0) vol *= g->thickness;
  if (dim == 1 && g->cross_section > 0) vol *= g->cross_section;

  int64_t count = 0;
  double x[3] = {0, 0, 0};
  for (int64_t k2 = kmin[2]; k2 <= kmax[2]; k2++) {
    if (dim > 2) x[2] = origin[2] + ((double)k2 + off) * dx;
    for (int64_t k1 = kmin[1]; k1 <= kmax[1]; k1++) {
      if (dim > 1) x[1] = origin[1] + ((double)k1 + off) * dx;
      for (int64_t k0 = kmin[0]; k0 <= kmax[0]; k0++) {
        x[0] = origin[0] + ((double)k0 + off) * dx;
        int owner = -1;
        for (int s = g->n_fill - 1; s >= 0 && owner < 0; s--)
          if (peri_shape_contains(&g->fill[s].shape, dim, x, tol)) owner = s;
        if (owner < 0) continue;
        bool removed = false;
        for (int r = 0; r < g->n_remove && !removed; r++)
          removed = peri_shape_contains(&g->remove[r], dim, x, tol);
        if (removed) continue;
        if (count >= INT32_MAX) {
          peri_error("grid: more than 2^31 nodes; use a coarser spacing");
          peri_particles_free(p);
          return -1;
        }
        peri_particles_add(p, x, vol, g->fill[owner].material, owner + 1);
        count++;
      }
    }
  }
  return count;
}
