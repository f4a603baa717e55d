/* Gmsh meshes (.msh, any version Gmsh reads), through the Gmsh library's C API: one point per
 * element of the deck's dimension, at the element's centroid, with its measure (volume; area
 * times thickness; length times cross-section) integrated from the Jacobians Gmsh computes,
 * so curved high-order elements are measured as Gmsh sees them. Physical groups of the deck's
 * dimension are the blocks (an element in several takes the one with the lowest tag) and,
 * like every physical group, sets: a group of lower dimension holds the points with a node in
 * it. Without physical groups of the deck's dimension, every element is in block 1. A .geo
 * file is a geometry that Gmsh meshes first. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/mesh.h"

#ifndef PERI_HAVE_GMSH

int peri_mesh_read_gmsh(peri_mesh *m, const char *path, int dim, double thickness, double cross_section) {
  (void)thickness, (void)cross_section;
  peri_mesh_init(m, dim);
  peri_error("%s: this build of peri reads no Gmsh meshes (built without libgmsh-dev)", path);
  return PERI_ERR_INPUT;
}

#else
#include <gmshc.h>
#include "gmsh_session.h"

static char *group_name(int dim, int tag) {
  char *name = NULL;
  int ierr = 0;
  gmshModelGetPhysicalName(dim, tag, &name, &ierr);
  char *out;
  if (ierr == 0 && name && *name) {
    out = peri_strdup(name);
  } else {
    char made[64];
    snprintf(made, sizeof made, "physical_%dd_%d", dim, tag); /* an unnamed group */
    out = peri_strdup(made);
  }
  gmshFree(name);
  return out;
}

typedef struct points_conn {
  int64_t *offset, *conn;
  int64_t n_conn, cap_offset, cap_conn;
  int *entity; /* each point's entity tag */
} points_conn;

/* The elements of one entity: a point each. */
static int read_entity(peri_mesh *m, points_conn *pc, const char *path, int dim, int entity, int32_t block,
                       double scale) {
  int *types = NULL, ierr = 0, rc = PERI_OK;
  size_t n_types = 0, **etags = NULL, *etags_n = NULL, etags_nn = 0, **ntags = NULL, *ntags_n = NULL, ntags_nn = 0;
  gmshModelMeshGetElements(&types, &n_types, &etags, &etags_n, &etags_nn, &ntags, &ntags_n, &ntags_nn, dim, entity, &ierr);
  if (ierr) return peri_gmsh_failed(path, "cannot read the elements");
  for (size_t t = 0; t < n_types && rc == PERI_OK; ++t) {
    char *tname = NULL;
    int edim = 0, order = 0, nn = 0, nprimary = 0;
    double *local = NULL, *weights = NULL, *jac = NULL, *det = NULL, *coord = NULL;
    size_t local_n = 0, weights_n = 0, jac_n = 0, det_n = 0, coord_n = 0;
    gmshModelMeshGetElementProperties(types[t], &tname, &edim, &order, &nn, &local, &local_n, &nprimary, &ierr);
    gmshFree(local);
    local = NULL;
    char rule[32];
    snprintf(rule, sizeof rule, "Gauss%d", 2 * order + 2); /* x det J: degree <= 2 order + 1 per variable */
    if (!ierr) gmshModelMeshGetIntegrationPoints(types[t], rule, &local, &local_n, &weights, &weights_n, &ierr);
    if (!ierr) gmshModelMeshGetJacobians(types[t], local, local_n, &jac, &jac_n, &det, &det_n, &coord, &coord_n,
                                         entity, 0, 1, &ierr);
    const size_t G = weights_n, ne = etags_n[t];
    if (ierr || det_n != ne * G || coord_n != 3 * ne * G) {
      rc = peri_gmsh_failed(path, "cannot measure the elements");
    } else if (edim == dim) {
      for (size_t e = 0; e < ne && rc == PERI_OK; ++e) {
        double v = 0.0, c[3] = {0, 0, 0};
        for (size_t g = 0; g < G; ++g) {
          const double w = weights[g] * det[e * G + g];
          v += w;
          for (int d = 0; d < 3; ++d) c[d] += w * coord[3 * (e * G + g) + d];
        }
        for (int d = 0; d < 3; ++d) c[d] = v != 0.0 ? c[d] / v : 0.0;
        const double volume = (v < 0 ? -v : v) * scale;
        for (int d = dim; d < 3; ++d)
          if (c[d] != 0.0) {
            peri_error("%s: element %zu lies at %c = %g, but the deck has dimension %d", path, etags[t][e],
                       "xyz"[d], c[d], dim);
            rc = PERI_ERR_INPUT;
          }
        if (rc != PERI_OK) break;
        if (!(volume > 0.0)) {
          peri_error("%s: element %zu (%s) has measure %g; a degenerate element", path, etags[t][e], tname, volume);
          rc = PERI_ERR_INPUT;
          break;
        }
        peri_mesh_add_point(m, c, volume, block, (int64_t)etags[t][e]);
        const int32_t k = m->n - 1;
        if ((int64_t)m->n + 1 > pc->cap_offset) {
          pc->cap_offset = 2 * (int64_t)m->n + 1024;
          pc->offset = peri_realloc(pc->offset, sizeof(int64_t) * (size_t)pc->cap_offset);
          pc->entity = peri_realloc(pc->entity, sizeof(int) * (size_t)pc->cap_offset);
        }
        if (pc->n_conn + nn > pc->cap_conn) {
          pc->cap_conn = 2 * (pc->n_conn + nn) + 4096;
          pc->conn = peri_realloc(pc->conn, sizeof(int64_t) * (size_t)pc->cap_conn);
        }
        for (int a = 0; a < nn; ++a) pc->conn[pc->n_conn++] = (int64_t)ntags[t][e * (size_t)nn + (size_t)a];
        pc->offset[k + 1] = pc->n_conn;
        pc->entity[k] = entity;
      }
    }
    gmshFree(tname);
    gmshFree(local);
    gmshFree(weights);
    gmshFree(jac);
    gmshFree(det);
    gmshFree(coord);
  }
  for (size_t t = 0; t < etags_nn; ++t) gmshFree(etags[t]);
  for (size_t t = 0; t < ntags_nn; ++t) gmshFree(ntags[t]);
  gmshFree(etags);
  gmshFree(etags_n);
  gmshFree(ntags);
  gmshFree(ntags_n);
  gmshFree(types);
  return rc;
}

static int read_model(peri_mesh *m, const char *path, int dim, double scale) {
  int ierr = 0, rc = PERI_OK;
  int *groups = NULL, *entities = NULL;
  size_t groups_n = 0, entities_n = 0;
  gmshModelGetPhysicalGroups(&groups, &groups_n, -1, &ierr);
  gmshModelGetEntities(&entities, &entities_n, dim, &ierr);
  if (ierr) {
    gmshFree(groups);
    gmshFree(entities);
    return peri_gmsh_failed(path, "cannot read the model's entities");
  }
  bool have_blocks = false;
  for (size_t g = 0; g < groups_n / 2; ++g) have_blocks |= groups[2 * g] == dim;
  points_conn pc = {0};
  pc.cap_offset = 1024;
  pc.offset = peri_calloc((size_t)pc.cap_offset, sizeof(int64_t));
  pc.entity = peri_calloc((size_t)pc.cap_offset, sizeof(int));
  for (size_t e = 0; e < entities_n / 2 && rc == PERI_OK; ++e) {
    const int entity = entities[2 * e + 1];
    int32_t block = 0;
    if (have_blocks) {
      int *tags = NULL;
      size_t tags_n = 0;
      gmshModelGetPhysicalGroupsForEntity(dim, entity, &tags, &tags_n, &ierr);
      int lowest = 0;
      for (size_t k = 0; k < tags_n; ++k)
        if (lowest == 0 || tags[k] < lowest) lowest = tags[k];
      gmshFree(tags);
      if (lowest == 0) { /* elements outside every physical group of the dimension */
        int *t2 = NULL;
        size_t *t2n = NULL, **et = NULL, **nt = NULL, *etn = NULL, *ntn = NULL, etnn = 0, ntnn = 0, nt2 = 0;
        gmshModelMeshGetElements(&t2, &nt2, &et, &etn, &etnn, &nt, &ntn, &ntnn, dim, entity, &ierr);
        size_t count = 0;
        for (size_t t = 0; t < etnn; ++t) count += etn[t];
        for (size_t t = 0; t < etnn; ++t) gmshFree(et[t]);
        for (size_t t = 0; t < ntnn; ++t) gmshFree(nt[t]);
        gmshFree(et), gmshFree(etn), gmshFree(nt), gmshFree(ntn), gmshFree(t2);
        (void)t2n;
        if (count > 0) {
          peri_error("%s: %zu elements of entity %d (dimension %d) belong to no physical group of "
                     "dimension %d, while others do; put them in one (the groups are the blocks)",
                     path, count, entity, dim, dim);
          rc = PERI_ERR_INPUT;
        }
        continue;
      }
      char *name = group_name(dim, lowest);
      block = peri_mesh_block_index(m, lowest, name);
      free(name);
    } else {
      block = peri_mesh_block_index(m, 1, "block_1");
    }
    rc = read_entity(m, &pc, path, dim, entity, block, scale);
  }
  /* the sets: every physical group */
  for (size_t g = 0; g < groups_n / 2 && rc == PERI_OK; ++g) {
    const int gdim = groups[2 * g], gtag = groups[2 * g + 1];
    char *name = group_name(gdim, gtag);
    if (gdim == dim) {
      int *ents = NULL;
      size_t ents_n = 0;
      gmshModelGetEntitiesForPhysicalGroup(gdim, gtag, &ents, &ents_n, &ierr);
      int32_t *points = peri_malloc(sizeof(int32_t) * (size_t)(m->n > 0 ? m->n : 1)), count = 0;
      for (int32_t k = 0; k < m->n; ++k)
        for (size_t a = 0; a < ents_n; ++a)
          if (pc.entity[k] == ents[a]) {
            points[count++] = k;
            break;
          }
      peri_mesh_add_set(m, name, gtag, "physical group", points, count);
      free(points);
      gmshFree(ents);
    } else {
      size_t *nodes = NULL, nodes_n = 0, coord_n = 0;
      double *coord = NULL;
      gmshModelMeshGetNodesForPhysicalGroup(gdim, gtag, &nodes, &nodes_n, &coord, &coord_n, &ierr);
      int64_t *vertices = peri_malloc(sizeof(int64_t) * (nodes_n > 0 ? nodes_n : 1));
      for (size_t a = 0; a < nodes_n; ++a) vertices[a] = (int64_t)nodes[a];
      peri_mesh_add_vertex_set(m, name, gtag, "physical group", pc.offset, pc.conn, vertices, (int64_t)nodes_n);
      free(vertices);
      gmshFree(nodes);
      gmshFree(coord);
    }
    free(name);
  }
  free(pc.offset);
  free(pc.conn);
  free(pc.entity);
  gmshFree(groups);
  gmshFree(entities);
  return rc;
}

typedef struct mesh_reading {
  peri_mesh *m;
  const char *path;
  int dim;
  double scale;
} mesh_reading;

static int read_file(void *context) {
  const mesh_reading *r = context;
  peri_mesh_init(r->m, r->dim);
  int rc = peri_gmsh_open(r->path, r->dim), ierr = 0;
  if (rc != PERI_OK) {
    peri_mesh_free(r->m);
    return rc;
  }
  rc = read_model(r->m, r->path, r->dim, r->scale);
  gmshFinalize(&ierr);
  if (rc != PERI_OK) peri_mesh_free(r->m);
  return rc;
}

int peri_mesh_read_gmsh(peri_mesh *m, const char *path, int dim, double thickness, double cross_section) {
  mesh_reading r = {m, path, dim, dim == 2 ? thickness : dim == 1 ? cross_section : 1.0};
  peri_mesh_init(m, dim); /* (an empty mesh where the guard refuses the file) */
  return peri_gmsh_guarded(path, dim, read_file, &r);
}

#endif
