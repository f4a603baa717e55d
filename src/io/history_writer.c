/* history.csv: one header line of column names, then one line of values per call. */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif
#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/output.h"

struct peri_history {
  FILE *out;
  char *path;
  int n_columns;
  int digits; /* significant digits of each value */
};

/* CSV quoting (RFC 4180) only where a name would otherwise break the columns. */
static void csv_name_write(FILE *out, const char *name) {
  if (!strpbrk(name, ",\"\r\n")) {
    fputs(name, out);
    return;
  }
  fputc('"', out);
  for (const char *c = name; *c; c++) {
    if (*c == '"') fputc('"', out);
    fputc(*c, out);
  }
  fputc('"', out);
}

/* Flushes so the line reaches the file now: a run that stops keeps what it wrote. */
static int flush_line(peri_history *h) {
  if (fflush(h->out) != 0 || ferror(h->out)) {
    peri_error("cannot write '%s': %s", h->path, strerror(errno ? errno : EIO));
    return PERI_ERR_RUN;
  }
  return 0;
}

peri_history *peri_history_open(const char *path, int n_columns, const char *const *names) {
  FILE *out = fopen(path, "w");
  if (!out) {
    peri_error("cannot write '%s': %s", path, strerror(errno));
    return NULL;
  }
  peri_history *h = peri_malloc(sizeof *h);
  h->out = out;
  h->path = peri_strdup(path);
  h->n_columns = n_columns;
  h->digits = 10;
  errno = 0;
  for (int c = 0; c < n_columns; c++) {
    if (c > 0) fputc(',', out);
    csv_name_write(out, names[c]);
  }
  fputc('\n', out);
  if (flush_line(h) != 0) {
    peri_history_close(h);
    return NULL;
  }
  return h;
}

int peri_history_write(peri_history *h, const double *values) {
  errno = 0;
  for (int c = 0; c < h->n_columns; c++) {
    if (c > 0) fputc(',', h->out);
    fprintf(h->out, "%.*g", h->digits, values[c]);
  }
  fputc('\n', h->out);
  return flush_line(h);
}

void peri_history_set_digits(peri_history *h, int digits) { h->digits = digits; }

void peri_history_close(peri_history *h) {
  if (!h) return;
  errno = 0;
  if (fclose(h->out) != 0) peri_error("cannot write '%s': %s", h->path, strerror(errno));
  free(h->path);
  free(h);
}

peri_history *peri_history_open_in(const char *directory, int n_columns, char **names) {
  size_t len = strlen(directory) + sizeof "/history.csv";
  char *path = malloc(len);
  peri_history *h = NULL;
  if (path) {
    snprintf(path, len, "%s/history.csv", directory);
    h = peri_history_open(path, n_columns, (const char *const *)names);
    free(path);
  }
  for (int j = 0; j < n_columns; ++j) free(names[j]);
  free(names);
  return h;
}

int peri_history_units_write(const char *directory, int n_columns, char *const *names, const char *const *units) {
  size_t len = strlen(directory) + sizeof "/history_units.csv";
  char *path = peri_malloc(len);
  snprintf(path, len, "%s/history_units.csv", directory);
  FILE *out = fopen(path, "w");
  if (!out) {
    peri_error("cannot write '%s': %s", path, strerror(errno));
    free(path);
    return PERI_ERR_RUN;
  }
  errno = 0;
  for (int row = 0; row < 2; ++row) {
    for (int c = 0; c < n_columns; c++) {
      if (c > 0) fputc(',', out);
      csv_name_write(out, row == 0 ? names[c] : units[c]);
    }
    fputc('\n', out);
  }
  bool failed = ferror(out) != 0;
  int saved = errno;
  if (fclose(out) != 0 && !failed) failed = true, saved = errno;
  if (failed) peri_error("cannot write '%s': %s", path, strerror(saved ? saved : EIO));
  free(path);
  return failed ? PERI_ERR_RUN : PERI_OK;
}
