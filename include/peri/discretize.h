/* Discretization: nodes on a uniform grid filling shapes minus removed shapes, or read
 * from a node file; ordering along a space-filling curve. */
#ifndef PERI_DISCRETIZE_H
#define PERI_DISCRETIZE_H
#include "peri/detachment.h"
#include "peri/particles.h"
#include "peri/phase_map.h"
#include "peri/shape.h"

typedef enum {
  PERI_PLACE_CENTERS = 0, /* cell centres: origin + (k + 1/2) dx; origin defaults to the
                             lower corner of the union of the fill shapes' bounds */
  PERI_PLACE_LATTICE = 1, /* lattice points origin + k dx (LAMMPS `lattice sc`) */
} peri_placement;

typedef struct peri_fill {
  peri_shape shape;
  int32_t material;
  peri_phase_map *phases;       /* an image: the material of each pixel (shape is its rectangle);
                                   a void pixel's points get no node; NULL otherwise */
  double spacing;          /* > 0: this zone's own node spacing (a graded grid), else the grid's */
  peri_detachment *detachment; /* a defect along a phase boundary, applied after every other fill
                                  shape (shape is the region it is limited to); NULL otherwise */
} peri_fill;

typedef struct peri_grid_params {
  int dim;
  double spacing;          /* dx */
  peri_placement placement;
  double origin[3];
  bool origin_given;       /* else derived as above (lattice: 0,0,0) */
  double thickness;        /* 2D: node volume dx^2 * thickness */
  double cross_section;    /* 1D: node volume dx * cross_section */
  int n_fill;
  peri_fill *fill;         /* a point takes the material of the last fill shape containing it */
  int n_remove;
  peri_shape *remove;      /* holes, notches: points inside any are removed */
} peri_grid_params;

/* Generates the nodes (boundary inclusive with a tolerance of 1e-9 dx, both for fill and
 * remove), scanning each fill shape's own bounding box, in the order of a scan over the
 * box around all of them (z slowest, x fastest). Node volume = dx^dim (x thickness in
 * 2D, x cross_section in 1D); block = index of the fill shape + 1. Returns the number of nodes, or -1 with a message when a fill
 * shape is unbounded (PERI_SHAPE_ALL) or the grid would exceed 2^31 nodes. */
int64_t peri_grid_generate(peri_particles *p, const peri_grid_params *g);

/* One axis of a uniform grid, x_k = o + (k + off) dx, and the same coordinates exactly:
 * origin + (2k + 2 off) half with origin and half = dx/2 rounded to multiples of one power
 * of two q (src/core/grid.c, peri_exact_coordinate); half = 0: no exact form. */
typedef struct peri_exact_axis {
  double o, dx, off, origin, half;
} peri_exact_axis;

/* The exact axes (peri_exact_axis) of a uniform grid g whose nodes are p; false for a graded
 * grid. */
bool peri_grid_exact_axes(const peri_grid_params *g, const peri_particles *p, peri_exact_axis axis[3]);

/* x at exact lattice coordinates: on axis a the coordinate o + (k + off) dx nearest x, as
 * origin + (2k + 2 off) half, exact in floating point, so that x_{k+n} - x_k is one number for
 * every k; x itself when it is off the axis by more than 1e-9 dx or the axis has no exact
 * form. */
double peri_exact_coordinate(const peri_exact_axis *a, double x);

/* An upper bound of the nodes the grid can have, before generating it: the grid points
 * in the bounding boxes of the fill shapes, each with one or two spacings of margin (0
 * when a fill shape is unbounded). Cheap: no point is tested. */
double peri_grid_points_bound(const peri_grid_params *g);

/* A graded grid: a fill shape has its own spacing (peri_fill.spacing). Each shape is then
 * a zone whose lattice starts at its own lower corner, so disjoint boxes whose sides are
 * whole multiples of their spacing are tiled exactly (docs/variable_horizon.md). */
bool peri_grid_is_graded(const peri_grid_params *g);
/* The edge of the square, cube or interval of a node's volume: its spacing on a grid. */
double peri_grid_node_spacing(double volume, int dim, double thickness, double cross_section);

/* Permutation that orders nodes in rows along the axis with the longest rows (rows one
 * `spacing` wide), the rows along a Morton (Z-order) curve of the other two axes; ties
 * broken by index (deterministic). perm has n entries. */
void peri_sfc_order(const peri_particles *p, double spacing, int32_t *perm);

#endif
