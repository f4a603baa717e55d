/* The FEM part of a coupled model on a mesh read from a file (include/peri/fem_mesh.h,
 * docs/coupling.md "Gmsh meshes"). The PD rows reach every node within a horizon, so near the
 * PD nodes the mesh's nodes must be the PD grid's own (002_b20c318388227af9.txt §2.1: the
 * interface elements reference PD nodes): a file node on a node of the grid becomes that node,
 * the others are added, and the grid's points that the mesh covers without a node there
 * (holes) are left out. Nodes within reach of an added node off the grid or of a hole may not
 * be PD nodes (fem_only), which the coupling checks against the PD zone. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/fem_mesh.h"
#include "lattice_mesh.h"

void peri_fem_mesh_file_free(peri_fem_mesh_file *f) {
  if (!f) return;
  free(f->path);
  free(f->node_tag);
  free(f->x);
  free(f->element_tag);
  free(f->offset);
  free(f->corner);
  memset(f, 0, sizeof *f);
}

/* Corners of the faces of a hexahedron, outward (include/peri/fem.h order). */
static const int hex_face[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};

/* det J at the Gauss points of an element (2 per axis for Q4 and Hex8; the constant one of a
 * bar and a triangle) and its measure (sum of weight x det J). Returns 0, 1 when det J < 0 at a
 * point (inverted), 2 when |det J| is below 1e-10 of the element's size to the power dim
 * (degenerate). */
static int element_measure(int dim, int corners, const double *x, double *measure) {
  double size = 0.0; /* the largest extent of the corners along an axis */
  for (int d = 0; d < dim; ++d) {
    double lo = x[d], hi = x[d];
    for (int a = 1; a < corners; ++a) lo = fmin(lo, x[dim * a + d]), hi = fmax(hi, x[dim * a + d]);
    size = fmax(size, hi - lo);
  }
  const double tiny = 1e-10 * pow(size, dim);
  double dets[8];
  int n = 0;
  if (dim == 1) {
    dets[n++] = x[1] - x[0];
    if (dets[0] < 0) dets[0] = -dets[0]; /* a bar has no orientation */
  } else if (dim == 2 && corners == 3) {
    dets[n++] = 0.5 * ((x[2] - x[0]) * (x[5] - x[1]) - (x[4] - x[0]) * (x[3] - x[1]));
  } else if (dim == 2) {
    static const double xa[4] = {-1, 1, 1, -1}, ya[4] = {-1, -1, 1, 1};
    const double g = 1.0 / sqrt(3.0);
    for (int q = 0; q < 4; ++q) {
      double J[2][2] = {{0, 0}, {0, 0}};
      for (int a = 0; a < 4; ++a) {
        const double dxi = 0.25 * xa[a] * (1.0 + ya[a] * ya[q] * g), deta = 0.25 * ya[a] * (1.0 + xa[a] * xa[q] * g);
        for (int c = 0; c < 2; ++c) J[0][c] += dxi * x[2 * a + c], J[1][c] += deta * x[2 * a + c];
      }
      dets[n++] = J[0][0] * J[1][1] - J[0][1] * J[1][0];
    }
  } else {
    static const double xa[8] = {-1, 1, 1, -1, -1, 1, 1, -1}, ya[8] = {-1, -1, 1, 1, -1, -1, 1, 1},
                        za[8] = {-1, -1, -1, -1, 1, 1, 1, 1};
    const double g = 1.0 / sqrt(3.0);
    for (int q = 0; q < 8; ++q) {
      double J[3][3] = {{0}};
      for (int a = 0; a < 8; ++a) {
        const double fx = 1.0 + xa[a] * xa[q] * g, fy = 1.0 + ya[a] * ya[q] * g, fz = 1.0 + za[a] * za[q] * g;
        const double dN[3] = {0.125 * xa[a] * fy * fz, 0.125 * ya[a] * fx * fz, 0.125 * za[a] * fx * fy};
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) J[i][j] += dN[i] * x[3 * a + j];
      }
      dets[n++] = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                  J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
    }
  }
  *measure = 0.0;
  bool inverted = false, degenerate = false;
  for (int q = 0; q < n; ++q) {
    *measure += dets[q]; /* the Gauss weights are 1 and the reference cells have measure 2^dim */
    inverted |= dets[q] < -tiny;
    degenerate |= fabs(dets[q]) <= tiny;
  }
  if (dim == 1) *measure = dets[0];
  return inverted ? 1 : degenerate ? 2 : 0;
}

/* Whether point y lies inside or on the element (within tol): an interval, a counter-clockwise
 * polygon, or a hexahedron whose faces are split in two triangles (exact for plane faces). */
static bool element_holds(int dim, int corners, const double *x, const double *y, double tol) {
  if (dim == 1) return y[0] >= fmin(x[0], x[1]) - tol && y[0] <= fmax(x[0], x[1]) + tol;
  if (dim == 2) {
    for (int a = 0; a < corners; ++a) {
      const double *p = &x[2 * a], *q = &x[2 * ((a + 1) % corners)];
      const double ex = q[0] - p[0], ey = q[1] - p[1], L = hypot(ex, ey);
      if (ex * (y[1] - p[1]) - ey * (y[0] - p[0]) < -tol * L) return false;
    }
    return true;
  }
  for (int f = 0; f < 6; ++f)
    for (int t = 0; t < 2; ++t) {
      const double *a = &x[3 * hex_face[f][0]], *b = &x[3 * hex_face[f][1 + t]], *c = &x[3 * hex_face[f][2 + t]];
      const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
      const double nrm[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
      const double len = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
      if (nrm[0] * (y[0] - a[0]) + nrm[1] * (y[1] - a[1]) + nrm[2] * (y[2] - a[2]) > tol * len) return false;
    }
  return true;
}

int peri_fem_mesh_from_file(peri_particles *p, double dx, double reach, double h, int32_t material,
                            const peri_fem_mesh_file *f, peri_fem_mesh *m, char *why, size_t n) {
  memset(m, 0, sizeof *m);
  const int dim = f->dim;
  peri_lattice l;
  int rc = peri_lattice_build(p, dim, dx, &l, why, n);
  if (rc != PERI_OK) return rc;
  const int32_t n_grid = p->n, nf = f->n_nodes;
  double lo[3] = {0, 0, 0};
  for (int d = 0; d < dim; ++d) lo[d] = p->x[d] - (double)l.cell[d] * dx;
  const double tol = 1e-6 * dx;

  /* the elements: measure and orientation */
  double *measure = peri_malloc(sizeof(double) * (size_t)(f->n_elements > 0 ? f->n_elements : 1));
  for (int32_t e = 0; e < f->n_elements && rc == PERI_OK; ++e) {
    const int corners = (int)(f->offset[e + 1] - f->offset[e]);
    double x[24];
    for (int a = 0; a < corners; ++a)
      for (int d = 0; d < dim; ++d) x[dim * a + d] = f->x[3 * (size_t)f->corner[f->offset[e] + a] + d];
    const int bad = element_measure(dim, corners, x, &measure[e]);
    if (bad) {
      const int32_t c0 = f->corner[f->offset[e]];
      snprintf(why, n, "%s: element %lld (first node %lld at (%g, %g, %g)) is %s", f->path, (long long)f->element_tag[e],
               (long long)f->node_tag[c0], f->x[3 * (size_t)c0], f->x[3 * (size_t)c0 + 1], f->x[3 * (size_t)c0 + 2],
               bad == 1 ? "inverted: det J < 0 at a Gauss point (its nodes go clockwise, or it folds over)"
                        : "degenerate: det J = 0 at a Gauss point (coincident nodes or collinear corners)");
      rc = PERI_ERR_INPUT;
    }
  }

  /* the file nodes on the grid: their lattice point, and the node of p there */
  int64_t *point = peri_malloc(sizeof(int64_t) * 3 * (size_t)(nf > 0 ? nf : 1));
  uint8_t *on_grid = peri_calloc((size_t)(nf > 0 ? nf : 1), 1);
  int32_t *node_of = peri_malloc(sizeof(int32_t) * (size_t)(nf > 0 ? nf : 1)); /* file node -> node of p, or -1 */
  int32_t *file_of = peri_malloc(sizeof(int32_t) * (size_t)(n_grid > 0 ? n_grid : 1)); /* node of p -> file node */
  for (int32_t i = 0; i < n_grid; ++i) file_of[i] = -1;
  for (int32_t a = 0; a < nf && rc == PERI_OK; ++a) {
    bool on = true;
    for (int d = 0; d < 3; ++d) {
      const double t = d < dim ? (f->x[3 * (size_t)a + d] - lo[d]) / dx : 0.0, k = nearbyint(t);
      point[3 * (size_t)a + d] = (int64_t)k;
      on = on && fabs(t - k) * dx <= tol;
    }
    on_grid[a] = on;
    node_of[a] = on ? peri_lattice_node(&l, &point[3 * (size_t)a]) : -1;
    if (node_of[a] >= 0 && file_of[node_of[a]] >= 0) {
      snprintf(why, n, "%s: nodes %lld and %lld coincide at (%g, %g, %g) (an unmerged mesh: Coherence in Gmsh)",
               f->path, (long long)f->node_tag[file_of[node_of[a]]], (long long)f->node_tag[a], f->x[3 * (size_t)a],
               f->x[3 * (size_t)a + 1], f->x[3 * (size_t)a + 2]);
      rc = PERI_ERR_INPUT;
    } else if (node_of[a] >= 0) {
      file_of[node_of[a]] = a;
    }
  }

  /* holes and off-grid nodes, by their effect on the grid's points within reach: cause[] over
   * the lattice box of p widened by R on each side */
  const int R = (int)ceil(reach / dx - 1e-9);
  int64_t ext[3] = {1, 1, 1}, box = 1;
  for (int d = 0; d < dim; ++d) ext[d] = l.extent[d] + 2 * R, box *= ext[d];
  int64_t *cause = peri_calloc((size_t)(rc == PERI_OK ? box : 1), sizeof(int64_t));
  uint8_t *removed = peri_calloc((size_t)(n_grid > 0 ? n_grid : 1), 1);
  for (int32_t e = 0; e < f->n_elements && rc == PERI_OK; ++e) {
    const int64_t a0 = f->offset[e];
    const int corners = (int)(f->offset[e + 1] - a0);
    double x[24];
    int64_t kmin[3] = {0, 0, 0}, kmax[3] = {0, 0, 0};
    for (int d = 0; d < dim; ++d) {
      double xl = INFINITY, xh = -INFINITY;
      for (int a = 0; a < corners; ++a) {
        x[dim * a + d] = f->x[3 * (size_t)f->corner[a0 + a] + d];
        xl = fmin(xl, x[dim * a + d]), xh = fmax(xh, x[dim * a + d]);
      }
      kmin[d] = (int64_t)fmax(ceil((xl - lo[d]) / dx - 1e-6), (double)-R);
      kmax[d] = (int64_t)fmin(floor((xh - lo[d]) / dx + 1e-6), (double)(l.extent[d] - 1 + R));
    }
    for (int64_t k2 = kmin[2]; k2 <= kmax[2]; ++k2)
      for (int64_t k1 = kmin[1]; k1 <= kmax[1]; ++k1)
        for (int64_t k0 = kmin[0]; k0 <= kmax[0]; ++k0) {
          const int64_t k[3] = {k0, k1, k2};
          bool corner = false;
          for (int a = 0; a < corners && !corner; ++a) {
            const int32_t c = f->corner[a0 + a];
            corner = on_grid[c] && point[3 * (size_t)c] == k0 && point[3 * (size_t)c + 1] == k1 &&
                     point[3 * (size_t)c + 2] == k2;
          }
          const double y[3] = {lo[0] + (double)k0 * dx, lo[1] + (double)k1 * dx, lo[2] + (double)k2 * dx};
          if (corner || !element_holds(dim, corners, x, y, tol)) continue;
          const int32_t j = peri_lattice_node(&l, k);
          if (j >= 0 && file_of[j] >= 0) continue; /* a node of another element on this one's side */
          if (j >= 0) removed[j] = 1;
          cause[((k2 + (dim > 2 ? R : 0)) * ext[1] + k1 + (dim > 1 ? R : 0)) * ext[0] + k0 + R] = -f->element_tag[e];
        }
  }
  /* the nodes of p within reach of a hole (in the lattice box) */
  uint8_t *only = peri_calloc((size_t)(n_grid + nf > 0 ? n_grid + nf : 1), 1);
  int64_t *only_tag = peri_calloc((size_t)(n_grid + nf > 0 ? n_grid + nf : 1), sizeof(int64_t));
  const double limit = reach * reach * (1.0 + 1e-9);
  for (int32_t i = 0; i < n_grid && rc == PERI_OK; ++i) {
    const int64_t *c = &l.cell[3 * (size_t)i];
    for (int64_t b2 = dim > 2 ? -R : 0; b2 <= (dim > 2 ? R : 0) && !only[i]; ++b2)
      for (int64_t b1 = dim > 1 ? -R : 0; b1 <= (dim > 1 ? R : 0) && !only[i]; ++b1)
        for (int64_t b0 = -R; b0 <= R && !only[i]; ++b0) {
          if ((double)(b0 * b0 + b1 * b1 + b2 * b2) * dx * dx > limit) continue;
          const int64_t q = ((c[2] + b2 + (dim > 2 ? R : 0)) * ext[1] + c[1] + b1 + (dim > 1 ? R : 0)) * ext[0] + c[0] + b0 + R;
          if (cause[q]) only[i] = 1, only_tag[i] = cause[q];
        }
  }
  /* ... and of a file node off the grid */
  for (int32_t a = 0; a < nf && rc == PERI_OK; ++a) {
    if (on_grid[a]) continue;
    const int64_t *c = &point[3 * (size_t)a];
    for (int64_t b2 = dim > 2 ? -R - 1 : 0; b2 <= (dim > 2 ? R + 1 : 0); ++b2)
      for (int64_t b1 = dim > 1 ? -R - 1 : 0; b1 <= (dim > 1 ? R + 1 : 0); ++b1)
        for (int64_t b0 = -R - 1; b0 <= R + 1; ++b0) {
          const int64_t k[3] = {c[0] + b0, c[1] + b1, c[2] + b2};
          const int32_t j = peri_lattice_node(&l, k);
          if (j < 0 || only[j]) continue;
          double r2 = 0.0;
          for (int d = 0; d < dim; ++d) r2 += pow(p->x[3 * (size_t)j + d] - f->x[3 * (size_t)a + d], 2);
          if (r2 <= limit) only[j] = 1, only_tag[j] = f->node_tag[a];
        }
  }

  /* volumes: a file node's share of its elements, unless all of them are lattice cells */
  double *share = peri_calloc((size_t)(nf > 0 ? nf : 1), sizeof(double));
  uint8_t *all_cells = peri_malloc((size_t)(nf > 0 ? nf : 1));
  memset(all_cells, 1, (size_t)(nf > 0 ? nf : 1));
  for (int32_t e = 0; e < f->n_elements && rc == PERI_OK; ++e) {
    const int64_t a0 = f->offset[e];
    const int corners = (int)(f->offset[e + 1] - a0);
    bool cell = corners == 1 << dim;
    for (int d = 0; d < dim && cell; ++d) {
      int64_t kl = INT64_MAX, kh = INT64_MIN;
      for (int a = 0; a < corners; ++a) {
        const int32_t c = f->corner[a0 + a];
        cell = cell && on_grid[c];
        kl = point[3 * (size_t)c + d] < kl ? point[3 * (size_t)c + d] : kl;
        kh = point[3 * (size_t)c + d] > kh ? point[3 * (size_t)c + d] : kh;
      }
      cell = cell && kh - kl == 1;
    }
    for (int a = 0; a < corners; ++a) {
      share[f->corner[a0 + a]] += measure[e] * h / corners;
      if (!cell) all_cells[f->corner[a0 + a]] = 0;
    }
  }

  /* the added nodes, then the removed nodes of p left out: kept nodes first, in their order */
  int32_t *index = peri_malloc(sizeof(int32_t) * (size_t)(nf > 0 ? nf : 1)); /* file node -> node (before removal) */
  for (int32_t a = 0; a < nf && rc == PERI_OK; ++a) {
    if (node_of[a] >= 0) {
      index[a] = node_of[a];
      if (!all_cells[a]) p->volume[node_of[a]] = share[a];
    } else {
      index[a] = peri_particles_add(p, &f->x[3 * (size_t)a], share[a], material, 0);
      only[index[a]] = 1, only_tag[index[a]] = 0;
    }
  }
  if (rc == PERI_OK) {
    const int32_t total = p->n;
    int32_t *perm = peri_malloc(sizeof(int32_t) * (size_t)(total > 0 ? total : 1));
    int32_t *new_of_old = peri_malloc(sizeof(int32_t) * (size_t)(total > 0 ? total : 1));
    int32_t kept = 0;
    for (int pass = 0; pass < 2; ++pass)
      for (int32_t i = 0; i < total; ++i) {
        const bool gone = i < n_grid && removed[i];
        if (gone == (pass == 1)) {
          new_of_old[i] = pass == 0 ? kept : -1;
          perm[kept++] = i;
        }
      }
    int32_t n_kept = 0;
    for (int32_t i = 0; i < total; ++i) n_kept += new_of_old[i] >= 0;
    m->n_nodes = n_kept;
    m->removed = total - n_kept;
    m->fem_only = peri_calloc((size_t)(n_kept > 0 ? n_kept : 1), 1);
    m->fem_only_tag = peri_calloc((size_t)(n_kept > 0 ? n_kept : 1), sizeof(int64_t));
    m->node_tag = peri_calloc((size_t)(n_kept > 0 ? n_kept : 1), sizeof(int64_t));
    for (int32_t i = 0; i < total; ++i)
      if (new_of_old[i] >= 0) m->fem_only[new_of_old[i]] = only[i], m->fem_only_tag[new_of_old[i]] = only_tag[i];
    for (int32_t a = 0; a < nf; ++a) {
      m->node_tag[new_of_old[index[a]]] = f->node_tag[a];
      m->coarse_nodes += !all_cells[a];
    }
    m->n_elements = f->n_elements;
    m->offset = peri_malloc(sizeof(int64_t) * ((size_t)f->n_elements + 1));
    memcpy(m->offset, f->offset, sizeof(int64_t) * ((size_t)f->n_elements + 1));
    m->nodes = peri_malloc(sizeof(int32_t) * (size_t)(f->offset[f->n_elements] > 0 ? f->offset[f->n_elements] : 1));
    for (int64_t q = 0; q < f->offset[f->n_elements]; ++q) m->nodes[q] = new_of_old[index[f->corner[q]]];
    m->coarse = peri_calloc((size_t)(f->n_elements > 0 ? f->n_elements : 1), 1); /* plain Q4 */
    m->element_tag = peri_malloc(sizeof(int64_t) * (size_t)(f->n_elements > 0 ? f->n_elements : 1));
    memcpy(m->element_tag, f->element_tag, sizeof(int64_t) * (size_t)f->n_elements);
    m->file = peri_strdup(f->path);
    peri_particles_permute(p, perm);
    p->n = p->n_owned = n_kept;
    free(perm), free(new_of_old);
  }
  free(measure), free(point), free(on_grid), free(node_of), free(file_of), free(cause), free(removed);
  free(only), free(only_tag), free(share), free(all_cells), free(index);
  peri_lattice_free(&l);
  if (rc != PERI_OK) peri_fem_mesh_free(m);
  return rc;
}
