/* history.csv of a run, shared by the mechanical and heat drivers (include/peri/history.h):
 * the column list, the row being filled, the rows replayed after a restart, and the series
 * of output.plot. Rank 0 writes the file. */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/checkpoint.h"
#include "peri/checkpoint_schedule.h"
#include "peri/comm.h"
#include "peri/error.h"
#include "peri/frames.h"
#include "peri/history.h"
#include "peri/history_log.h"
#include "peri/output.h"

int peri_history_log_open(peri_history_log *h, const peri_sim *s) {
  int n = 0;
  char **names = peri_history_columns(s, &n); /* the order the drivers fill */
  *h = (peri_history_log){.n_columns = n, .row = peri_calloc((size_t)(n > 0 ? n : 1), sizeof(double))};
  peri_plot_series_init(&h->plot, s, names, n);
  if (peri_comm_rank() > 0) { /* rank 0 writes history.csv (docs/parallel.md) */
    peri_history_columns_free(names, n);
    return PERI_OK;
  }
  const char **units = peri_calloc((size_t)(n > 0 ? n : 1), sizeof(char *));
  for (int k = 0; k < n; ++k) {
    units[k] = peri_history_unit(names[k]);
    if (!units[k]) units[k] = "1"; /* every column of peri_history_columns has a unit: a new one belongs there */
  }
  const int units_rc = peri_history_units_write(s->out.directory, n, names, units);
  free(units);
  h->file = peri_history_open_in(s->out.directory, n, names);
  if (h->file && s->out.history_digits > 0) peri_history_set_digits(h->file, s->out.history_digits);
  return h->file && units_rc == PERI_OK ? PERI_OK : PERI_ERR_RUN;
}

int peri_history_log_record(peri_history_log *h) {
  if (h->keep) {
    if (h->rows == h->kept_capacity) {
      h->kept_capacity = h->kept_capacity ? 2 * h->kept_capacity : 64;
      h->kept = peri_realloc(h->kept, sizeof(double) * (size_t)h->kept_capacity * (size_t)h->n_columns);
    }
    memcpy(h->kept + (size_t)h->rows * (size_t)h->n_columns, h->row, sizeof(double) * (size_t)h->n_columns);
  }
  h->rows++;
  peri_plot_series_add(&h->plot, h->row);
  peri_frames_history(h->frames, h->row);
  return h->file ? peri_history_write(h->file, h->row) : PERI_OK;
}

int peri_history_log_resume(peri_history_log *h, peri_sim *s, struct peri_frames *frames) {
  long rows = 0;
  const double *kept = peri_restart_resume(s, frames, h->n_columns, &rows);
  if (rows < 0) return PERI_ERR_RUN;
  for (long r = 0; r < rows; ++r) {
    memcpy(h->row, kept + (size_t)r * (size_t)h->n_columns, sizeof(double) * (size_t)h->n_columns);
    if (peri_history_log_record(h) != PERI_OK) return PERI_ERR_RUN;
  }
  return PERI_OK;
}

/* The names of `names` that `other` lacks, as "'a', 'b'" into out; their count. */
static int missing_names(char *const *names, int n, char *const *other, int n_other, char *out, size_t size) {
  int count = 0;
  size_t len = 0;
  out[0] = '\0';
  for (int k = 0; k < n; ++k) {
    bool found = false;
    for (int j = 0; j < n_other && !found; ++j) found = !strcmp(names[k], other[j]);
    if (found) continue;
    if (len < size) len += (size_t)snprintf(out + len, size - len, "%s'%s'", count ? ", " : "", names[k]);
    ++count;
  }
  return count;
}

int peri_restart_check_history(const peri_sim *s) {
  int n_kept = 0, n = 0;
  char *const *kept = peri_restart_history_names(s, &n_kept);
  if (!kept) return PERI_OK; /* no rows kept */
  char **names = peri_history_columns(s, &n);
  bool same = n == n_kept;
  for (int k = 0; same && k < n; ++k) same = !strcmp(names[k], kept[k]);
  if (!same) {
    char added[2048], removed[2048], what[4200] = "";
    const int n_added = missing_names(names, n, kept, n_kept, added, sizeof added);
    const int n_removed = missing_names(kept, n_kept, names, n, removed, sizeof removed);
    if (n_added) snprintf(what, sizeof what, "the deck adds the column%s %s", n_added == 1 ? "" : "s", added);
    if (n_removed)
      snprintf(what + strlen(what), sizeof what - strlen(what), "%sthe deck no longer has the column%s %s",
               n_added ? " and " : "", n_removed == 1 ? "" : "s", removed);
    if (!n_added && !n_removed) snprintf(what, sizeof what, "the columns are in another order");
    peri_error("restart: '%s/history.csv' has %d columns and this deck's run writes %d: %s. Its rows cannot be "
               "continued in one file; restart into another directory (--output DIR) to start a new history.csv "
               "at the checkpoint, or restart with the deck the checkpoint was written with", s->out.directory,
               n_kept, n, what);
  }
  peri_history_columns_free(names, n);
  return same ? PERI_OK : PERI_ERR_INPUT;
}

void peri_history_log_close(peri_history_log *h) {
  peri_history_close(h->file);
  free(h->row);
  free(h->kept);
  peri_plot_series_free(&h->plot);
  *h = (peri_history_log){0};
}

const double *peri_restart_resume(peri_sim *s, peri_frames *frames, int n_columns, long *rows) {
  peri_restart_apply(s);
  long listed = 0;
  const double *times = NULL;
  char *const *files = NULL;
  const long next = peri_restart_frames(s, &listed, &times, &files);
  if (peri_frames_resume(frames, next, listed, times, files) != PERI_OK) {
    *rows = -1;
    return NULL;
  }
  int columns = 0;
  const double *kept = peri_restart_history(s, rows, &columns);
  if (kept && columns != n_columns) { /* refused before the run (peri_restart_check_history) */
    peri_error("restart: history.csv has %d columns, this run writes %d", columns, n_columns);
    *rows = -1;
    return NULL;
  }
  if (!kept) *rows = 0;
  return kept;
}
