/* A picture of phases: one material (or a void) per pixel of a rectangular image placed in
 * the plane, read from an image file by the deck (docs/microstructures.md). */
#ifndef PERI_PHASE_MAP_H
#define PERI_PHASE_MAP_H
#include <stdint.h>

enum { PERI_PHASE_VOID = -1 }; /* a pixel without material: its grid points get no node */

typedef struct peri_phase_map {
  int width, height;  /* pixels */
  double pixel_size;  /* side of a square pixel (m) */
  double origin[2];   /* lower-left corner of the image in the plane (m) */
  int32_t *phase;     /* [width * height], row 0 the top row of the image: a material or PERI_PHASE_VOID */
} peri_phase_map;

/* The phase of the pixel that contains point x (x, y), the edges of the image counted in
 * the pixel next to them. The point must lie in the image's rectangle (with a tolerance). */
int32_t peri_phase_map_at(const peri_phase_map *m, const double x[3]);
void peri_phase_map_free(peri_phase_map *m);

#endif
