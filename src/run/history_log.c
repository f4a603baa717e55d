/* history.csv of a run, shared by the mechanical and heat drivers (include/peri/history.h):
 * the column list, the row being filled, the rows replayed after a restart, and the series
 * of output.plot. Rank 0 writes the file. */
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
  h->file = peri_history_open_in(s->out.directory, n, names);
  return h->file ? PERI_OK : PERI_ERR_RUN;
}

int peri_history_log_record(peri_history_log *h) {
  h->rows++;
  peri_plot_series_add(&h->plot, h->row);
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

void peri_history_log_close(peri_history_log *h) {
  peri_history_close(h->file);
  free(h->row);
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
  if (kept && columns != n_columns) {
    peri_warning("restart: history.csv has %d columns, this run writes %d; its rows are not kept", columns,
                 n_columns);
    *rows = 0;
    return NULL;
  }
  if (!kept) *rows = 0;
  return kept;
}
