/* Exodus II meshes (the Exodus C library, libexoIIv2c): one point per element. SPHERE
 * elements (Peridigm's sphere meshes) are points at their node with the volume of an element
 * attribute (the second, as Sierra and Peridigm write it, or one named "volume") or of a
 * nodal variable "volume" (PeriLab); solid elements are points at their centroid with their
 * volume (side nodes of quadratic elements are ignored, as Peridigm does). Element blocks are
 * the blocks; node sets become sets of the points that have a node in them. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "peri/error.h"
#include "peri/mesh.h"
#include "element_geometry.h"
#include "guarded_read.h"

#ifndef PERI_HAVE_EXODUS

int peri_mesh_read_exodus(peri_mesh *m, const char *path, int dim, double thickness, double cross_section) {
  (void)thickness, (void)cross_section;
  peri_mesh_init(m, dim);
  peri_error("%s: this build of peri reads no Exodus II meshes (built without libexodusii-dev)", path);
  return PERI_ERR_INPUT;
}

#else
#include <exodusII.h>

enum { NAME_LEN = 256 };

typedef enum { SHAPE_SPHERE = -1 } sphere_marker;

/* The element shape of an Exodus type name, -1 for SPHERE, -2 when unknown. */
static int shape_of(const char *type) {
  static const struct { const char *prefix; int shape; } table[] = {
      {"SPHERE", SHAPE_SPHERE}, {"TETRA", PERI_ELEMENT_TET}, {"TET", PERI_ELEMENT_TET},
      {"HEX", PERI_ELEMENT_HEX}, {"WEDGE", PERI_ELEMENT_WEDGE}, {"PYRAMID", PERI_ELEMENT_PYRAMID},
      {"TRIANGLE", PERI_ELEMENT_TRI}, {"TRI", PERI_ELEMENT_TRI}, {"QUAD", PERI_ELEMENT_QUAD},
      {"SHELL4", PERI_ELEMENT_QUAD}, {"SHELL3", PERI_ELEMENT_TRI}, {"BAR", PERI_ELEMENT_LINE},
      {"BEAM", PERI_ELEMENT_LINE}, {"TRUSS", PERI_ELEMENT_LINE}, {"EDGE", PERI_ELEMENT_LINE}};
  for (size_t k = 0; k < sizeof table / sizeof table[0]; ++k)
    if (strncasecmp(type, table[k].prefix, strlen(table[k].prefix)) == 0) return table[k].shape;
  return -2;
}

typedef struct reader {
  const char *path;
  int exoid;
  int num_dim, num_nodes, num_elem, num_blocks, num_node_sets;
  double *coord[3];
  double *nodal_volume; /* a nodal variable "volume", or NULL */
  int64_t *offset, *conn; /* each point's nodes (1-based), for the node sets */
  int64_t n_conn, cap_conn;
} reader;

static int fail(const reader *r, const char *what, int status) {
  peri_error("%s: cannot read %s (Exodus II error %d): not an Exodus II file, or a damaged one", r->path,
             what, status);
  return PERI_ERR_INPUT;
}

/* PeriLab's sphere meshes: the volume as the nodal variable "volume" of the first time step. */
static int read_nodal_volume(reader *r) {
  int nvars = 0;
  if (ex_get_var_param(r->exoid, "n", &nvars) < 0 || nvars <= 0) return PERI_OK;
  char **names = peri_calloc((size_t)nvars, sizeof(char *));
  for (int v = 0; v < nvars; ++v) names[v] = peri_calloc(NAME_LEN + 1, 1);
  int rc = PERI_OK;
  if (ex_get_var_names(r->exoid, "n", nvars, names) >= 0 && ex_inquire_int(r->exoid, EX_INQ_TIME) > 0) {
    for (int v = 0; v < nvars; ++v)
      if (strcasecmp(names[v], "volume") == 0) {
        r->nodal_volume = peri_malloc(sizeof(double) * (size_t)(r->num_nodes > 0 ? r->num_nodes : 1));
        int status = ex_get_nodal_var(r->exoid, 1, v + 1, r->num_nodes, r->nodal_volume);
        if (status < 0) rc = fail(r, "the nodal variable 'volume'", status);
        break;
      }
  }
  for (int v = 0; v < nvars; ++v) free(names[v]);
  free(names);
  return rc;
}

static void add_conn(reader *r, const int *nodes, int count) {
  if (r->n_conn + count > r->cap_conn) {
    r->cap_conn = 2 * (r->n_conn + count) + 1024;
    r->conn = peri_realloc(r->conn, sizeof(int64_t) * (size_t)r->cap_conn);
  }
  for (int k = 0; k < count; ++k) r->conn[r->n_conn++] = nodes[k];
}

static int read_block(reader *r, peri_mesh *m, int block_id, const int *elem_id, int *first_elem,
                      double thickness, double cross_section) {
  char type[NAME_LEN + 1] = "", name[NAME_LEN + 1] = "";
  int nelem = 0, npe = 0, nattr = 0, status;
  if ((status = ex_get_elem_block(r->exoid, block_id, type, &nelem, &npe, &nattr)) < 0)
    return fail(r, "an element block", status);
  ex_get_name(r->exoid, EX_ELEM_BLOCK, block_id, name);
  const int32_t b = peri_mesh_block_index(m, block_id, name);
  const char *bname = m->blocks[b].name;
  const int shape = shape_of(type);
  /* the counts before anything is sized or indexed by them: the blocks' elements together are
   * the header's (elem_id and r->offset hold that many) */
  if (nelem < 0 || npe < 0 || nattr < 0 || nelem > r->num_elem - *first_elem) {
    peri_error("%s: block '%s' (id %d) gives %d elements of %d nodes and %d attributes, but the header's %d "
               "elements leave %d for it (a damaged file)",
               r->path, bname, block_id, nelem, npe, nattr, r->num_elem, r->num_elem - *first_elem);
    return PERI_ERR_INPUT;
  }
  if (nelem == 0) return PERI_OK;
  if (shape == -2) {
    peri_error("%s: block '%s' (id %d): unknown element type '%s' (peri reads SPHERE, TETRA, HEX, "
               "WEDGE, PYRAMID, TRI, QUAD, BAR)", r->path, bname, block_id, type);
    return PERI_ERR_INPUT;
  }
  if (shape != SHAPE_SPHERE && peri_element_dim((peri_element_shape)shape) != m->dim) {
    peri_error("%s: block '%s' (id %d): %s elements are %dD, the deck has dimension %d", r->path, bname,
               block_id, type, peri_element_dim((peri_element_shape)shape), m->dim);
    return PERI_ERR_INPUT;
  }
  if (npe < (shape == SHAPE_SPHERE ? 1 : peri_element_corners((peri_element_shape)shape))) {
    peri_error("%s: block '%s' (id %d): %s elements with %d nodes", r->path, bname, block_id, type, npe);
    return PERI_ERR_INPUT;
  }
  int *conn = peri_malloc(sizeof(int) * (size_t)nelem * (size_t)(npe > 0 ? npe : 1));
  double *attr = NULL;
  int volume_attr = -1, rc = PERI_OK;
  if ((status = ex_get_elem_conn(r->exoid, block_id, conn)) < 0) rc = fail(r, "an element block's connectivity", status);
  if (rc == PERI_OK && shape == SHAPE_SPHERE) {
    if (nattr > 0) {
      attr = peri_malloc(sizeof(double) * (size_t)nelem * (size_t)nattr);
      if ((status = ex_get_elem_attr(r->exoid, block_id, attr)) < 0) rc = fail(r, "element attributes", status);
      char **anames = peri_calloc((size_t)nattr, sizeof(char *));
      for (int a = 0; a < nattr; ++a) anames[a] = peri_calloc(NAME_LEN + 1, 1);
      if (rc == PERI_OK && ex_get_elem_attr_names(r->exoid, block_id, anames) >= 0)
        for (int a = 0; a < nattr; ++a)
          if (strcasecmp(anames[a], "volume") == 0) volume_attr = a;
      for (int a = 0; a < nattr; ++a) free(anames[a]);
      free(anames);
      if (volume_attr < 0 && nattr >= 2) volume_attr = 1; /* Sierra/Peridigm: radius, volume */
    }
    if (rc == PERI_OK && volume_attr < 0 && !r->nodal_volume) {
      peri_error("%s: block '%s' (id %d): SPHERE elements without volumes (expected an element "
                 "attribute 'volume', the second attribute as Peridigm reads it, or a nodal "
                 "variable 'volume')", r->path, bname, block_id);
      rc = PERI_ERR_INPUT;
    }
  }
  const int corners = shape == SHAPE_SPHERE ? 1 : peri_element_corners((peri_element_shape)shape);
  const double scale = shape == SHAPE_SPHERE ? 1.0
                       : peri_element_dim((peri_element_shape)shape) == 2 ? thickness
                       : peri_element_dim((peri_element_shape)shape) == 1 ? cross_section : 1.0;
  for (int e = 0; rc == PERI_OK && e < nelem; ++e) {
    const int *nodes = conn + (size_t)e * (size_t)npe;
    double xyz[24], c[3] = {0, 0, 0}, v = 0.0;
    for (int k = 0; k < corners; ++k) {
      if (nodes[k] < 1 || nodes[k] > r->num_nodes) {
        peri_error("%s: block '%s' (id %d), element %d names node %d, which does not exist (the mesh "
                   "has %d nodes)", r->path, bname, block_id, elem_id[*first_elem + e], nodes[k], r->num_nodes);
        rc = PERI_ERR_INPUT;
        break;
      }
      for (int d = 0; d < 3; ++d) xyz[3 * k + d] = r->coord[d] ? r->coord[d][nodes[k] - 1] : 0.0;
    }
    if (rc != PERI_OK) break;
    if (shape == SHAPE_SPHERE) {
      for (int d = 0; d < 3; ++d) c[d] = xyz[d];
      v = volume_attr >= 0 ? attr[(size_t)e * (size_t)nattr + (size_t)volume_attr] : r->nodal_volume[nodes[0] - 1];
    } else {
      peri_element_measure((peri_element_shape)shape, xyz, &v, c);
      v *= scale;
    }
    for (int d = m->dim; d < 3; ++d)
      if (c[d] != 0.0) {
        peri_error("%s: block '%s' (id %d), element %d lies at %c = %g, but the deck has dimension %d",
                   r->path, bname, block_id, elem_id[*first_elem + e], "xyz"[d], c[d], m->dim);
        rc = PERI_ERR_INPUT;
      }
    if (rc != PERI_OK) break;
    if (!(v > 0.0)) {
      peri_error("%s: block '%s' (id %d), element %d has volume %g; volumes must be positive", r->path,
                 bname, block_id, elem_id[*first_elem + e], v);
      rc = PERI_ERR_INPUT;
      break;
    }
    peri_mesh_add_point(m, c, v, b, elem_id[*first_elem + e]);
    add_conn(r, nodes, npe);
    r->offset[m->n] = r->n_conn;
  }
  *first_elem += nelem;
  free(conn);
  free(attr);
  return rc;
}

static int read_node_sets(reader *r, peri_mesh *m) {
  if (r->num_node_sets <= 0) return PERI_OK;
  int *ids = peri_malloc(sizeof(int) * (size_t)r->num_node_sets), status, rc = PERI_OK;
  if ((status = ex_get_node_set_ids(r->exoid, ids)) < 0) rc = fail(r, "the node set ids", status);
  for (int s = 0; rc == PERI_OK && s < r->num_node_sets; ++s) {
    char name[NAME_LEN + 1] = "";
    ex_get_name(r->exoid, EX_NODE_SET, ids[s], name);
    if (!name[0]) snprintf(name, sizeof name, "nodelist_%d", ids[s]); /* Peridigm's name */
    int count = 0, ndf = 0;
    if ((status = ex_get_node_set_param(r->exoid, ids[s], &count, &ndf)) < 0) {
      rc = fail(r, "a node set", status);
      break;
    }
    int *nodes = peri_malloc(sizeof(int) * (size_t)(count > 0 ? count : 1));
    int64_t *vertices = peri_malloc(sizeof(int64_t) * (size_t)(count > 0 ? count : 1));
    if (count > 0 && (status = ex_get_node_set(r->exoid, ids[s], nodes)) < 0) rc = fail(r, "a node set", status);
    for (int k = 0; rc == PERI_OK && k < count; ++k) {
      if (nodes[k] < 1 || nodes[k] > r->num_nodes) {
        peri_error("%s: node set '%s' (id %d) names node %d, which does not exist (the mesh has %d nodes)",
                   r->path, name, ids[s], nodes[k], r->num_nodes);
        rc = PERI_ERR_INPUT;
      }
      vertices[k] = nodes[k];
    }
    if (rc == PERI_OK) peri_mesh_add_vertex_set(m, name, ids[s], "node set", r->offset, r->conn, vertices, count);
    free(nodes);
    free(vertices);
  }
  free(ids);
  return rc;
}

typedef struct exodus_reading {
  peri_mesh *m;
  const char *path;
  int dim;
  double thickness, cross_section;
} exodus_reading;

static int read_file(void *context);

/* netCDF allocates and fills arrays at sizes from the file's header before it finds a damaged
 * one (tens of GB): the reading runs in a child process with a bound on its memory first. */
int peri_mesh_read_exodus(peri_mesh *m, const char *path, int dim, double thickness, double cross_section) {
  exodus_reading r = {m, path, dim, thickness, cross_section};
  peri_mesh_init(m, dim); /* (an empty mesh where the guard refuses the file) */
  return peri_guarded_read(path, "Exodus II", read_file, &r);
}

static int read_file(void *context) {
  const exodus_reading *g = context;
  peri_mesh *m = g->m;
  const char *path = g->path;
  const int dim = g->dim;
  const double thickness = g->thickness, cross_section = g->cross_section;
  peri_mesh_init(m, dim);
  ex_opts(EX_DEFAULT); /* errors are reported here, with the file's name */
  reader r = {.path = path};
  int cpu_ws = sizeof(double), io_ws = 0;
  float version = 0;
  r.exoid = ex_open(path, EX_READ, &cpu_ws, &io_ws, &version);
  if (r.exoid < 0) {
    peri_error("%s: cannot open as an Exodus II file (not one, or damaged)", path);
    return PERI_ERR_INPUT;
  }
  ex_set_max_name_length(r.exoid, NAME_LEN);
  char title[MAX_LINE_LENGTH + 1] = "";
  int num_side_sets = 0, status, rc = PERI_OK;
  if ((status = ex_get_init(r.exoid, title, &r.num_dim, &r.num_nodes, &r.num_elem, &r.num_blocks,
                            &r.num_node_sets, &num_side_sets)) < 0) {
    rc = fail(&r, "the header", status);
  } else if (r.num_dim < 1 || r.num_dim > 3 || r.num_nodes < 0 || r.num_elem < 0) {
    peri_error("%s: the header gives %d dimensions, %d nodes, %d elements", path, r.num_dim, r.num_nodes, r.num_elem);
    rc = PERI_ERR_INPUT;
  }
  int *elem_id = NULL, *block_ids = NULL;
  if (rc == PERI_OK) {
    for (int d = 0; d < r.num_dim; ++d) r.coord[d] = peri_calloc((size_t)(r.num_nodes > 0 ? r.num_nodes : 1), sizeof(double));
    if (r.num_nodes > 0 && (status = ex_get_coord(r.exoid, r.coord[0], r.num_dim > 1 ? r.coord[1] : NULL,
                                                  r.num_dim > 2 ? r.coord[2] : NULL)) < 0)
      rc = fail(&r, "the node coordinates", status);
  }
  if (rc == PERI_OK) {
    elem_id = peri_malloc(sizeof(int) * (size_t)(r.num_elem > 0 ? r.num_elem : 1));
    if (r.num_elem > 0 && ex_get_id_map(r.exoid, EX_ELEM_MAP, elem_id) < 0)
      for (int e = 0; e < r.num_elem; ++e) elem_id[e] = e + 1;
    r.offset = peri_calloc((size_t)r.num_elem + 1, sizeof(int64_t));
    rc = read_nodal_volume(&r);
  }
  if (rc == PERI_OK && r.num_blocks > 0) {
    block_ids = peri_malloc(sizeof(int) * (size_t)r.num_blocks);
    if ((status = ex_get_elem_blk_ids(r.exoid, block_ids)) < 0) rc = fail(&r, "the element block ids", status);
    int first = 0;
    for (int b = 0; rc == PERI_OK && b < r.num_blocks; ++b)
      rc = read_block(&r, m, block_ids[b], elem_id, &first, thickness, cross_section);
  }
  if (rc == PERI_OK) rc = read_node_sets(&r, m);
  ex_close(r.exoid);
  for (int d = 0; d < 3; ++d) free(r.coord[d]);
  free(r.nodal_volume);
  free(r.offset);
  free(r.conn);
  free(elem_id);
  free(block_ids);
  if (rc != PERI_OK) peri_mesh_free(m);
  return rc;
}

#endif
