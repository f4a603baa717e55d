/* The columns of history.csv (src/post/history_columns.c). One list of column names serves
 * the file, the plot and the deck checks, for the mechanical and quasi-static runs and for
 * the heat runs (docs/deck.md, output). */
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

/* The SI unit of a history.csv column ("1" for a ratio or a count), NULL for a name that is
 * not a column of peri's (history_units.csv, plot axes). */
const char *peri_history_unit(const char *column);

#endif
