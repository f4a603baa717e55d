/* output.plot: a line plot of two history.csv columns at the end of the run, e.g. the
 * reaction force against the imposed displacement of a quasi-static fracture run, or a
 * temperature against time (include/peri/history.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/comm.h"
#include "peri/error.h"
#include "peri/history.h"
#include "peri/history_log.h"
#include "peri/plot.h"

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
  char xlabel[300], ylabel[300]; /* the column and its unit (history_units.csv) */
  const char *xu = peri_history_unit(s->out.plot_x), *yu = peri_history_unit(s->out.plot_y);
  snprintf(xlabel, sizeof xlabel, "%s [%s]", s->out.plot_x, xu ? xu : "1");
  snprintf(ylabel, sizeof ylabel, "%s [%s]", s->out.plot_y, yu ? yu : "1");
  /* output.plot.reference: the expression of x over the range of the x column, 201 points */
  enum { REFERENCE_POINTS = 201 };
  double xr[REFERENCE_POINTS], yr[REFERENCE_POINTS];
  size_t nr = 0;
  if (s->out.plot_reference) {
    double lo = p->xs[0], hi = p->xs[0];
    for (size_t k = 1; k < p->n; ++k) lo = p->xs[k] < lo ? p->xs[k] : lo, hi = p->xs[k] > hi ? p->xs[k] : hi;
    for (nr = 0; nr < REFERENCE_POINTS; ++nr) {
      xr[nr] = lo + (hi - lo) * (double)nr / (REFERENCE_POINTS - 1);
      yr[nr] = peri_expr_eval(s->out.plot_reference, xr[nr], 0.0, 0.0, 0.0);
    }
  }
  if (peri_plot_write_reference(path, p->xs, p->ys, p->n, xr, yr, nr, NULL, 0, NULL, xlabel, ylabel,
                                s->out.basename, 1200, 800) == PERI_OK)
    return PERI_OK;
  path[0] = '\0';
  return PERI_ERR_RUN;
}

void peri_plot_series_free(peri_plot_series *p) {
  free(p->xs);
  free(p->ys);
  *p = (peri_plot_series){.x = -1, .y = -1};
}
