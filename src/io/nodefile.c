/* Node files in the Peridigm/PeriLab text format: "x y [z] block volume" per line. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/discretize.h"
#include "peri/error.h"

static const char *const columns[] = {"", "x block volume", "x y block volume",
                                      "x y z block volume"};

int peri_nodefile_read(peri_particles *p, const char *path, int dim,
                       const int32_t *block_to_material, int n_blocks) {
  peri_particles_init(p, dim);
  if (dim < 1 || dim > 3) {
    peri_error("%s: dimension must be 1, 2 or 3, got %d", path, dim);
    return PERI_ERR_INPUT;
  }
  FILE *fp = fopen(path, "r");
  if (!fp) {
    peri_error("cannot open node file '%s': %s", path, strerror(errno));
    return PERI_ERR_INPUT;
  }
  int want = dim + 2, rc = PERI_OK;
  char *line = NULL;
  size_t cap = 0;
  long lineno = 0;
  while (getline(&line, &cap, fp) >= 0) {
    lineno++;
    char *hash = strchr(line, '#');
    if (hash) *hash = '\0';
    double v[5];
    int got = 0;
    char *s = line, *bad = NULL;
    for (;;) {
      while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n' || *s == ',') s++;
      if (!*s) break;
      char *end;
      double val = strtod(s, &end);
      if (end == s || !isfinite(val)) {
        bad = s;
        break;
      }
      if (got < 5) v[got] = val;
      got++;
      s = end;
    }
    if (got == 0 && !bad) continue; /* blank or comment line */
    if (bad) {
      char *e = bad;
      while (*e && *e != ' ' && *e != '\t' && *e != '\r' && *e != '\n') e++;
      *e = '\0';
      peri_error("%s:%ld: expected %d numbers (%s), got '%s'", path, lineno, want, columns[dim],
                 bad);
      rc = PERI_ERR_INPUT;
      break;
    }
    if (got != want) {
      peri_error("%s:%ld: expected %d numbers (%s), got %d", path, lineno, want, columns[dim], got);
      rc = PERI_ERR_INPUT;
      break;
    }
    double blk = v[dim], vol = v[dim + 1];
    if (blk != floor(blk) || blk < 1 || blk > INT32_MAX) {
      peri_error("%s:%ld: block id must be a positive integer, got %g", path, lineno, blk);
      rc = PERI_ERR_INPUT;
      break;
    }
    if ((block_to_material || n_blocks > 0) && blk > n_blocks) {
      peri_error("%s:%ld: block %g is not defined (the deck defines blocks 1..%d)", path, lineno,
                 blk, n_blocks);
      rc = PERI_ERR_INPUT;
      break;
    }
    if (!(vol > 0)) {
      peri_error("%s:%ld: node volume must be positive, got %g", path, lineno, vol);
      rc = PERI_ERR_INPUT;
      break;
    }
    double x[3] = {0, 0, 0};
    for (int d = 0; d < dim; d++) x[d] = v[d];
    int32_t b = (int32_t)blk;
    int32_t mat = block_to_material ? block_to_material[b - 1] : 0;
    peri_particles_add(p, x, vol, mat, b);
  }
  if (rc == PERI_OK && ferror(fp)) {
    peri_error("error reading node file '%s': %s", path, strerror(errno));
    rc = PERI_ERR_INPUT;
  }
  if (rc == PERI_OK && p->n == 0) {
    peri_error("%s: the node file has no nodes", path);
    rc = PERI_ERR_INPUT;
  }
  free(line);
  fclose(fp);
  if (rc != PERI_OK) peri_particles_free(p);
  return rc;
}
