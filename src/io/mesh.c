/* Meshes as peridynamic points: the container the readers fill, the sets of points, and node
 * set files (include/peri/mesh.h). The choice of a reader is in mesh_read.c. */
#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "peri/error.h"
#include "peri/mesh.h"

void peri_mesh_init(peri_mesh *m, int dim) {
  memset(m, 0, sizeof *m);
  m->dim = dim;
}

void peri_mesh_free(peri_mesh *m) {
  free(m->x);
  free(m->volume);
  free(m->block);
  free(m->id);
  for (int b = 0; b < m->n_blocks; ++b) free(m->blocks[b].name);
  free(m->blocks);
  for (int s = 0; s < m->n_sets; ++s) {
    free(m->sets[s].name);
    free(m->sets[s].points);
  }
  free(m->sets);
  peri_mesh_init(m, m->dim);
}

int32_t peri_mesh_add_point(peri_mesh *m, const double x[3], double volume, int32_t block, int64_t id) {
  if (m->n == m->capacity) {
    m->capacity = m->capacity ? 2 * m->capacity : 1024;
    m->x = peri_realloc(m->x, sizeof(double) * 3 * (size_t)m->capacity);
    m->volume = peri_realloc(m->volume, sizeof(double) * (size_t)m->capacity);
    m->block = peri_realloc(m->block, sizeof(int32_t) * (size_t)m->capacity);
    m->id = peri_realloc(m->id, sizeof(int64_t) * (size_t)m->capacity);
  }
  const int32_t k = m->n++;
  for (int d = 0; d < 3; ++d) m->x[3 * (size_t)k + d] = d < m->dim ? x[d] : 0.0;
  m->volume[k] = volume;
  m->block[k] = block;
  m->id[k] = id;
  return k;
}

int32_t peri_mesh_block_index(peri_mesh *m, int64_t id, const char *name) {
  for (int b = 0; b < m->n_blocks; ++b)
    if (m->blocks[b].id == id) return b;
  m->blocks = peri_realloc(m->blocks, sizeof(peri_mesh_block) * (size_t)(m->n_blocks + 1));
  peri_mesh_block *b = &m->blocks[m->n_blocks];
  if (name && *name) {
    b->name = peri_strdup(name);
  } else {
    char made[64];
    snprintf(made, sizeof made, "block_%lld", (long long)id);
    b->name = peri_strdup(made);
  }
  b->id = id;
  return m->n_blocks++;
}

static int by_index(const void *a, const void *b) {
  int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
  return (x > y) - (x < y);
}

peri_mesh_set *peri_mesh_add_set(peri_mesh *m, const char *name, int64_t id, const char *kind,
                                 const int32_t *points, int32_t count) {
  m->sets = peri_realloc(m->sets, sizeof(peri_mesh_set) * (size_t)(m->n_sets + 1));
  peri_mesh_set *s = &m->sets[m->n_sets++];
  s->name = peri_strdup(name);
  s->id = id;
  s->kind = kind;
  s->points = peri_malloc(sizeof(int32_t) * (size_t)(count > 0 ? count : 1));
  if (count > 0) memcpy(s->points, points, sizeof(int32_t) * (size_t)count);
  qsort(s->points, (size_t)count, sizeof(int32_t), by_index);
  int32_t kept = 0;
  for (int32_t a = 0; a < count; ++a)
    if (kept == 0 || s->points[kept - 1] != s->points[a]) s->points[kept++] = s->points[a];
  s->count = kept;
  return s;
}

static int by_vertex(const void *a, const void *b) {
  int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
  return (x > y) - (x < y);
}

peri_mesh_set *peri_mesh_add_vertex_set(peri_mesh *m, const char *name, int64_t id, const char *kind,
                                        const int64_t *offset, const int64_t *conn,
                                        const int64_t *vertices, int64_t n_vertices) {
  int64_t *sorted = peri_malloc(sizeof(int64_t) * (size_t)(n_vertices > 0 ? n_vertices : 1));
  if (n_vertices > 0) memcpy(sorted, vertices, sizeof(int64_t) * (size_t)n_vertices);
  qsort(sorted, (size_t)n_vertices, sizeof(int64_t), by_vertex);
  int32_t *points = peri_malloc(sizeof(int32_t) * (size_t)(m->n > 0 ? m->n : 1));
  int32_t count = 0;
  for (int32_t k = 0; k < m->n; ++k)
    for (int64_t c = offset[k]; c < offset[k + 1]; ++c)
      if (n_vertices > 0 && bsearch(&conn[c], sorted, (size_t)n_vertices, sizeof(int64_t), by_vertex)) {
        points[count++] = k;
        break;
      }
  peri_mesh_set *s = peri_mesh_add_set(m, name, id, kind, points, count);
  free(points);
  free(sorted);
  return s;
}

const peri_mesh_set *peri_mesh_find_set(const peri_mesh *m, const char *name) {
  for (int s = 0; s < m->n_sets; ++s)
    if (strcmp(m->sets[s].name, name) == 0) return &m->sets[s];
  const peri_mesh_set *found = NULL;
  for (int s = 0; s < m->n_sets; ++s)
    if (strcasecmp(m->sets[s].name, name) == 0) {
      if (found) return NULL;
      found = &m->sets[s];
    }
  return found;
}

/* ---------------------------------------------------------------- node set files */

static int by_id(const void *a, const void *b) {
  const int64_t *x = a, *y = b;
  return (x[0] > y[0]) - (x[0] < y[0]);
}

int peri_node_set_file_read(const peri_mesh *m, const char *path, int32_t **points, int32_t *count) {
  *points = NULL;
  *count = 0;
  FILE *fp = fopen(path, "r");
  if (!fp) {
    peri_error("cannot open node set file '%s': %s", path, strerror(errno));
    return PERI_ERR_INPUT;
  }
  /* (id, index) pairs sorted by id, for the look-up of each listed id */
  int64_t *pairs = peri_malloc(sizeof(int64_t) * 2 * (size_t)(m->n > 0 ? m->n : 1));
  for (int32_t k = 0; k < m->n; ++k) pairs[2 * k] = m->id[k], pairs[2 * k + 1] = k;
  qsort(pairs, (size_t)m->n, 2 * sizeof(int64_t), by_id);
  int32_t cap = 1024, n = 0;
  int32_t *out = peri_malloc(sizeof(int32_t) * (size_t)cap);
  char *line = NULL;
  size_t linecap = 0;
  long lineno = 0;
  int rc = PERI_OK;
  while (rc == PERI_OK && getline(&line, &linecap, fp) >= 0) {
    lineno++;
    char *hash = strchr(line, '#');
    if (hash) *hash = '\0';
    char *s = line;
    while (isspace((unsigned char)*s)) s++;
    if (strncmp(s, "header:", 7) == 0) continue; /* PeriLab's "header: global_id" */
    for (;;) {
      while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n' || *s == ',') s++;
      if (!*s) break;
      char *end;
      errno = 0;
      long long v = strtoll(s, &end, 10);
      if (end == s || errno || (*end && !strchr(" \t\r\n,", *end))) {
        char *e = s;
        while (*e && !strchr(" \t\r\n,", *e)) e++;
        *e = '\0';
        peri_error("%s:%ld: expected node ids (integers), got '%s'", path, lineno, s);
        rc = PERI_ERR_INPUT;
        break;
      }
      int64_t key[2] = {v, 0};
      const int64_t *hit = m->n > 0 ? bsearch(key, pairs, (size_t)m->n, 2 * sizeof(int64_t), by_id) : NULL;
      if (!hit) {
        peri_error("%s:%ld: node %lld does not exist (the discretization's ids run from %lld to %lld)",
                   path, lineno, v, m->n > 0 ? (long long)pairs[0] : 0LL,
                   m->n > 0 ? (long long)pairs[2 * (m->n - 1)] : 0LL);
        rc = PERI_ERR_INPUT;
        break;
      }
      if (n == cap) out = peri_realloc(out, sizeof(int32_t) * (size_t)(cap *= 2));
      out[n++] = (int32_t)hit[1];
      s = end;
    }
  }
  free(line);
  fclose(fp);
  free(pairs);
  if (rc != PERI_OK) {
    free(out);
    return rc;
  }
  qsort(out, (size_t)n, sizeof(int32_t), by_index);
  int32_t kept = 0;
  for (int32_t a = 0; a < n; ++a)
    if (kept == 0 || out[kept - 1] != out[a]) out[kept++] = out[a];
  *points = out;
  *count = kept;
  return PERI_OK;
}
