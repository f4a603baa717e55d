/* A graded structured FEM mesh on the node lattice (docs/coupling.md, "Graded meshes";
 * include/peri/fem_mesh.h): a balanced quadtree of square cells. The lattice's own cells
 * (level 0) fill the fine zone, where the nodes coincide with the PD grid, so that FEM nodes
 * there can switch to PD; away from it the cells double in size every `layers` elements. A
 * coarse cell that has a node in the middle of a side (a finer neighbour: the quadtree is
 * balanced, so only the middle) is split about its centre, into two quadrilaterals and a
 * triangle (one such side) or a triangle per boundary segment (more), which keeps the mesh
 * conforming without constraints: every element is a Q4 or a constant-strain triangle and a
 * linear field is reproduced exactly (the patch test). */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/fem_mesh.h"
#include "lattice_mesh.h"

enum { ABSENT = 0, FINE = 1, COARSE = 2, REMOVED = 3 };

void peri_fem_mesh_free(peri_fem_mesh *m) {
  if (!m) return;
  free(m->offset);
  free(m->nodes);
  free(m->coarse);
  free(m->fem_only);
  free(m->file);
  free(m->element_tag);
  free(m->node_tag);
  free(m->fem_only_tag);
  memset(m, 0, sizeof *m);
}

void peri_fem_mesh_permute(peri_fem_mesh *m, const int32_t *perm) {
  if (!m->nodes) return;
  int32_t *new_of_old = peri_malloc(sizeof(int32_t) * (size_t)m->n_nodes);
  uint8_t *only = peri_malloc((size_t)m->n_nodes);
  for (int32_t k = 0; k < m->n_nodes; ++k) new_of_old[perm[k]] = k, only[k] = m->fem_only[perm[k]];
  for (int64_t q = 0; q < m->offset[m->n_elements]; ++q) m->nodes[q] = new_of_old[m->nodes[q]];
  int64_t *tags[2] = {m->node_tag, m->fem_only_tag}; /* a mesh from a file */
  for (int t = 0; t < 2; ++t) {
    if (!tags[t]) continue;
    int64_t *moved = peri_malloc(sizeof(int64_t) * (size_t)m->n_nodes);
    for (int32_t k = 0; k < m->n_nodes; ++k) moved[k] = tags[t][perm[k]];
    memcpy(tags[t], moved, sizeof(int64_t) * (size_t)m->n_nodes);
    free(moved);
  }
  free(m->fem_only);
  m->fem_only = only;
  free(new_of_old);
}

/* The highest level a cell at Chebyshev distance d (cells) from the fine zone may belong to. */
static int allowed_level(int64_t d, int levels, int layers) {
  int l = 0;
  while (l < levels && (int64_t)layers * ((1 << (l + 1)) - 2) < d) ++l;
  return l;
}

typedef struct quadtree {
  int64_t cx, cy;  /* cells per axis */
  int8_t *level;   /* [cx cy] the level of the leaf holding each cell */
} quadtree;

static inline int8_t cell_level(const quadtree *t, int64_t i, int64_t j) {
  return i < 0 || j < 0 || i >= t->cx || j >= t->cy ? INT8_MAX : t->level[j * t->cx + i];
}

/* Whether the leaf of level l at cell (i0, j0) must split: it leaves the box, holds a cell
 * too near the fine zone or a lattice point with no node, or has a neighbour two levels finer. */
static bool must_split(const quadtree *t, int64_t i0, int64_t j0, int l, const int64_t *dist, const uint8_t *present,
                       int levels, int layers) {
  const int64_t S = (int64_t)1 << l, px = t->cx + 1;
  if (i0 + S > t->cx || j0 + S > t->cy) return true;
  for (int64_t j = j0; j < j0 + S; ++j)
    for (int64_t i = i0; i < i0 + S; ++i)
      if (allowed_level(dist[j * t->cx + i], levels, layers) < l) return true;
  for (int64_t j = j0; j <= j0 + S; ++j)
    for (int64_t i = i0; i <= i0 + S; ++i)
      if (!present[j * px + i]) return true;
  for (int64_t k = 0; k < S; ++k) /* the cells across the four sides */
    if (cell_level(t, i0 + k, j0 - 1) < l - 1 || cell_level(t, i0 + k, j0 + S) < l - 1 ||
        cell_level(t, i0 - 1, j0 + k) < l - 1 || cell_level(t, i0 + S, j0 + k) < l - 1)
      return true;
  return false;
}

static void build_quadtree(quadtree *t, const int64_t *dist, const uint8_t *present, int levels, int layers) {
  for (int64_t c = 0; c < t->cx * t->cy; ++c) t->level[c] = (int8_t)levels;
  for (bool changed = true; changed;) {
    changed = false;
    for (int l = levels; l >= 1; --l) {
      const int64_t S = (int64_t)1 << l;
      for (int64_t j0 = 0; j0 < t->cy; j0 += S)
        for (int64_t i0 = 0; i0 < t->cx; i0 += S) {
          if (t->level[j0 * t->cx + i0] != l || !must_split(t, i0, j0, l, dist, present, levels, layers)) continue;
          for (int64_t j = j0; j < j0 + S && j < t->cy; ++j)
            for (int64_t i = i0; i < i0 + S && i < t->cx; ++i) t->level[j * t->cx + i] = (int8_t)(l - 1);
          changed = true;
        }
    }
  }
}

/* Chebyshev distance in cells from each cell to the nearest fine cell (two chamfer passes). */
static void distance_to_fine(int64_t cx, int64_t cy, const uint8_t *fine, int64_t *dist) {
  const int64_t far = cx + cy + 2;
  for (int64_t c = 0; c < cx * cy; ++c) dist[c] = fine[c] ? 0 : far;
  for (int pass = 0; pass < 2; ++pass)
    for (int64_t jj = 0; jj < cy; ++jj)
      for (int64_t ii = 0; ii < cx; ++ii) {
        const int64_t i = pass ? cx - 1 - ii : ii, j = pass ? cy - 1 - jj : jj, step = pass ? 1 : -1;
        int64_t *d = &dist[j * cx + i];
        const int64_t ni[4] = {i + step, i + step, i, i - step}, nj[4] = {j, j + step, j + step, j + step};
        for (int k = 0; k < 4; ++k)
          if (ni[k] >= 0 && ni[k] < cx && nj[k] >= 0 && nj[k] < cy && dist[nj[k] * cx + ni[k]] + 1 < *d)
            *d = dist[nj[k] * cx + ni[k]] + 1;
      }
}

typedef struct element_list {
  int32_t count, cap;
  int64_t *offset, *corner, n_corners, cap_corners; /* corners as lattice point indices */
  int8_t *level;
} element_list;

static void add_element(element_list *e, const int64_t *corners, int n, int level) {
  if (e->count + 1 >= e->cap) {
    e->cap = 2 * e->cap + 64;
    e->offset = peri_realloc(e->offset, sizeof(int64_t) * (size_t)(e->cap + 1));
    e->level = peri_realloc(e->level, (size_t)e->cap);
  }
  if (e->n_corners + n > e->cap_corners) {
    e->cap_corners = 2 * e->cap_corners + 256;
    e->corner = peri_realloc(e->corner, sizeof(int64_t) * (size_t)e->cap_corners);
  }
  e->offset[e->count] = e->n_corners;
  for (int a = 0; a < n; ++a) e->corner[e->n_corners++] = corners[a];
  e->level[e->count++] = (int8_t)level;
  e->offset[e->count] = e->n_corners;
}

/* The elements of the leaves: Q4, or triangles about the centre where a side has its middle
 * node; marks the nodes (corners of every leaf, centres of the split ones). */
static void make_elements(const quadtree *t, const uint8_t *present, uint8_t *node, element_list *e) {
  const int64_t px = t->cx + 1;
  for (int pass = 0; pass < 2; ++pass)
    for (int64_t j0 = 0; j0 < t->cy; ++j0)
      for (int64_t i0 = 0; i0 < t->cx; ++i0) {
        const int l = t->level[j0 * t->cx + i0];
        const int64_t S = (int64_t)1 << l;
        if (i0 % S || j0 % S) continue; /* not the leaf's first cell */
        const int64_t c[4] = {j0 * px + i0, j0 * px + i0 + S, (j0 + S) * px + i0 + S, (j0 + S) * px + i0};
        if (pass == 0) { /* the corners first: the middles of the sides are the finer leaves' corners */
          for (int a = 0; a < 4; ++a) node[c[a]] |= present[c[a]];
          continue;
        }
        if (l == 0) {
          if (present[c[0]] && present[c[1]] && present[c[2]] && present[c[3]]) add_element(e, c, 4, 0);
          continue;
        }
        const int64_t h = S / 2;
        const int64_t mid[4] = {j0 * px + i0 + h, (j0 + h) * px + i0 + S, (j0 + S) * px + i0 + h, (j0 + h) * px + i0};
        int64_t ring[8];
        int n = 0;
        for (int a = 0; a < 4; ++a) {
          ring[n++] = c[a];
          if (node[mid[a]]) ring[n++] = mid[a];
        }
        if (n == 4) {
          add_element(e, c, 4, l);
          continue;
        }
        const int64_t centre = (j0 + h) * px + i0 + h;
        node[centre] = 1;
        if (n == 5) { /* one middle node, after corner k: two quadrilaterals and a triangle */
          int k = 0;
          while (!node[mid[k]]) ++k;
          const int64_t qa[4] = {c[k], mid[k], centre, c[(k + 3) % 4]};
          const int64_t qb[4] = {mid[k], c[(k + 1) % 4], c[(k + 2) % 4], centre};
          const int64_t tri[3] = {centre, c[(k + 2) % 4], c[(k + 3) % 4]};
          add_element(e, qa, 4, l);
          add_element(e, qb, 4, l);
          add_element(e, tri, 3, l);
          continue;
        }
        for (int a = 0; a < n; ++a) {
          const int64_t tri[3] = {centre, ring[a], ring[(a + 1) % n]};
          add_element(e, tri, 3, l);
        }
      }
}

/* The polygon area of an element's corners (lattice units). */
static double corner_area(const element_list *e, int32_t k, int64_t px) {
  double area = 0.0;
  const int64_t a0 = e->offset[k], n = e->offset[k + 1] - a0;
  for (int64_t a = 0; a < n; ++a) {
    const int64_t p = e->corner[a0 + a], q = e->corner[a0 + (a + 1) % n];
    area += (double)(p % px) * (double)(q / px) - (double)(q % px) * (double)(p / px);
  }
  return 0.5 * area;
}

int peri_graded_mesh_build(peri_particles *p, double dx, double reach, double h, const peri_shape *fine, int n_fine_shapes,
                           int levels, int layers, peri_fem_mesh *m, char *why, size_t n) {
  memset(m, 0, sizeof *m);
  peri_lattice l;
  int rc = peri_lattice_build(p, 2, dx, &l, why, n);
  if (rc != PERI_OK) return rc;
  const int64_t px = l.extent[0], py = l.extent[1], points = px * py;
  if (px < 2 || py < 2) {
    snprintf(why, n, "the body is less than one lattice cell wide (%lld x %lld nodes)", (long long)px, (long long)py);
    peri_lattice_free(&l);
    return PERI_ERR_INPUT;
  }
  quadtree t = {.cx = px - 1, .cy = py - 1};
  const int64_t cells = t.cx * t.cy;
  double lo[2] = {p->x[0] - (double)l.cell[0] * dx, p->x[1] - (double)l.cell[1] * dx};
  uint8_t *present = peri_calloc((size_t)points, 1), *node = peri_calloc((size_t)points, 1);
  uint8_t *fine_cell = peri_calloc((size_t)cells, 1);
  for (int64_t k = 0; k < points; ++k) present[k] = l.at[k] >= 0;
  int64_t n_fine = 0;
  for (int64_t j = 0; j < t.cy; ++j)
    for (int64_t i = 0; i < t.cx; ++i) {
      const double centre[3] = {lo[0] + ((double)i + 0.5) * dx, lo[1] + ((double)j + 0.5) * dx, 0.0};
      for (int k = 0; k < n_fine_shapes && !fine_cell[j * t.cx + i]; ++k)
        fine_cell[j * t.cx + i] = peri_shape_contains(&fine[k], 2, centre, 1e-9 * dx);
      n_fine += fine_cell[j * t.cx + i];
    }
  if (n_fine == 0) {
    snprintf(why, n, "the fine zone holds no lattice cell (no cell centre of spacing %g lies in it)", dx);
    free(present), free(node), free(fine_cell), peri_lattice_free(&l);
    return PERI_ERR_INPUT;
  }
  int64_t *dist = peri_malloc(sizeof(int64_t) * (size_t)cells);
  distance_to_fine(t.cx, t.cy, fine_cell, dist);
  t.level = peri_malloc((size_t)cells);
  build_quadtree(&t, dist, present, levels, layers);
  element_list e = {0};
  make_elements(&t, present, node, &e);

  /* the status of each lattice point and the coarse nodes' shares of their elements' areas */
  uint8_t *status = peri_calloc((size_t)points, 1);
  double *area = peri_calloc((size_t)points, sizeof(double));
  for (int64_t k = 0; k < points; ++k) status[k] = !present[k] ? ABSENT : node[k] ? FINE : REMOVED;
  for (int32_t k = 0; k < e.count; ++k) {
    const double share = corner_area(&e, k, px) * dx * dx / (double)(e.offset[k + 1] - e.offset[k]);
    for (int64_t a = e.offset[k]; a < e.offset[k + 1]; ++a) {
      area[e.corner[a]] += share;
      if (e.level[k] > 0) status[e.corner[a]] = COARSE;
    }
  }
  /* the nodes whose horizon reaches a coarse node or a removed point stay FEM */
  const int R = (int)ceil(reach / dx);
  uint8_t *only = peri_calloc((size_t)points, 1);
  for (int64_t j = 0; j < py; ++j)
    for (int64_t i = 0; i < px; ++i) {
      if (status[j * px + i] != COARSE && status[j * px + i] != REMOVED) continue;
      for (int64_t b = -R; b <= R; ++b)
        for (int64_t a = -R; a <= R; ++a)
          if (i + a >= 0 && i + a < px && j + b >= 0 && j + b < py && (double)(a * a + b * b) * dx * dx <= reach * reach)
            only[(j + b) * px + i + a] = 1;
    }
  /* remove the lattice nodes inside coarse elements: the kept ones first, in their order */
  const int32_t nn = p->n;
  int32_t *perm = peri_malloc(sizeof(int32_t) * (size_t)(nn > 0 ? nn : 1));
  int32_t *new_of_old = peri_malloc(sizeof(int32_t) * (size_t)(nn > 0 ? nn : 1));
  int32_t kept = 0;
  for (int pass = 0; pass < 2; ++pass)
    for (int32_t i = 0; i < nn; ++i) {
      const int64_t k = l.cell[3 * (size_t)i + 1] * px + l.cell[3 * (size_t)i];
      if ((status[k] != REMOVED) == (pass == 0)) {
        if (pass == 0) new_of_old[i] = kept;
        perm[kept++] = i;
      }
    }
  int32_t n_kept = 0;
  for (int32_t i = 0; i < nn; ++i) {
    const int64_t k = l.cell[3 * (size_t)i + 1] * px + l.cell[3 * (size_t)i];
    if (status[k] == COARSE) p->volume[i] = area[k] * h, m->coarse_nodes++;
    n_kept += status[k] != REMOVED;
  }
  m->removed = nn - n_kept;
  m->n_nodes = n_kept;
  m->fem_only = peri_calloc((size_t)(n_kept > 0 ? n_kept : 1), 1);
  for (int32_t i = 0; i < nn; ++i) {
    const int64_t k = l.cell[3 * (size_t)i + 1] * px + l.cell[3 * (size_t)i];
    if (status[k] != REMOVED) m->fem_only[new_of_old[i]] = only[k];
  }
  m->n_elements = e.count;
  m->offset = e.offset ? e.offset : peri_calloc(1, sizeof(int64_t));
  m->nodes = peri_malloc(sizeof(int32_t) * (size_t)(e.n_corners > 0 ? e.n_corners : 1));
  m->coarse = peri_malloc((size_t)(e.count > 0 ? e.count : 1));
  for (int32_t k = 0; k < e.count; ++k) m->coarse[k] = e.level[k] > 0;
  for (int64_t a = 0; a < e.n_corners; ++a) m->nodes[a] = new_of_old[l.at[e.corner[a]]];
  peri_particles_permute(p, perm);
  p->n = p->n_owned = n_kept;
  free(perm), free(new_of_old), free(only), free(status), free(area), free(e.corner), free(e.level);
  free(dist), free(t.level), free(present), free(node), free(fine_cell);
  peri_lattice_free(&l);
  return PERI_OK;
}
