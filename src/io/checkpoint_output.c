/* A restart continues the output of the run it restarts (docs/restart.md): it keeps the
 * history.csv rows and the .pvd frames written up to the checkpoint. Rows were written
 * with 10 significant digits and frame times with 9, so reading them back and writing
 * them again reproduces the same text (any decimal of at most 15 digits survives the
 * round trip through a double). */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/checkpoint.h"
#include "peri/error.h"

/* Next line of `in` into a growing buffer, without its newline; false at the end. */
static bool read_line(FILE *in, char **line, size_t *cap) {
  size_t len = 0;
  int ch;
  while ((ch = fgetc(in)) != EOF && ch != '\n') {
    if (len + 2 > *cap) *line = peri_realloc(*line, *cap = *cap ? 2 * *cap : 256);
    (*line)[len++] = (char)ch;
  }
  if (ch == EOF && len == 0) return false;
  if (!*line) *line = peri_malloc(*cap = 256);
  (*line)[len] = '\0';
  if (len > 0 && (*line)[len - 1] == '\r') (*line)[len - 1] = '\0';
  return ch == '\n'; /* a last line without its newline was cut off mid-write */
}

/* The column names of a CSV header, newly allocated; quoted names may hold commas and
 * doubled quotes (src/io/history_writer.c writes them so). */
static char **header_names(const char *line, int *count) {
  int n = 1;
  bool quoted = false;
  for (const char *c = line; *c; ++c) {
    if (*c == '"') quoted = !quoted;
    else if (*c == ',' && !quoted) ++n;
  }
  char **names = peri_calloc((size_t)n, sizeof(char *));
  const char *c = line;
  for (int k = 0; k < n; ++k) {
    char *name = peri_malloc(strlen(c) + 1);
    size_t len = 0;
    quoted = false;
    for (; *c && (quoted || *c != ','); ++c) {
      if (*c == '"' && quoted && c[1] == '"') name[len++] = *c++;
      else if (*c == '"') quoted = !quoted;
      else name[len++] = *c;
    }
    name[len] = '\0';
    names[k] = name;
    if (*c == ',') ++c;
  }
  *count = n;
  return names;
}

/* Parses one row of n numbers; false if it is not one. */
static bool parse_row(const char *line, int n, double *out) {
  const char *c = line;
  for (int k = 0; k < n; ++k) {
    char *end = NULL;
    out[k] = strtod(c, &end);
    if (end == c) return false;
    c = end;
    if (k + 1 < n) {
      if (*c != ',') return false;
      ++c;
    }
  }
  return *c == '\0';
}

/* The first `rows` rows of history.csv. The arrays grow with the rows the file holds, never
 * with the count the checkpoint claims. A missing file is a warning (a restart into another
 * directory); one with fewer complete rows than the checkpoint records is not the output of
 * the run that wrote the checkpoint, and an error. */
static int read_history(const char *directory, long rows, double **history, long *n_rows, int *n_columns,
                        char ***names) {
  *history = NULL;
  *names = NULL;
  *n_rows = 0;
  *n_columns = 0;
  if (rows <= 0) return PERI_OK;
  char path[4200];
  snprintf(path, sizeof path, "%s/history.csv", directory);
  FILE *in = fopen(path, "r");
  if (!in) {
    peri_warning("restart: cannot read '%s' (%s): history.csv starts again at the checkpoint", path, strerror(errno));
    return PERI_OK;
  }
  char *line = NULL;
  size_t cap = 0;
  if (read_line(in, &line, &cap)) {
    int n = 0;
    *names = header_names(line, &n);
    double *row = peri_malloc(sizeof(double) * (size_t)n);
    double *values = NULL;
    long got = 0, capacity = 0;
    while (got < rows && read_line(in, &line, &cap) && parse_row(line, n, row)) {
      if (got == capacity) values = peri_realloc(values, sizeof(double) * (size_t)n * (size_t)(capacity = 2 * capacity + 64));
      memcpy(values + (size_t)got * (size_t)n, row, sizeof(double) * (size_t)n);
      ++got;
    }
    free(row);
    *history = values;
    *n_rows = got;
    *n_columns = n;
  }
  free(line);
  fclose(in);
  if (*n_rows < rows) {
    peri_error("restart: '%s' holds %ld complete rows, but the checkpoint records %ld written up to it: the "
               "directory holds the output of another run (restart into the directory of the run that wrote the "
               "checkpoint, or into a new one with --output)", path, *n_rows, rows);
    return PERI_ERR_INPUT;
  }
  return PERI_OK;
}

/* The value of attribute `name` in an XML tag, unescaped, newly allocated; NULL if absent. */
static char *xml_attribute(const char *tag, const char *name) {
  char key[64];
  snprintf(key, sizeof key, " %s=\"", name);
  const char *at = strstr(tag, key);
  if (!at) return NULL;
  at += strlen(key);
  const char *end = strchr(at, '"');
  if (!end) return NULL;
  char *out = peri_malloc((size_t)(end - at) + 1);
  size_t k = 0;
  static const struct { const char *entity, ch; } entities[] = {
      {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
  for (const char *c = at; c < end;) {
    bool replaced = false;
    for (size_t e = 0; e < sizeof entities / sizeof entities[0] && *c == '&'; ++e) {
      const size_t len = strlen(entities[e].entity);
      if (!strncmp(c, entities[e].entity, len)) {
        out[k++] = entities[e].ch;
        c += len;
        replaced = true;
        break;
      }
    }
    if (!replaced) out[k++] = *c++;
  }
  out[k] = '\0';
  return out;
}

/* The first `frames` frames listed in the .pvd, read as read_history reads rows. */
static int read_frames(const char *directory, const char *basename, long frames, double **times, char ***files,
                       long *listed) {
  *times = NULL;
  *files = NULL;
  *listed = 0;
  if (frames <= 0) return PERI_OK;
  char path[4200];
  snprintf(path, sizeof path, "%s/%s.pvd", directory, basename);
  FILE *in = fopen(path, "r");
  if (!in) {
    peri_warning("restart: cannot read '%s' (%s): the new .pvd lists the frames written after the checkpoint "
                 "only", path, strerror(errno));
    return PERI_OK;
  }
  char *line = NULL;
  size_t cap = 0;
  long capacity = 0;
  while (*listed < frames && read_line(in, &line, &cap)) {
    if (!strstr(line, "<DataSet ")) continue;
    char *time = xml_attribute(line, "timestep"), *file = xml_attribute(line, "file");
    if (time && file) {
      if (*listed == capacity) {
        capacity = 2 * capacity + 16;
        *times = peri_realloc(*times, sizeof(double) * (size_t)capacity);
        *files = peri_realloc(*files, sizeof(char *) * (size_t)capacity);
      }
      (*times)[*listed] = strtod(time, NULL);
      (*files)[(*listed)++] = file;
      file = NULL;
    }
    free(time);
    free(file);
  }
  free(line);
  fclose(in);
  if (*listed < frames) {
    peri_error("restart: '%s' lists %ld frames, but the checkpoint records %ld written up to it: the directory "
               "holds the output of another run (restart into the directory of the run that wrote the checkpoint, "
               "or into a new one with --output)", path, *listed, frames);
    return PERI_ERR_INPUT;
  }
  return PERI_OK;
}

int peri_restart_read_output(const char *directory, const char *basename, long rows, long frames,
                             double **history, long *history_rows, int *history_columns, char ***history_names,
                             double **frame_times, char ***frame_files, long *frames_listed) {
  const int rc = read_history(directory, rows, history, history_rows, history_columns, history_names);
  const int frames_rc = read_frames(directory, basename, frames, frame_times, frame_files, frames_listed);
  return rc != PERI_OK ? rc : frames_rc;
}
