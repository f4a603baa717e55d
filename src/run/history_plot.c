/* output.plot: a line plot of two history.csv columns at the end of the run, e.g. the
 * reaction force against the imposed displacement of a quasi-static fracture run, or a
 * temperature against time (include/peri/history.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/comm.h"
#include "peri/error.h"
#include "peri/history.h"
#include "peri/plot.h"

int peri_plot_parse(peri_sim *s, const peri_node *output) {
  const peri_node *plot = peri_deck_get(output, "plot");
  if (!plot) return PERI_OK;
  static const char *const keys[] = {"x", "y", NULL};
  int rc = peri_deck_allow(plot, "output.plot", keys);
  const char *x = NULL, *y = NULL;
  if (rc == PERI_OK) rc = peri_deck_string(plot, "x", true, &x);
  if (rc == PERI_OK) rc = peri_deck_string(plot, "y", true, &y);
  if (rc != PERI_OK) return rc;
  s->out.plot_x = peri_strdup(x);
  s->out.plot_y = peri_strdup(y);
  return PERI_OK;
}

/* The message for a column history.csv will not have: the columns it will have. */
static int no_column(const peri_sim *s, const peri_node *plot, const char *key, const char *name) {
  int n = 0;
  char **names = peri_history_columns(s, &n);
  size_t length = 1;
  for (int k = 0; k < n; ++k) length += strlen(names[k]) + 2;
  char *list = peri_calloc(length, 1);
  for (int k = 0; k < n; ++k) {
    if (k) strcat(list, ", ");
    strcat(list, names[k]);
  }
  const int rc = peri_deck_error(peri_deck_get(plot, key), "key '%s': history.csv has no column '%s' (columns: %s)",
                                 key, name, list);
  free(list);
  peri_history_columns_free(names, n);
  return rc;
}

int peri_plot_check(const peri_sim *s, const peri_node *output) {
  const peri_node *plot = output ? peri_deck_get(output, "plot") : NULL;
  if (!plot || !s->out.plot_x) return PERI_OK;
  if (!peri_history_has_column(s, s->out.plot_x)) return no_column(s, plot, "x", s->out.plot_x);
  if (!peri_history_has_column(s, s->out.plot_y)) return no_column(s, plot, "y", s->out.plot_y);
  return PERI_OK;
}

void peri_plot_series_init(peri_plot_series *p, const peri_sim *s, char *const *names, int count) {
  *p = (peri_plot_series){.x = -1, .y = -1};
  for (int j = 0; j < count && s->out.plot_x; ++j) {
    if (!strcmp(names[j], s->out.plot_x)) p->x = j;
    if (!strcmp(names[j], s->out.plot_y)) p->y = j;
  }
  if (p->x < 0 || p->y < 0) p->x = p->y = -1;
}

void peri_plot_series_add(peri_plot_series *p, const double *row) {
  if (p->x < 0) return;
  if (p->n == p->capacity) {
    p->capacity = p->capacity ? 2 * p->capacity : 256;
    p->xs = peri_realloc(p->xs, sizeof(double) * p->capacity);
    p->ys = peri_realloc(p->ys, sizeof(double) * p->capacity);
  }
  p->xs[p->n] = row[p->x];
  p->ys[p->n++] = row[p->y];
}

int peri_plot_series_write(const peri_plot_series *p, const peri_sim *s, char *path, size_t size) {
  path[0] = '\0';
  if (p->x < 0 || p->n == 0 || peri_comm_rank() != 0) return PERI_OK; /* rank 0 draws */
  snprintf(path, size, "%s/%s_vs_%s.png", s->out.directory, s->out.plot_y, s->out.plot_x);
  if (peri_plot_write(path, p->xs, p->ys, p->n, s->out.plot_x, s->out.plot_y, s->out.basename, 1200, 800) ==
      PERI_OK)
    return PERI_OK;
  path[0] = '\0';
  return PERI_ERR_RUN;
}

void peri_plot_series_free(peri_plot_series *p) {
  free(p->xs);
  free(p->ys);
  *p = (peri_plot_series){.x = -1, .y = -1};
}
