/* Node files: one node per line. Three layouts: the Peridigm/PeriLab text format
 * "x y [z] block volume" without a header; PeriLab's "header: x y z block_id volume" line
 * naming the columns; and a first row of column names (CSV, comma-separated). */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "peri/discretize.h"
#include "peri/error.h"
#include "peri/mesh.h"
#include "peri/nodefile.h"

enum { COL_X, COL_Y, COL_Z, COL_BLOCK, COL_VOLUME, COL_OTHER };
enum { MAX_COLUMNS = 64 };

static const char *const columns[] = {"", "x block volume", "x y block volume",
                                      "x y z block volume"};

static bool is_separator(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == ','; }

/* A column name: x, y, z, block_id (or block), volume; anything else is read and ignored. */
static int column_kind(const char *name) {
  static const char *const names[] = {"x", "y", "z", "block_id", "volume"};
  for (int k = 0; k < 5; ++k)
    if (strcasecmp(name, names[k]) == 0) return k;
  if (strcasecmp(name, "block") == 0) return COL_BLOCK;
  return COL_OTHER;
}

/* Splits a header into column names (quotes removed); returns their count or -1. */
static int split_header(char *s, int kind[MAX_COLUMNS], char names[], size_t names_cap) {
  int n = 0;
  names[0] = '\0';
  for (;;) {
    while (*s && is_separator(*s)) s++;
    if (!*s) break;
    char *start = s;
    while (*s && !is_separator(*s)) s++;
    char save = *s;
    *s = '\0';
    if (*start == '"' || *start == '\'') start++;
    size_t len = strlen(start);
    if (len > 0 && (start[len - 1] == '"' || start[len - 1] == '\'')) start[len - 1] = '\0';
    if (n == MAX_COLUMNS) return -1;
    kind[n++] = column_kind(start);
    snprintf(names + strlen(names), names_cap - strlen(names), "%s%s", n > 1 ? " " : "", start);
    *s = save;
  }
  return n;
}

/* Reads the file into m. A block id beyond max_block (when > 0) is an error at its line. */
static int read_text(peri_mesh *m, const char *path, int dim, int max_block) {
  peri_mesh_init(m, dim);
  if (dim < 1 || dim > 3) {
    peri_error("%s: dimension must be 1, 2 or 3, got %d", path, dim);
    return PERI_ERR_INPUT;
  }
  FILE *fp = fopen(path, "r");
  if (!fp) {
    peri_error("cannot open node file '%s': %s", path, strerror(errno));
    return PERI_ERR_INPUT;
  }
  /* without a header the columns are x [y [z]] block volume */
  int kind[MAX_COLUMNS], ncol = dim + 2;
  for (int d = 0; d < dim; ++d) kind[d] = d;
  kind[dim] = COL_BLOCK, kind[dim + 1] = COL_VOLUME;
  char described[512];
  snprintf(described, sizeof described, "%s", columns[dim]);
  bool first = true;
  int rc = PERI_OK;
  char *line = NULL;
  size_t cap = 0;
  long lineno = 0;
  int64_t node = 0;
  while (getline(&line, &cap, fp) >= 0) {
    lineno++;
    char *hash = strchr(line, '#');
    if (hash) *hash = '\0';
    char *s = line;
    while (*s && is_separator(*s)) s++;
    if (!*s) continue; /* blank or comment line */
    bool header = strncmp(s, "header:", 7) == 0;
    if (first && !header) { /* a first row of names (CSV) */
      char *end;
      strtod(s, &end);
      header = end == s;
    } else if (!first && header) {
      peri_error("%s:%ld: a second header line", path, lineno);
      rc = PERI_ERR_INPUT;
      break;
    }
    first = false;
    if (header) {
      if (strncmp(s, "header:", 7) == 0) s += 7;
      ncol = split_header(s, kind, described, sizeof described);
      bool has[COL_OTHER] = {false};
      for (int c = 0; c < ncol; ++c)
        if (kind[c] != COL_OTHER) {
          if (has[kind[c]]) {
            peri_error("%s:%ld: column '%s' appears twice in the header", path, lineno,
                       (const char *[]){"x", "y", "z", "block_id", "volume"}[kind[c]]);
            rc = PERI_ERR_INPUT;
          }
          has[kind[c]] = true;
        }
      static const char *const need[] = {"x", "y", "z", "block_id", "volume"};
      for (int k = 0; rc == PERI_OK && k < COL_OTHER; ++k)
        if (!has[k] && (k >= COL_BLOCK || k < dim)) {
          peri_error("%s:%ld: the header '%s' has no column '%s' (a %dD node file needs %s)", path,
                     lineno, described, need[k], dim, columns[dim]);
          rc = PERI_ERR_INPUT;
        }
      if (ncol < 0) {
        peri_error("%s:%ld: more than %d columns in the header", path, lineno, MAX_COLUMNS);
        rc = PERI_ERR_INPUT;
      }
      if (rc != PERI_OK) break;
      continue;
    }
    double v[MAX_COLUMNS];
    int got = 0;
    char *bad = NULL;
    for (;;) {
      while (*s && is_separator(*s)) s++;
      if (!*s) break;
      char *end;
      double val = strtod(s, &end);
      if (end == s || !isfinite(val) || (*end && !is_separator(*end))) {
        bad = s;
        break;
      }
      if (got < MAX_COLUMNS) v[got] = val;
      got++;
      s = end;
    }
    if (bad) {
      char *e = bad;
      while (*e && !is_separator(*e)) e++;
      *e = '\0';
      peri_error("%s:%ld: expected %d numbers (%s), got '%s'", path, lineno, ncol, described, bad);
      rc = PERI_ERR_INPUT;
      break;
    }
    if (got != ncol) {
      peri_error("%s:%ld: expected %d numbers (%s), got %d", path, lineno, ncol, described, got);
      rc = PERI_ERR_INPUT;
      break;
    }
    double x[3] = {0, 0, 0}, blk = 0, vol = 0;
    for (int c = 0; c < ncol; ++c) {
      if (kind[c] <= COL_Z) x[kind[c]] = v[c];
      else if (kind[c] == COL_BLOCK) blk = v[c];
      else if (kind[c] == COL_VOLUME) vol = v[c];
    }
    for (int d = dim; d < 3; ++d)
      if (x[d] != 0.0) {
        peri_error("%s:%ld: %c = %g, but the deck has dimension %d", path, lineno, "xyz"[d], x[d], dim);
        rc = PERI_ERR_INPUT;
      }
    if (rc != PERI_OK) break;
    if (blk != floor(blk) || blk < 1 || blk > INT32_MAX) {
      peri_error("%s:%ld: block id must be a positive integer, got %g", path, lineno, blk);
      rc = PERI_ERR_INPUT;
      break;
    }
    if (max_block > 0 && blk > max_block) {
      peri_error("%s:%ld: block %g is not defined (the deck defines blocks 1..%d)", path, lineno,
                 blk, max_block);
      rc = PERI_ERR_INPUT;
      break;
    }
    if (!(vol > 0)) {
      peri_error("%s:%ld: node volume must be positive, got %g", path, lineno, vol);
      rc = PERI_ERR_INPUT;
      break;
    }
    peri_mesh_add_point(m, x, vol, peri_mesh_block_index(m, (int64_t)blk, NULL), ++node);
  }
  if (rc == PERI_OK && ferror(fp)) {
    peri_error("error reading node file '%s': %s", path, strerror(errno));
    rc = PERI_ERR_INPUT;
  }
  if (rc == PERI_OK && m->n == 0) {
    peri_error("%s: the node file has no nodes", path);
    rc = PERI_ERR_INPUT;
  }
  free(line);
  fclose(fp);
  if (rc != PERI_OK) peri_mesh_free(m);
  return rc;
}

int peri_mesh_read_text(peri_mesh *m, const char *path, int dim) { return read_text(m, path, dim, 0); }

int peri_nodefile_read(peri_particles *p, const char *path, int dim,
                       const int32_t *block_to_material, int n_blocks) {
  peri_particles_init(p, dim);
  peri_mesh m;
  if (block_to_material && n_blocks <= 0) {
    peri_error("%s: no blocks defined for the node file", path);
    return PERI_ERR_INPUT;
  }
  int rc = read_text(&m, path, dim, n_blocks > 0 ? n_blocks : 0);
  if (rc != PERI_OK) return rc;
  for (int32_t k = 0; k < m.n; ++k) {
    int32_t b = (int32_t)m.blocks[m.block[k]].id;
    peri_particles_add(p, &m.x[3 * (size_t)k], m.volume[k], block_to_material ? block_to_material[b - 1] : 0, b);
  }
  peri_mesh_free(&m);
  return PERI_OK;
}
