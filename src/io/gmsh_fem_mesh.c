/* A finite-element mesh of the FEM part of a coupled model from a Gmsh file (.msh, any version
 * Gmsh reads; a .geo geometry is meshed by Gmsh first), through the Gmsh library's C API
 * (include/peri/mesh.h, docs/coupling.md "Gmsh meshes"). The elements of the deck's dimension
 * are the mesh: 2-node lines (1D), 3-node triangles and 4-node quadrilaterals (2D), 8-node
 * hexahedra (3D); elements of lower dimensions (boundaries, points) are skipped. Gmsh's corner
 * orders are those of include/peri/fem.h. */
#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/fem_mesh.h"
#include "peri/mesh.h"

#ifndef PERI_HAVE_GMSH

int peri_fem_mesh_file_read(const char *path, int dim, peri_fem_mesh_file *f) {
  (void)dim;
  memset(f, 0, sizeof *f);
  peri_error("%s: this build of peri reads no Gmsh meshes: it was built without the Gmsh library (install "
             "libgmsh-dev, e.g. with scripts/install-deps, and build again)", path);
  return PERI_ERR_INPUT;
}

#else
#include <gmshc.h>
#include "gmsh_session.h"

typedef struct tag_index {
  int64_t tag;
  int32_t index;
} tag_index;

static int by_tag(const void *a, const void *b) {
  const int64_t x = ((const tag_index *)a)->tag, y = ((const tag_index *)b)->tag;
  return (x > y) - (x < y);
}

/* Gmsh element types peri takes in each dimension (Gmsh's numbering: 1 line, 2 triangle,
 * 3 quadrangle, 5 hexahedron). */
static bool supported(int dim, int type) {
  return (dim == 1 && type == 1) || (dim == 2 && (type == 2 || type == 3)) || (dim == 3 && type == 5);
}

/* Reads the open model's nodes and elements into f. */
static int read_model(const char *path, int dim, peri_fem_mesh_file *f) {
  int ierr = 0, rc = PERI_OK;
  size_t *ntags = NULL, ntags_n = 0, coord_n = 0, param_n = 0;
  double *coord = NULL, *param = NULL;
  gmshModelMeshGetNodes(&ntags, &ntags_n, &coord, &coord_n, &param, &param_n, -1, -1, 0, 0, &ierr);
  if (ierr) return peri_gmsh_failed(path, "cannot read the nodes");
  f->n_nodes = (int32_t)ntags_n;
  f->node_tag = peri_malloc(sizeof(int64_t) * (ntags_n > 0 ? ntags_n : 1));
  f->x = peri_malloc(sizeof(double) * 3 * (ntags_n > 0 ? ntags_n : 1));
  tag_index *order = peri_malloc(sizeof(tag_index) * (ntags_n > 0 ? ntags_n : 1));
  for (size_t a = 0; a < ntags_n; ++a) {
    f->node_tag[a] = (int64_t)ntags[a];
    memcpy(&f->x[3 * a], &coord[3 * a], 3 * sizeof(double));
    order[a] = (tag_index){(int64_t)ntags[a], (int32_t)a};
    for (int d = 0; d < 3 && rc == PERI_OK; ++d)
      if (!isfinite(coord[3 * a + d])) { /* (a damaged file's overflowed number) */
        peri_error("%s: node %zu lies at %c = %g; positions must be finite", path, ntags[a], "xyz"[d],
                   coord[3 * a + d]);
        rc = PERI_ERR_INPUT;
      }
    for (int d = dim; d < 3 && rc == PERI_OK; ++d)
      if (coord[3 * a + d] != 0.0) {
        peri_error("%s: node %zu lies at %c = %g, but the deck has dimension %d", path, ntags[a], "xyz"[d],
                   coord[3 * a + d], dim);
        rc = PERI_ERR_INPUT;
      }
  }
  gmshFree(ntags), gmshFree(coord), gmshFree(param);
  qsort(order, ntags_n, sizeof *order, by_tag);

  int *types = NULL;
  size_t types_n = 0, **etags = NULL, *etags_n = NULL, etags_nn = 0, **enodes = NULL, *enodes_n = NULL, enodes_nn = 0;
  if (rc == PERI_OK) gmshModelMeshGetElements(&types, &types_n, &etags, &etags_n, &etags_nn, &enodes, &enodes_n, &enodes_nn, -1, -1, &ierr);
  if (rc == PERI_OK && ierr) rc = peri_gmsh_failed(path, "cannot read the elements");
  size_t total = 0, corners = 0;
  for (size_t t = 0; t < types_n && rc == PERI_OK; ++t) {
    char *name = NULL;
    int edim = 0, order_ = 0, nn = 0, nprimary = 0;
    double *local = NULL;
    size_t local_n = 0;
    gmshModelMeshGetElementProperties(types[t], &name, &edim, &order_, &nn, &local, &local_n, &nprimary, &ierr);
    if (edim == dim && !supported(dim, types[t]) && etags_n[t] > 0) {
      peri_error("%s: element %zu is a %s (Gmsh type %d), which peri has no finite element for: the FEM part "
                 "takes %s", path, etags[t][0], name ? name : "?", types[t],
                 dim == 1 ? "2-node lines" : dim == 2 ? "4-node quadrangles and 3-node triangles" : "8-node hexahedra");
      rc = PERI_ERR_INPUT;
    } else if (edim > dim && etags_n[t] > 0) {
      peri_error("%s: element %zu is a %s of dimension %d, but the deck has dimension %d", path, etags[t][0],
                 name ? name : "?", edim, dim);
      rc = PERI_ERR_INPUT;
    } else if (edim == dim) {
      total += etags_n[t], corners += etags_n[t] * (size_t)nn;
    }
    gmshFree(name), gmshFree(local);
  }
  if (rc == PERI_OK && total == 0) {
    peri_error("%s: the mesh has no elements of dimension %d", path, dim);
    rc = PERI_ERR_INPUT;
  }
  uint8_t *used = peri_calloc(ntags_n > 0 ? ntags_n : 1, 1);
  if (rc == PERI_OK) {
    f->n_elements = (int32_t)total;
    f->element_tag = peri_malloc(sizeof(int64_t) * total);
    f->offset = peri_malloc(sizeof(int64_t) * (total + 1));
    f->corner = peri_malloc(sizeof(int32_t) * corners);
    f->offset[0] = 0;
    int32_t e = 0;
    for (size_t t = 0; t < types_n && rc == PERI_OK; ++t) {
      if (!supported(dim, types[t])) continue;
      const size_t nn = etags_n[t] > 0 ? enodes_n[t] / etags_n[t] : 0;
      for (size_t k = 0; k < etags_n[t] && rc == PERI_OK; ++k, ++e) {
        f->element_tag[e] = (int64_t)etags[t][k];
        f->offset[e + 1] = f->offset[e] + (int64_t)nn;
        for (size_t a = 0; a < nn; ++a) {
          const tag_index key = {(int64_t)enodes[t][k * nn + a], 0};
          const tag_index *hit = bsearch(&key, order, ntags_n, sizeof *order, by_tag);
          if (!hit) {
            peri_error("%s: element %zu names node %lld, which the file does not define", path, etags[t][k],
                       (long long)key.tag);
            rc = PERI_ERR_INPUT;
            break;
          }
          f->corner[f->offset[e] + (int64_t)a] = hit->index;
          used[hit->index] = 1;
        }
      }
    }
  }
  for (size_t a = 0; a < ntags_n && rc == PERI_OK; ++a)
    if (!used[a]) {
      peri_error("%s: node %lld at (%g, %g, %g) belongs to no element of dimension %d (an FEM node must be a "
                 "corner of an element)", path, (long long)f->node_tag[a], f->x[3 * a], f->x[3 * a + 1], f->x[3 * a + 2], dim);
      rc = PERI_ERR_INPUT;
    }
  free(used), free(order);
  for (size_t t = 0; t < etags_nn; ++t) gmshFree(etags[t]);
  for (size_t t = 0; t < enodes_nn; ++t) gmshFree(enodes[t]);
  gmshFree(etags), gmshFree(etags_n), gmshFree(enodes), gmshFree(enodes_n), gmshFree(types);
  return rc;
}

typedef struct fem_reading {
  const char *path;
  int dim;
  peri_fem_mesh_file *f;
} fem_reading;

static int read_file(void *context) {
  const fem_reading *r = context;
  int rc = peri_gmsh_open(r->path, r->dim), ierr = 0;
  if (rc != PERI_OK) return rc;
  rc = read_model(r->path, r->dim, r->f);
  gmshFinalize(&ierr);
  r->f->path = peri_strdup(r->path);
  if (rc != PERI_OK) peri_fem_mesh_file_free(r->f);
  return rc;
}

int peri_fem_mesh_file_read(const char *path, int dim, peri_fem_mesh_file *f) {
  memset(f, 0, sizeof *f);
  f->dim = dim;
  FILE *probe = fopen(path, "rb");
  if (!probe) {
    peri_error("cannot open mesh file '%s': %s", path, strerror(errno));
    return PERI_ERR_INPUT;
  }
  fclose(probe);
  fem_reading r = {path, dim, f};
  return peri_gmsh_guarded(path, dim, read_file, &r);
}

#endif
