/* Detachment defects on a uniform lattice (include/peri/detachment.h). The points are looked
 * up by lattice index in a dense table over their bounding index box, so the search for a
 * neighbour across the boundary costs (2r + 1)^dim lookups a point, r = thickness / dx. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/detachment.h"
#include "peri/error.h"

int64_t peri_detach_points(const peri_detachment *d, const peri_shape *within, int dim, int64_t count,
                           const int64_t *k, int32_t *material, const double origin[3], double dx, double off) {
  if (count <= 0) return 0;
  int64_t lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  for (int a = 0; a < dim; a++) lo[a] = hi[a] = k[a];
  for (int64_t i = 1; i < count; i++)
    for (int a = 0; a < dim; a++) {
      if (k[3 * i + a] < lo[a]) lo[a] = k[3 * i + a];
      if (k[3 * i + a] > hi[a]) hi[a] = k[3 * i + a];
    }
  int64_t extent[3] = {1, 1, 1};
  size_t cells = 1;
  for (int a = 0; a < dim; a++) {
    extent[a] = hi[a] - lo[a] + 1;
    cells *= (size_t)extent[a];
  }
  int64_t *at = peri_malloc(cells * sizeof *at);
  for (size_t c = 0; c < cells; c++) at[c] = -1;
  for (int64_t i = 0; i < count; i++) {
    size_t c = 0;
    for (int a = dim - 1; a >= 0; a--) c = c * (size_t)extent[a] + (size_t)(k[3 * i + a] - lo[a]);
    at[c] = i;
  }
  const double reach = d->thickness * (1.0 + 1e-9);
  const int64_t r = (int64_t)floor(reach / dx);
  const double tol = 1e-9 * dx;
  int32_t *before = peri_malloc((size_t)count * sizeof *before);
  memcpy(before, material, (size_t)count * sizeof *before);
  int64_t changed = 0;
  for (int64_t i = 0; i < count; i++) {
    if (before[i] != d->phase) continue;
    double x[3] = {0, 0, 0};
    for (int a = 0; a < dim; a++) x[a] = origin[a] + ((double)k[3 * i + a] + off) * dx;
    if (!peri_shape_contains(within, dim, x, tol)) continue;
    bool found = false;
    const int64_t r1 = dim > 1 ? r : 0, r2 = dim > 2 ? r : 0;
    for (int64_t o2 = -r2; o2 <= r2 && !found; o2++)
      for (int64_t o1 = -r1; o1 <= r1 && !found; o1++)
        for (int64_t o0 = -r; o0 <= r && !found; o0++) {
          const int64_t o[3] = {o0, o1, o2};
          if (dx * sqrt((double)(o0 * o0 + o1 * o1 + o2 * o2)) > reach) continue;
          size_t c = 0;
          bool inside = true;
          for (int a = dim - 1; a >= 0 && inside; a--) {
            const int64_t q = k[3 * i + a] + o[a] - lo[a];
            inside = q >= 0 && q < extent[a];
            c = c * (size_t)extent[a] + (size_t)q;
          }
          found = inside && at[c] >= 0 && before[at[c]] == d->along;
        }
    if (found) {
      material[i] = d->material;
      changed++;
    }
  }
  free(before);
  free(at);
  return changed;
}
