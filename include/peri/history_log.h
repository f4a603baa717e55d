/* The history.csv of a run and the end-of-run line plot of two of its columns (output.plot),
 * written by the run drivers (src/run/history_log.c, history_plot.c). */
#ifndef PERI_HISTORY_LOG_H
#define PERI_HISTORY_LOG_H
#include <stdbool.h>
#include <stddef.h>
#include "peri/history.h"

/* The two columns of output.plot collected row by row during a run. */
typedef struct peri_plot_series {
  int x, y; /* column indices, -1: no plot */
  size_t n, capacity;
  double *xs, *ys;
} peri_plot_series;

/* The columns of output.plot among `names` (x = y = -1 without output.plot). */
void peri_plot_series_init(peri_plot_series *p, const peri_sim *s, char *const *names, int count);
/* Adds the plotted values of one history row. */
void peri_plot_series_add(peri_plot_series *p, const double *row);
/* On rank 0, draws the curve so far into <directory>/<y>_vs_<x>.png and puts that path into
 * path (empty when there is nothing to draw or on other ranks). Returns PERI_OK or
 * PERI_ERR_RUN with a message. */
int peri_plot_series_write(const peri_plot_series *p, const peri_sim *s, char *path, size_t size);
void peri_plot_series_free(peri_plot_series *p);

/* The history.csv of a run, shared by the mechanical and heat drivers: the driver fills
 * `row` (in the order of peri_history_columns) and records it. */
struct peri_frames;
typedef struct peri_history_log {
  struct peri_history *file; /* rank 0 only */
  double *row;               /* [n_columns], filled by the driver */
  int n_columns;
  long rows;                 /* rows recorded (a checkpoint records it) */
  peri_plot_series plot;     /* the columns of output.plot */
  struct peri_frames *frames; /* receives each row (the Exodus file's global variables), or NULL */
  bool keep;                 /* keep the rows in memory too (the C API, include/peri/api.h) */
  double *kept;              /* [rows][n_columns] when keep */
  long kept_capacity;
} peri_history_log;

/* Opens <directory>/history.csv on rank 0 and the plot series; PERI_OK or PERI_ERR_RUN
 * with a message (on rank 0: agree on the status with peri_comm_max_int). */
int peri_history_log_open(peri_history_log *h, const peri_sim *s);
/* Adds h->row to the file and to the plot series. */
int peri_history_log_record(peri_history_log *h);
/* A restarted run: puts the checkpoint's state into s, continues the .pvd series in frames
 * and records again the rows written before the checkpoint (peri_restart_resume). */
int peri_history_log_resume(peri_history_log *h, peri_sim *s, struct peri_frames *frames);
/* A restart whose history.csv has other columns than the deck's run writes (a region or a
 * heat field added or removed) cannot continue it without losing or misplacing rows: the
 * error names the columns added and removed. PERI_OK or PERI_ERR_INPUT, before any output
 * (docs/restart.md). */
int peri_restart_check_history(const peri_sim *s);
void peri_history_log_close(peri_history_log *h);

#endif
