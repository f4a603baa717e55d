/* Phase lookup of an image placed in the plane (include/peri/phase_map.h). */
#include <math.h>
#include <stdlib.h>
#include "peri/phase_map.h"

int32_t peri_phase_map_at(const peri_phase_map *m, const double x[3]) {
  /* a grid point on a pixel edge belongs to the pixel above and to the right of it; points
   * within the tolerance outside the image belong to its edge pixels */
  long col = (long)floor((x[0] - m->origin[0]) / m->pixel_size);
  long row_from_bottom = (long)floor((x[1] - m->origin[1]) / m->pixel_size);
  if (col < 0) col = 0;
  if (col >= m->width) col = m->width - 1;
  if (row_from_bottom < 0) row_from_bottom = 0;
  if (row_from_bottom >= m->height) row_from_bottom = m->height - 1;
  const long row = m->height - 1 - row_from_bottom;
  return m->phase[(size_t)row * (size_t)m->width + (size_t)col];
}

void peri_phase_map_free(peri_phase_map *m) {
  if (!m) return;
  free(m->phase);
  m->phase = NULL;
}
