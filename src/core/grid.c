/* Uniform-grid discretization: nodes at cell centres or lattice points inside the fill
 * shapes and outside the removed shapes. Each fill shape is scanned over its own bounding
 * box, so two small shapes far apart cost their own nodes, not the box around both. */
#include <math.h>
#include <stdlib.h>
#include "peri/discretize.h"
#include "peri/error.h"

/* A grid point by its integer lattice index, with the fill shape that owns it. */
typedef struct {
  int64_t k[3];
  int32_t owner, material;
} grid_point;

/* The order of a scan over one box: z slowest, then y, then x. Nodes are added in this
 * order whatever the shapes, as a scan over the box around all of them would add them. */
static int compare_scan_order(const void *a, const void *b) {
  const grid_point *p = a, *q = b;
  for (int d = 2; d >= 0; d--)
    if (p->k[d] != q->k[d]) return p->k[d] < q->k[d] ? -1 : 1;
  return 0;
}

/* The lattice origin: given, or (cell centres) the lower corner of the fill shapes'
 * bounds; false when a fill shape is unbounded (with a message when `report`). */
static bool grid_origin(const peri_grid_params *g, bool report, double origin[3]) {
  double lo[3] = {0, 0, 0};
  for (int s = 0; s < g->n_fill; s++) {
    double slo[3], shi[3];
    if (g->fill[s].detachment) continue; /* it makes no points of its own */
    if (!peri_shape_bounds(&g->fill[s].shape, g->dim, slo, shi)) {
      if (report)
        peri_error("grid: fill shape %d is unbounded (shape: all); a grid needs bounded shapes",
                   s + 1);
      return false;
    }
    for (int d = 0; d < g->dim; d++)
      if (s == 0 || slo[d] < lo[d]) lo[d] = slo[d];
  }
  for (int d = 0; d < 3; d++) {
    origin[d] = 0.0;
    if (d >= g->dim) continue;
    if (g->origin_given)
      origin[d] = g->origin[d];
    else if (g->placement == PERI_PLACE_CENTERS)
      origin[d] = lo[d];
  }
  return true;
}

/* The node spacing of fill shape s: its own (a graded grid), else the grid's. */
static double fill_spacing(const peri_grid_params *g, int s) {
  return g->fill[s].spacing > 0 ? g->fill[s].spacing : g->spacing;
}

bool peri_grid_is_graded(const peri_grid_params *g) {
  for (int s = 0; s < g->n_fill; s++)
    if (fill_spacing(g, s) != g->spacing) return true;
  return false;
}

double peri_grid_node_spacing(double volume, int dim, double thickness, double cross_section) {
  if (dim == 2) return sqrt(volume / thickness);
  if (dim == 1) return volume / cross_section;
  return cbrt(volume);
}

/* The lattice origin of fill shape s: that of the grid, or on a graded grid the lower
 * corner of the shape's own box, so that its cells tile it. */
static void shape_origin(const peri_grid_params *g, int s, const double grid[3], double origin[3]) {
  double slo[3], shi[3];
  peri_shape_bounds(&g->fill[s].shape, g->dim, slo, shi);
  const bool graded = peri_grid_is_graded(g);
  for (int d = 0; d < 3; d++) origin[d] = graded && d < g->dim ? slo[d] : grid[d];
}

/* Index range of fill shape s, one extra on each side: containment (with the tolerance)
 * decides, so rounding here cannot drop a boundary node. Returns the number of points. */
static double shape_range(const peri_grid_params *g, int s, const double grid_origin[3],
                          int64_t kmin[3], int64_t kmax[3]) {
  double slo[3], shi[3], origin[3];
  peri_shape_bounds(&g->fill[s].shape, g->dim, slo, shi);
  shape_origin(g, s, grid_origin, origin);
  const double dx = fill_spacing(g, s);
  double off = g->placement == PERI_PLACE_CENTERS ? 0.5 : 0.0;
  double total = 1;
  for (int d = 0; d < 3; d++) {
    kmin[d] = kmax[d] = 0;
    if (d >= g->dim) continue;
    double a = floor((slo[d] - origin[d]) / dx - off) - 1;
    double b = ceil((shi[d] - origin[d]) / dx - off) + 1;
    total *= b - a + 1;
    if (!isfinite(total) || total > 1e18) return INFINITY;
    kmin[d] = (int64_t)a;
    kmax[d] = (int64_t)b;
  }
  return total;
}

double peri_grid_points_bound(const peri_grid_params *g) {
  double origin[3];
  if (g->n_fill <= 0 || !(g->spacing > 0) || !grid_origin(g, false, origin)) return 0;
  double total = 0;
  for (int s = 0; s < g->n_fill; s++) {
    int64_t kmin[3], kmax[3];
    if (g->fill[s].detachment) continue;
    total += shape_range(g, s, origin, kmin, kmax);
  }
  return total;
}

/* The detachment defects, in deck order, on the points the fill shapes made (a uniform grid:
 * the deck refuses them on a graded one); the points that turn void are dropped. */
static int64_t apply_detachments(const peri_grid_params *g, const double grid[3], double off, grid_point *points,
                                 int64_t count) {
  for (int s = 0; s < g->n_fill; s++) {
    if (!g->fill[s].detachment || count == 0) continue;
    int64_t *k = peri_malloc((size_t)count * 3 * sizeof *k);
    int32_t *material = peri_malloc((size_t)count * sizeof *material);
    for (int64_t i = 0; i < count; i++) {
      for (int d = 0; d < 3; d++) k[3 * i + d] = points[i].k[d];
      material[i] = points[i].material;
    }
    peri_detach_points(g->fill[s].detachment, &g->fill[s].shape, g->dim, count, k, material, grid, g->spacing, off);
    int64_t kept = 0;
    for (int64_t i = 0; i < count; i++) {
      if (material[i] == PERI_PHASE_VOID) continue;
      points[kept] = points[i];
      points[kept++].material = material[i];
    }
    count = kept;
    free(k);
    free(material);
  }
  return count;
}

int64_t peri_grid_generate(peri_particles *p, const peri_grid_params *g) {
  int dim = g->dim;
  peri_particles_init(p, dim);
  if (dim < 1 || dim > 3) {
    peri_error("grid: dimension must be 1, 2 or 3, got %d", dim);
    return -1;
  }
  for (int s = -1; s < g->n_fill; s++) {
    const double dx = s < 0 ? g->spacing : fill_spacing(g, s);
    if (!(dx > 0) || !isfinite(dx)) {
      peri_error("grid: spacing must be a positive number, got %g", dx);
      return -1;
    }
  }
  if (g->n_fill <= 0) {
    peri_error("grid: no shape to fill");
    return -1;
  }
  double grid[3];
  if (!grid_origin(g, true, grid)) return -1;
  if (!(peri_grid_points_bound(g) <= 4.0 * INT32_MAX)) {
    peri_error("grid: spacing %g over the fill shapes' bounding boxes would exceed 2^31 nodes", g->spacing);
    return -1;
  }
  double off = g->placement == PERI_PLACE_CENTERS ? 0.5 : 0.0;
  /* a graded grid keeps its nodes zone by zone (the zones' lattice indices do not compare) */
  const bool graded = peri_grid_is_graded(g);

  /* Each shape keeps the points it owns: a point belongs to the last fill shape that
   * contains it, so a point also inside a later shape is left to that one. */
  grid_point *points = NULL;
  int64_t count = 0, capacity = 0;
  bool in_scan_order = true;
  double x[3] = {0, 0, 0};
  for (int s = 0; s < g->n_fill; s++) {
    int64_t kmin[3], kmax[3];
    double origin[3];
    if (g->fill[s].detachment) continue;
    shape_origin(g, s, grid, origin);
    const double dx = fill_spacing(g, s), tol = 1e-9 * dx;
    shape_range(g, s, grid, kmin, kmax);
    for (int64_t k2 = kmin[2]; k2 <= kmax[2]; k2++) {
      if (dim > 2) x[2] = origin[2] + ((double)k2 + off) * dx;
      for (int64_t k1 = kmin[1]; k1 <= kmax[1]; k1++) {
        if (dim > 1) x[1] = origin[1] + ((double)k1 + off) * dx;
        for (int64_t k0 = kmin[0]; k0 <= kmax[0]; k0++) {
          x[0] = origin[0] + ((double)k0 + off) * dx;
          if (!peri_shape_contains(&g->fill[s].shape, dim, x, tol)) continue;
          bool later = false;
          for (int t = s + 1; t < g->n_fill && !later; t++)
            later = !g->fill[t].detachment && peri_shape_contains(&g->fill[t].shape, dim, x, tol);
          if (later) continue;
          bool removed = false;
          for (int r = 0; r < g->n_remove && !removed; r++)
            removed = peri_shape_contains(&g->remove[r], dim, x, tol);
          if (removed) continue;
          /* an image gives each point the material of its pixel; a void pixel is a hole */
          const int32_t material = g->fill[s].phases ? peri_phase_map_at(g->fill[s].phases, x) : g->fill[s].material;
          if (material == PERI_PHASE_VOID) continue;
          if (count >= INT32_MAX) {
            peri_error("grid: more than 2^31 nodes; use a coarser spacing");
            free(points);
            return -1;
          }
          if (count == capacity) {
            capacity = capacity ? 2 * capacity : 1024;
            points = peri_realloc(points, (size_t)capacity * sizeof *points);
          }
          grid_point *point = &points[count];
          *point = (grid_point){{k0, k1, k2}, s, material};
          if (!graded && count > 0 && compare_scan_order(&points[count - 1], point) > 0) in_scan_order = false;
          count++;
        }
      }
    }
  }
  if (!in_scan_order) qsort(points, (size_t)count, sizeof *points, compare_scan_order);
  count = apply_detachments(g, grid, off, points, count);

  for (int64_t i = 0; i < count; i++) {
    int32_t owner = points[i].owner;
    const double dx = fill_spacing(g, owner);
    double origin[3];
    shape_origin(g, owner, grid, origin);
    double vol = pow(dx, dim);
    if (dim == 2 && g->thickness > 0) vol *= g->thickness;
    if (dim == 1 && g->cross_section > 0) vol *= g->cross_section;
    for (int d = 0; d < 3; d++)
      x[d] = d < dim ? origin[d] + ((double)points[i].k[d] + off) * dx : 0.0;
    peri_particles_add(p, x, vol, points[i].material, owner + 1);
  }
  free(points);
  return count;
}

/* The exact form of the coordinates o + (k + off) dx, |k| <= kmax_abs: o and dx/2 rounded to
 * multiples of a power of two q small enough that every coordinate is a multiple of q below
 * 2^52 q, so that each product and sum is exact. dx/2 is rounded down (no lattice distance
 * grows past the horizon), by less than q, about 2^-51 of the axis' extent; an axis whose
 * rounding exceeds 1e-12 of dx/2 (a grid far from its origin) gets none (half = 0). */
static peri_exact_axis exact_axis_of(double o, double dx, double off, int64_t kmax_abs) {
  peri_exact_axis a = {o, dx, off, o, 0.0};
  const double extent = fabs(o) + ((double)kmax_abs + 1.0 + off) * dx;
  if (!(extent > 0) || !isfinite(extent)) return a;
  const double q = ldexp(1.0, ilogb(extent) - 51);
  const double half = floor(0.5 * dx / q) * q;
  if (!(half > 0) || (0.5 * dx - half) > 1e-12 * 0.5 * dx) return a;
  a.origin = nearbyint(o / q) * q, a.half = half;
  return a;
}

double peri_exact_coordinate(const peri_exact_axis *a, double x) {
  if (a->half == 0.0) return x;
  const double t = (x - a->o) / a->dx - a->off, k = nearbyint(t);
  if (!(fabs(t - k) <= 1e-9)) return x; /* a node of the grid, not of another lattice near it */
  return a->origin + (2.0 * k + (a->off != 0.0 ? 1.0 : 0.0)) * a->half;
}

bool peri_grid_exact_axes(const peri_grid_params *g, const peri_particles *p, peri_exact_axis axis[3]) {
  double origin[3];
  if (peri_grid_is_graded(g) || !grid_origin(g, false, origin)) return false;
  const double off = g->placement == PERI_PLACE_CENTERS ? 0.5 : 0.0;
  for (int d = 0; d < 3; d++) {
    double kmax = 0.0;
    for (int32_t i = 0; d < g->dim && i < p->n; i++)
      kmax = fmax(kmax, fabs(nearbyint((p->x[3 * (size_t)i + d] - origin[d]) / g->spacing - off)));
    axis[d] = d < g->dim ? exact_axis_of(origin[d], g->spacing, off, (int64_t)kmax)
                         : (peri_exact_axis){0.0, g->spacing, 0.0, 0.0, 0.0};
  }
  return true;
}
