/* Centroid and measure (length, area or volume) of a finite element from its corner nodes,
 * for the mesh readers of src/io/ (element_geometry.c). */
#ifndef PERI_IO_ELEMENT_GEOMETRY_H
#define PERI_IO_ELEMENT_GEOMETRY_H

typedef enum {
  PERI_ELEMENT_LINE,    /* 2 corners */
  PERI_ELEMENT_TRI,     /* 3 */
  PERI_ELEMENT_QUAD,    /* 4, counter-clockwise or clockwise */
  PERI_ELEMENT_TET,     /* 4 */
  PERI_ELEMENT_PYRAMID, /* 5: base 0-3, apex 4 */
  PERI_ELEMENT_WEDGE,   /* 6: triangles 0-2 and 3-5 */
  PERI_ELEMENT_HEX,     /* 8: face 0-3, opposite face 4-7 */
} peri_element_shape;

/* The element's dimension (1, 2 or 3) and its number of corner nodes. */
int peri_element_dim(peri_element_shape shape);
int peri_element_corners(peri_element_shape shape);

/* The exact measure and centroid of the element with straight edges (bilinear and trilinear
 * faces for quadrilaterals and hexahedra) through its corners xyz[3 * corner]. */
void peri_element_measure(peri_element_shape shape, const double *xyz, double *measure, double centroid[3]);

#endif
