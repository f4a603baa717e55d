/* output.plot keys: the two history.csv columns of the end-of-run line plot (include/peri/history.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/history.h"
#include "peri/setup.h"

int peri_plot_parse(peri_sim *s, const peri_node *output) {
  const peri_node *plot = peri_deck_get(output, "plot");
  if (!plot) return PERI_OK;
  static const char *const keys[] = {"x", "y", "reference", NULL};
  int rc = peri_deck_allow(plot, "output.plot", keys);
  const char *x = NULL, *y = NULL;
  if (rc == PERI_OK) rc = peri_deck_string(plot, "x", true, &x);
  if (rc == PERI_OK) rc = peri_deck_string(plot, "y", true, &y);
  if (rc == PERI_OK) rc = peri_deck_expr(plot, "reference", false, &s->out.plot_reference);
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
