/* The columns of history.csv and the end-of-run line plot of two of them (output.plot).
 * One list of column names serves the file, the plot and the deck checks, for the
 * mechanical and quasi-static runs and for the heat runs (docs/deck.md, output). */
#ifndef PERI_HISTORY_H
#define PERI_HISTORY_H
#include <stdbool.h>
#include <stddef.h>
#include "peri/sim.h"

/* The column names of history.csv of this simulation, in file order (*count of them);
 * free with peri_history_columns_free. */
char **peri_history_columns(const peri_sim *s, int *count);
void peri_history_columns_free(char **names, int count);
/* Whether history.csv has a column of that name. */
bool peri_history_has_column(const peri_sim *s, const char *name);

/* output.plot: {x: COLUMN, y: COLUMN}. peri_plot_parse reads the names (with the rest of
 * `output`); peri_plot_check, once the whole simulation is set up (thermal columns
 * included), checks that history.csv will have them. Both return PERI_OK or
 * PERI_ERR_INPUT after a positioned message. */
int peri_plot_parse(peri_sim *s, const peri_node *output);
int peri_plot_check(const peri_sim *s, const peri_node *output);

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

#endif
