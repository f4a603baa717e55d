/* output.plot: a line plot of two history.csv columns at the end of the run, e.g. the
 * reaction force against the imposed displacement of a quasi-static fracture run. */
#include <stdio.h>
#include <string.h>
#include "peri/error.h"
#include "peri/quasistatic.h"

static const char *const fixed[] = {"time", "step", "kinetic_energy", "strain_energy", "external_work",
                                    "energy_balance", "broken_bond_fraction", NULL};

bool peri_history_has_column(const peri_sim *s, const char *name) {
  for (int k = 0; fixed[k]; ++k)
    if (!strcmp(name, fixed[k])) return true;
  if (peri_is_quasi_static(s) && s->qs.dynamic.on && (!strcmp(name, "phase") || !strcmp(name, "dynamic_time")))
    return true; /* the switch to dynamics (docs/solvers.md 4) */
  char buf[512];
  for (int d = 0; d < s->geom.dim; ++d) {
    snprintf(buf, sizeof buf, "momentum_%c", "xyz"[d]);
    if (!strcmp(name, buf)) return true;
    snprintf(buf, sizeof buf, "indenter_force_%c", "xyz"[d]);
    if (s->indenter.on && !strcmp(name, buf)) return true;
    for (int r = 1; r < s->n_regions; ++r) {
      snprintf(buf, sizeof buf, "reaction_%s_%c", s->regions[r].name, "xyz"[d]);
      if (!strcmp(name, buf)) return true;
      snprintf(buf, sizeof buf, "displacement_%s_%c", s->regions[r].name, "xyz"[d]);
      if (peri_is_quasi_static(s) && !strcmp(name, buf)) return true;
    }
  }
  return false;
}

static int column(peri_sim *s, const peri_node *plot, const char *key, char **out) {
  const char *name = NULL;
  int rc = peri_deck_string(plot, key, true, &name);
  if (rc != PERI_OK) return rc;
  if (!peri_history_has_column(s, name))
    return peri_deck_error(peri_deck_get(plot, key), "key '%s': history.csv has no column '%s' (columns: time, "
                           "step, energies, broken_bond_fraction, reaction_REGION_x/y/z%s)", key, name,
                           peri_is_quasi_static(s) ? ", displacement_REGION_x/y/z" : "");
  *out = peri_strdup(name);
  return PERI_OK;
}

int peri_plot_parse(peri_sim *s, const peri_node *output) {
  const peri_node *plot = peri_deck_get(output, "plot");
  if (!plot) return PERI_OK;
  static const char *const keys[] = {"x", "y", NULL};
  int rc = peri_deck_allow(plot, "output.plot", keys);
  if (rc == PERI_OK) rc = column(s, plot, "x", &s->out.plot_x);
  if (rc == PERI_OK) rc = column(s, plot, "y", &s->out.plot_y);
  return rc;
}
