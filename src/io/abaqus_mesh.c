/* Abaqus input files (.inp), as PeriLab reads them: one point per element of the deck's
 * dimension, at its centroid with its volume (area times thickness in 2D). Read: *NODE,
 * *ELEMENT (TYPE=, ELSET=), *NSET and *ELSET (with GENERATE, and names of earlier sets as
 * members); every other keyword's data is skipped. The blocks are the ELSET= of the *ELEMENT
 * lines, numbered 1, 2, ... in order of appearance. An *NSET is a set of the points with a
 * node in it; an *ELSET the set of its elements (a lower-dimensional element in it, such as a
 * boundary edge, adds the points with a node on it). One part at most; instances must not move. */
#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "peri/error.h"
#include "peri/mesh.h"
#include "element_geometry.h"

typedef struct element_type {
  const char *name;
  peri_element_shape shape;
  int nodes;
} element_type;

/* Base names; a suffix of letters (C3D8R, CPS4I, C3D10H, ...) is allowed. */
static const element_type types[] = {
    {"C3D4", PERI_ELEMENT_TET, 4},      {"C3D10", PERI_ELEMENT_TET, 10},   {"C3D8", PERI_ELEMENT_HEX, 8},
    {"C3D20", PERI_ELEMENT_HEX, 20},    {"C3D27", PERI_ELEMENT_HEX, 27},   {"C3D6", PERI_ELEMENT_WEDGE, 6},
    {"C3D15", PERI_ELEMENT_WEDGE, 15},  {"C3D5", PERI_ELEMENT_PYRAMID, 5}, {"CPS3", PERI_ELEMENT_TRI, 3},
    {"CPE3", PERI_ELEMENT_TRI, 3},      {"CAX3", PERI_ELEMENT_TRI, 3},     {"S3", PERI_ELEMENT_TRI, 3},
    {"M3D3", PERI_ELEMENT_TRI, 3},      {"DC2D3", PERI_ELEMENT_TRI, 3},    {"CPS6", PERI_ELEMENT_TRI, 6},
    {"CPE6", PERI_ELEMENT_TRI, 6},      {"CAX6", PERI_ELEMENT_TRI, 6},     {"STRI65", PERI_ELEMENT_TRI, 6},
    {"CPS4", PERI_ELEMENT_QUAD, 4},     {"CPE4", PERI_ELEMENT_QUAD, 4},    {"CAX4", PERI_ELEMENT_QUAD, 4},
    {"S4", PERI_ELEMENT_QUAD, 4},       {"M3D4", PERI_ELEMENT_QUAD, 4},    {"DC2D4", PERI_ELEMENT_QUAD, 4},
    {"CPS8", PERI_ELEMENT_QUAD, 8},     {"CPE8", PERI_ELEMENT_QUAD, 8},    {"CAX8", PERI_ELEMENT_QUAD, 8},
    {"S8", PERI_ELEMENT_QUAD, 8},       {"T2D2", PERI_ELEMENT_LINE, 2},    {"T3D2", PERI_ELEMENT_LINE, 2},
    {"B21", PERI_ELEMENT_LINE, 2},      {"B31", PERI_ELEMENT_LINE, 2},     {"T2D3", PERI_ELEMENT_LINE, 3},
    {"T3D3", PERI_ELEMENT_LINE, 3},     {"B22", PERI_ELEMENT_LINE, 3},     {"B32", PERI_ELEMENT_LINE, 3},
};

static const element_type *find_type(const char *name) {
  for (size_t k = 0; k < sizeof types / sizeof types[0]; ++k) {
    size_t len = strlen(types[k].name);
    if (strncasecmp(name, types[k].name, len) == 0) {
      const char *rest = name + len;
      while (isalpha((unsigned char)*rest)) rest++;
      if (!*rest) return &types[k];
    }
  }
  return NULL;
}

typedef struct id_list {
  int64_t *v;
  int64_t n, cap;
} id_list;

static void push(id_list *l, int64_t x) {
  if (l->n == l->cap) l->v = peri_realloc(l->v, sizeof(int64_t) * (size_t)(l->cap = l->cap ? 2 * l->cap : 64));
  l->v[l->n++] = x;
}

typedef struct named_set {
  char *name;
  bool elements; /* an ELSET, else an NSET */
  long line;
  id_list ids;
} named_set;

typedef struct inp {
  const char *path;
  int dim;
  id_list node_id;
  double *coord;
  int64_t coord_cap;
  /* elements: id, type, line, nodes (offset into conn), block name index or -1 */
  id_list elem_id, elem_off, conn;
  const element_type **elem_type;
  long *elem_line;
  int *elem_block;
  int64_t elem_cap;
  char **block_names;
  int n_block_names;
  named_set *sets;
  int n_sets;
} inp;

static int by_first(const void *a, const void *b) {
  const int64_t *x = a, *y = b;
  return (x[0] > y[0]) - (x[0] < y[0]);
}

/* Keyword parameters: "KEY=value" pairs after the keyword, case-insensitive. */
static bool param(const char *line, const char *key, char *out, size_t cap) {
  const char *s = strchr(line, ',');
  size_t klen = strlen(key);
  while (s) {
    s++;
    while (*s == ' ' || *s == '\t') s++;
    if (strncasecmp(s, key, klen) == 0) {
      const char *p = s + klen;
      while (*p == ' ') p++;
      if (*p == '=' || *p == ',' || *p == '\0' || *p == '\r' || *p == '\n') {
        size_t n = 0;
        if (*p == '=') {
          p++;
          while (*p == ' ' || *p == '"') p++;
          while (p[n] && p[n] != ',' && p[n] != '"' && p[n] != '\r' && p[n] != '\n') n++;
          while (n > 0 && p[n - 1] == ' ') n--;
        }
        if (n >= cap) n = cap - 1;
        memcpy(out, p, n);
        out[n] = '\0';
        return true;
      }
    }
    s = strchr(s, ',');
  }
  return false;
}

static named_set *set_named(inp *a, const char *name, bool elements, long line) {
  for (int k = 0; k < a->n_sets; ++k)
    if (a->sets[k].elements == elements && strcasecmp(a->sets[k].name, name) == 0) return &a->sets[k];
  a->sets = peri_realloc(a->sets, sizeof(named_set) * (size_t)(a->n_sets + 1));
  named_set *s = &a->sets[a->n_sets++];
  memset(s, 0, sizeof *s);
  s->name = peri_strdup(name);
  s->elements = elements;
  s->line = line;
  return s;
}

/* Splits a data line into comma-separated fields (spaces trimmed); returns their count. */
static int fields(char *line, char **out, int cap) {
  int n = 0;
  char *s = line;
  while (*s && n < cap) {
    while (*s == ' ' || *s == '\t') s++;
    char *start = s;
    while (*s && *s != ',' && *s != '\r' && *s != '\n') s++;
    char *end = s;
    while (end > start && (end[-1] == ' ' || end[-1] == '\t')) end--;
    bool last = *s != ',';
    *end = '\0';
    if (*start || !last) out[n++] = start;
    if (last) break;
    s++;
  }
  while (n > 0 && !*out[n - 1]) n--; /* a trailing comma */
  return n;
}

static bool integer(const char *s, int64_t *v) {
  char *end;
  errno = 0;
  long long x = strtoll(s, &end, 10);
  if (end == s || *end || errno) return false;
  *v = x;
  return true;
}

static bool number(const char *s, double *v) {
  char *end;
  *v = strtod(s, &end);
  return end != s && !*end;
}

enum { K_NONE, K_NODE, K_ELEMENT, K_NSET, K_ELSET, K_INSTANCE, K_SKIP };

static int parse(inp *a, FILE *fp) {
  char *line = NULL;
  size_t cap = 0;
  long lineno = 0;
  int keyword = K_NONE, parts = 0, rc = PERI_OK, block = -1;
  const element_type *etype = NULL;
  named_set *cur = NULL, *nset_of_nodes = NULL;
  bool generate = false;
  int64_t pending = -1; /* an element whose node list continues on the next line */
  int64_t pending_need = 0;
  while (rc == PERI_OK && getline(&line, &cap, fp) >= 0) {
    lineno++;
    char *s = line;
    while (*s == ' ' || *s == '\t') s++;
    if (s[0] == '*' && s[1] == '*') continue; /* comment */
    if (!*s || *s == '\r' || *s == '\n') continue;
    if (*s == '*') {
      if (pending >= 0) {
        peri_error("%s:%ld: element %lld has too few nodes", a->path, lineno - 1, (long long)a->elem_id.v[pending]);
        { free(line); return PERI_ERR_INPUT; }
      }
      char kw[64] = "";
      size_t n = 0;
      for (const char *p = s + 1; *p && *p != ',' && *p != '\r' && *p != '\n' && n + 1 < sizeof kw; ++p) kw[n++] = *p;
      while (n > 0 && kw[n - 1] == ' ') n--;
      kw[n] = '\0';
      char value[256];
      keyword = K_SKIP;
      cur = nset_of_nodes = NULL;
      generate = param(s, "GENERATE", value, sizeof value);
      if (!strcasecmp(kw, "NODE")) {
        keyword = K_NODE;
        if (param(s, "NSET", value, sizeof value)) nset_of_nodes = set_named(a, value, false, lineno);
      } else if (!strcasecmp(kw, "ELEMENT")) {
        keyword = K_ELEMENT;
        if (!param(s, "TYPE", value, sizeof value)) {
          peri_error("%s:%ld: *ELEMENT without TYPE=", a->path, lineno);
          { free(line); return PERI_ERR_INPUT; }
        }
        etype = find_type(value);
        if (!etype) {
          peri_error("%s:%ld: unknown element type '%s' (peri reads C3D4, C3D8, C3D6, C3D5, C3D10, "
                     "C3D20, CPS3/CPE3/S3, CPS4/CPE4/S4, CPS6, CPS8, T2D2/T3D2, with letter suffixes)",
                     a->path, lineno, value);
          { free(line); return PERI_ERR_INPUT; }
        }
        if (peri_element_dim(etype->shape) > a->dim) {
          peri_error("%s:%ld: elements of type %s are %dD, the deck has dimension %d", a->path, lineno,
                     value, peri_element_dim(etype->shape), a->dim);
          { free(line); return PERI_ERR_INPUT; }
        }
        char bname[256] = "";
        if (param(s, "ELSET", bname, sizeof bname)) cur = set_named(a, bname, true, lineno);
        block = -1;
        if (peri_element_dim(etype->shape) == a->dim) {
          for (int b = 0; b < a->n_block_names; ++b)
            if (strcasecmp(a->block_names[b], bname) == 0) block = b;
          if (block < 0) {
            a->block_names = peri_realloc(a->block_names, sizeof(char *) * (size_t)(a->n_block_names + 1));
            a->block_names[a->n_block_names] = peri_strdup(bname);
            block = a->n_block_names++;
          }
        }
      } else if (!strcasecmp(kw, "NSET") || !strcasecmp(kw, "ELSET")) {
        const bool el = !strcasecmp(kw, "ELSET");
        if (!param(s, el ? "ELSET" : "NSET", value, sizeof value) || !*value) {
          peri_error("%s:%ld: *%s without a name (%s=)", a->path, lineno, kw, el ? "ELSET" : "NSET");
          { free(line); return PERI_ERR_INPUT; }
        }
        keyword = el ? K_ELSET : K_NSET;
        cur = set_named(a, value, el, lineno);
      } else if (!strcasecmp(kw, "PART")) {
        if (++parts > 1) {
          peri_error("%s:%ld: a second *PART; peri reads one part (or a file without parts)", a->path, lineno);
          { free(line); return PERI_ERR_INPUT; }
        }
      } else if (!strcasecmp(kw, "INSTANCE")) {
        keyword = K_INSTANCE;
      } else if (!strcasecmp(kw, "INCLUDE")) {
        peri_error("%s:%ld: *INCLUDE is not read; write the included lines into the file", a->path, lineno);
        { free(line); return PERI_ERR_INPUT; }
      }
      continue;
    }
    char *f[64];
    const int nf = fields(s, f, 64);
    if (nf == 0) continue;
    switch (keyword) {
    case K_NODE: {
      int64_t id;
      double x[3] = {0, 0, 0};
      if (nf < 2 || nf > 4 || !integer(f[0], &id)) {
        peri_error("%s:%ld: expected 'node id, x, y[, z]'", a->path, lineno);
        { free(line); return PERI_ERR_INPUT; }
      }
      for (int k = 1; k < nf; ++k)
        if (!number(f[k], &x[k - 1])) {
          peri_error("%s:%ld: node %lld: '%s' is not a number", a->path, lineno, (long long)id, f[k]);
          { free(line); return PERI_ERR_INPUT; }
        }
      push(&a->node_id, id);
      if (a->node_id.n > a->coord_cap) a->coord = peri_realloc(a->coord, sizeof(double) * 3 * (size_t)(a->coord_cap = 2 * a->node_id.n + 64));
      memcpy(&a->coord[3 * (a->node_id.n - 1)], x, sizeof x);
      if (nset_of_nodes) push(&nset_of_nodes->ids, id);
      break;
    }
    case K_ELEMENT: {
      int k = 0;
      if (pending < 0) {
        int64_t id;
        if (!integer(f[0], &id)) {
          peri_error("%s:%ld: expected 'element id, node, node, ...', got '%s'", a->path, lineno, f[0]);
          { free(line); return PERI_ERR_INPUT; }
        }
        if (a->elem_id.n == a->elem_cap) {
          a->elem_cap = 2 * a->elem_cap + 64;
          a->elem_type = peri_realloc(a->elem_type, sizeof(*a->elem_type) * (size_t)a->elem_cap);
          a->elem_line = peri_realloc(a->elem_line, sizeof(long) * (size_t)a->elem_cap);
          a->elem_block = peri_realloc(a->elem_block, sizeof(int) * (size_t)a->elem_cap);
        }
        pending = a->elem_id.n;
        push(&a->elem_id, id);
        push(&a->elem_off, a->conn.n);
        a->elem_type[pending] = etype;
        a->elem_line[pending] = lineno;
        a->elem_block[pending] = block;
        pending_need = etype->nodes;
        if (cur) push(&cur->ids, id);
        k = 1;
      }
      for (; k < nf; ++k) {
        int64_t node;
        if (!integer(f[k], &node)) {
          peri_error("%s:%ld: element %lld: '%s' is not a node id", a->path, lineno,
                     (long long)a->elem_id.v[pending], f[k]);
          { free(line); return PERI_ERR_INPUT; }
        }
        if (pending_need == 0) {
          peri_error("%s:%ld: element %lld: more than %d nodes for type %s", a->path, lineno,
                     (long long)a->elem_id.v[pending], etype->nodes, etype->name);
          { free(line); return PERI_ERR_INPUT; }
        }
        push(&a->conn, node);
        pending_need--;
      }
      if (pending_need == 0) pending = -1;
      break;
    }
    case K_NSET:
    case K_ELSET: {
      if (generate) {
        int64_t g[3] = {0, 0, 1};
        if (nf < 2 || nf > 3 || !integer(f[0], &g[0]) || !integer(f[1], &g[1]) || (nf == 3 && !integer(f[2], &g[2])) ||
            g[2] < 1 || g[1] < g[0]) {
          peri_error("%s:%ld: expected 'first, last[, increment]' with GENERATE", a->path, lineno);
          { free(line); return PERI_ERR_INPUT; }
        }
        if ((g[1] - g[0]) / g[2] > 100000000) {
          peri_error("%s:%ld: GENERATE range too long", a->path, lineno);
          { free(line); return PERI_ERR_INPUT; }
        }
        for (int64_t v = g[0]; v <= g[1]; v += g[2]) push(&cur->ids, v);
        break;
      }
      for (int k = 0; k < nf; ++k) {
        int64_t v;
        if (integer(f[k], &v)) {
          push(&cur->ids, v);
          continue;
        }
        named_set *other = NULL; /* a set named as a member */
        for (int o = 0; o < a->n_sets; ++o)
          if (&a->sets[o] != cur && a->sets[o].elements == (keyword == K_ELSET) && !strcasecmp(a->sets[o].name, f[k]))
            other = &a->sets[o];
        if (!other) {
          peri_error("%s:%ld: '%s' is neither an id nor an earlier %s", a->path, lineno, f[k],
                     keyword == K_ELSET ? "ELSET" : "NSET");
          { free(line); return PERI_ERR_INPUT; }
        }
        for (int64_t j = 0; j < other->ids.n; ++j) push(&cur->ids, other->ids.v[j]);
      }
      break;
    }
    case K_INSTANCE:
      peri_error("%s:%ld: an *INSTANCE that is moved (translated or rotated) is not read; "
                 "write the mesh in place", a->path, lineno);
      { free(line); return PERI_ERR_INPUT; }
    default: break;
    }
  }
  free(line);
  if (pending >= 0) {
    peri_error("%s:%ld: element %lld has too few nodes (the file ends)", a->path, lineno, (long long)a->elem_id.v[pending]);
    rc = PERI_ERR_INPUT;
  }
  return rc;
}

/* index of id in sorted (id, index) pairs, or -1 */
static int64_t lookup(const int64_t *pairs, int64_t n, int64_t id) {
  int64_t key[2] = {id, 0};
  const int64_t *hit = n > 0 ? bsearch(key, pairs, (size_t)n, 2 * sizeof(int64_t), by_first) : NULL;
  return hit ? hit[1] : -1;
}

static int build(inp *a, peri_mesh *m, double thickness, double cross_section) {
  const int64_t nn = a->node_id.n, ne = a->elem_id.n;
  push(&a->elem_off, a->conn.n);
  int64_t *nodes = peri_malloc(sizeof(int64_t) * 2 * (size_t)(nn + 1));
  for (int64_t k = 0; k < nn; ++k) nodes[2 * k] = a->node_id.v[k], nodes[2 * k + 1] = k;
  qsort(nodes, (size_t)nn, 2 * sizeof(int64_t), by_first);
  int64_t *elems = peri_malloc(sizeof(int64_t) * 2 * (size_t)(ne + 1));
  for (int64_t k = 0; k < ne; ++k) elems[2 * k] = a->elem_id.v[k], elems[2 * k + 1] = k;
  qsort(elems, (size_t)ne, 2 * sizeof(int64_t), by_first);
  int rc = PERI_OK;
  for (int64_t k = 1; k < nn && rc == PERI_OK; ++k)
    if (nodes[2 * k] == nodes[2 * k - 2]) {
      peri_error("%s: node %lld is defined twice", a->path, (long long)nodes[2 * k]);
      rc = PERI_ERR_INPUT;
    }
  for (int64_t k = 1; k < ne && rc == PERI_OK; ++k)
    if (elems[2 * k] == elems[2 * k - 2]) {
      peri_error("%s: element %lld is defined twice", a->path, (long long)elems[2 * k]);
      rc = PERI_ERR_INPUT;
    }
  /* points: the elements of the deck's dimension; conn keeps node indices for the sets */
  int32_t *point_of = peri_malloc(sizeof(int32_t) * (size_t)(ne + 1));
  int64_t *offset = peri_calloc((size_t)ne + 1, sizeof(int64_t)), *pconn = peri_malloc(sizeof(int64_t) * (size_t)(a->conn.n + 1));
  int64_t np_conn = 0;
  for (int64_t e = 0; e < ne && rc == PERI_OK; ++e) {
    point_of[e] = -1;
    const element_type *t = a->elem_type[e];
    for (int64_t c = a->elem_off.v[e]; c < a->elem_off.v[e + 1]; ++c) {
      const int64_t idx = lookup(nodes, nn, a->conn.v[c]);
      if (idx < 0) {
        peri_error("%s:%ld: element %lld names node %lld, which does not exist", a->path, a->elem_line[e],
                   (long long)a->elem_id.v[e], (long long)a->conn.v[c]);
        rc = PERI_ERR_INPUT;
        break;
      }
      a->conn.v[c] = idx;
    }
    if (rc != PERI_OK || peri_element_dim(t->shape) != a->dim) continue;
    double xyz[24], v = 0, c[3];
    const int corners = peri_element_corners(t->shape);
    for (int k = 0; k < corners; ++k)
      for (int d = 0; d < 3; ++d) xyz[3 * k + d] = a->coord[3 * a->conn.v[a->elem_off.v[e] + k] + d];
    peri_element_measure(t->shape, xyz, &v, c);
    v *= a->dim == 2 ? thickness : a->dim == 1 ? cross_section : 1.0;
    for (int d = a->dim; d < 3; ++d)
      if (c[d] != 0.0) {
        peri_error("%s:%ld: element %lld lies at %c = %g, but the deck has dimension %d", a->path, a->elem_line[e],
                   (long long)a->elem_id.v[e], "xyz"[d], c[d], a->dim);
        rc = PERI_ERR_INPUT;
      }
    if (rc == PERI_OK && !(v > 0.0)) {
      peri_error("%s:%ld: element %lld has volume %g; a degenerate element", a->path, a->elem_line[e],
                 (long long)a->elem_id.v[e], v);
      rc = PERI_ERR_INPUT;
    }
    if (rc != PERI_OK) break;
    const int b = a->elem_block[e];
    const int32_t block = peri_mesh_block_index(m, b + 1, a->block_names[b]);
    point_of[e] = peri_mesh_add_point(m, c, v, block, a->elem_id.v[e]);
    for (int64_t k = a->elem_off.v[e]; k < a->elem_off.v[e + 1]; ++k) pconn[np_conn++] = a->conn.v[k];
    offset[m->n] = np_conn;
  }
  /* the sets */
  for (int s = 0; s < a->n_sets && rc == PERI_OK; ++s) {
    named_set *set = &a->sets[s];
    id_list vertices = {0};
    int32_t *points = peri_malloc(sizeof(int32_t) * (size_t)(set->ids.n + 1)), count = 0;
    for (int64_t k = 0; k < set->ids.n && rc == PERI_OK; ++k) {
      const int64_t idx = lookup(set->elements ? elems : nodes, set->elements ? ne : nn, set->ids.v[k]);
      if (idx < 0) {
        peri_error("%s:%ld: %s '%s' names %s %lld, which does not exist", a->path, set->line,
                   set->elements ? "ELSET" : "NSET", set->name, set->elements ? "element" : "node",
                   (long long)set->ids.v[k]);
        rc = PERI_ERR_INPUT;
      } else if (!set->elements) {
        push(&vertices, idx);
      } else if (point_of[idx] >= 0) {
        points[count++] = point_of[idx];
      } else { /* a boundary element: its nodes */
        for (int64_t c = a->elem_off.v[idx]; c < a->elem_off.v[idx + 1]; ++c) push(&vertices, a->conn.v[c]);
      }
    }
    if (rc == PERI_OK) {
      const char *kind = set->elements ? "ELSET" : "NSET";
      if (vertices.n > 0) {
        peri_mesh_set *vs = peri_mesh_add_vertex_set(m, set->name, 0, kind, offset, pconn, vertices.v, vertices.n);
        int32_t *all = peri_malloc(sizeof(int32_t) * (size_t)(vs->count + count + 1));
        memcpy(all, points, sizeof(int32_t) * (size_t)count);
        memcpy(all + count, vs->points, sizeof(int32_t) * (size_t)vs->count);
        const int32_t total = count + vs->count;
        free(vs->name);
        free(vs->points);
        m->n_sets--;
        peri_mesh_add_set(m, set->name, 0, kind, all, total);
        free(all);
      } else {
        peri_mesh_add_set(m, set->name, 0, kind, points, count);
      }
    }
    free(vertices.v);
    free(points);
  }
  free(point_of);
  free(offset);
  free(pconn);
  free(nodes);
  free(elems);
  return rc;
}

int peri_mesh_read_abaqus(peri_mesh *m, const char *path, int dim, double thickness, double cross_section) {
  peri_mesh_init(m, dim);
  FILE *fp = fopen(path, "r");
  if (!fp) {
    peri_error("cannot open Abaqus file '%s': %s", path, strerror(errno));
    return PERI_ERR_INPUT;
  }
  inp a = {.path = path, .dim = dim};
  int rc = parse(&a, fp);
  fclose(fp);
  if (rc == PERI_OK) rc = build(&a, m, thickness, cross_section);
  free(a.node_id.v);
  free(a.coord);
  free(a.elem_id.v);
  free(a.elem_off.v);
  free(a.conn.v);
  free(a.elem_type);
  free(a.elem_line);
  free(a.elem_block);
  for (int b = 0; b < a.n_block_names; ++b) free(a.block_names[b]);
  free(a.block_names);
  for (int s = 0; s < a.n_sets; ++s) {
    free(a.sets[s].name);
    free(a.sets[s].ids.v);
  }
  free(a.sets);
  if (rc != PERI_OK) peri_mesh_free(m);
  return rc;
}
