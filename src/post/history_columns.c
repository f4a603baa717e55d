/* The columns of history.csv: the one list behind the file's header, output.plot and the
 * deck checks (include/peri/history.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/heat_quantities.h"
#include "peri/history.h"
#include "peri/thermal.h"

typedef struct column_list {
  char **names;
  int count, capacity;
} column_list;

static void add(column_list *c, const char *name) {
  if (c->count == c->capacity) {
    c->capacity = c->capacity ? 2 * c->capacity : 32;
    c->names = peri_realloc(c->names, sizeof(char *) * (size_t)c->capacity);
  }
  c->names[c->count++] = peri_strdup(name);
}

/* name_<region>_<axis> for every named region (region 0 is the whole body) and axis */
static void add_per_region_axis(column_list *c, const peri_sim *s, const char *what) {
  char buf[300];
  for (int r = 1; r < s->cond.n_regions; ++r)
    for (int d = 0; d < s->disc.geom.dim; ++d) {
      snprintf(buf, sizeof buf, "%s_%s_%c", what, s->cond.regions[r].name, "xyz"[d]);
      add(c, buf);
    }
}

/* Conduction only (src/run/heat_run.c). */
static void heat_columns(column_list *c, const peri_sim *s) {
  static const char *const fixed[] = {"time", "step", "total_heat", "min_temperature", "max_temperature",
                                      "broken_bond_fraction"};
  for (size_t k = 0; k < sizeof fixed / sizeof fixed[0]; ++k) add(c, fixed[k]);
  char buf[300];
  for (int r = 1; r < s->cond.n_regions; ++r) {
    snprintf(buf, sizeof buf, "mean_temperature_%s", s->cond.regions[r].name);
    add(c, buf);
    snprintf(buf, sizeof buf, "heat_inflow_%s", s->cond.regions[r].name);
    add(c, buf);
  }
}

/* Mechanical runs, explicit and quasi-static (src/run/run.c). */
static void mechanical_columns(column_list *c, const peri_sim *s) {
  static const char *const fixed[] = {"time", "step", "kinetic_energy", "strain_energy", "external_work",
                                      "energy_balance", "broken_bond_fraction"};
  for (size_t k = 0; k < sizeof fixed / sizeof fixed[0]; ++k) add(c, fixed[k]);
  add(c, "mean_damage"); /* the mean damage index of the nodes */
  if (s->state.plastic_stretch) add(c, "mean_yield_index"); /* docs/plasticity.md */
  char buf[64];
  for (int d = 0; d < s->disc.geom.dim; ++d) {
    snprintf(buf, sizeof buf, "momentum_%c", "xyz"[d]);
    add(c, buf);
  }
  for (int d = 0; s->cond.indenter.on && d < s->disc.geom.dim; ++d) {
    snprintf(buf, sizeof buf, "indenter_force_%c", "xyz"[d]);
    add(c, buf);
  }
  add_per_region_axis(c, s, "reaction");
  const bool qs = peri_is_quasi_static(s);
  if (qs) add_per_region_axis(c, s, "displacement"); /* the imposed displacements */
  if (qs && s->solver.qs.dynamic.on) { /* the switch to dynamics (docs/solvers.md section 4) */
    add(c, "phase");
    add(c, "dynamic_time");
  }
  for (int m = 0; s->out.phase_stress && m < s->mat.n_materials; ++m) { /* docs/microstructures.md */
    char name[300];
    snprintf(name, sizeof name, "max_von_mises_%s", s->mat.materials[m].name);
    add(c, name);
    for (int d = 0; d < s->disc.geom.dim; ++d) {
      snprintf(name, sizeof name, "max_von_mises_at_%s_%c", s->mat.materials[m].name, "xyz"[d]);
      add(c, name);
    }
    snprintf(name, sizeof name, "mean_stress_%s", s->mat.materials[m].name);
    add(c, name);
  }
  const int n_thermal = peri_thermal_history_count(s); /* thermomechanics (docs/heat.md) */
  if (n_thermal > 0) {
    char **thermal = peri_calloc((size_t)n_thermal, sizeof(char *));
    peri_thermal_history_names(s, thermal);
    for (int k = 0; k < n_thermal; ++k) {
      add(c, thermal[k]);
      free(thermal[k]);
    }
    free(thermal);
  }
  if (s->coupling) { /* out-of-balance of the PD-FEM coupling (docs/coupling.md) */
    char name[64];
    for (int d = 0; d < s->disc.geom.dim; ++d) {
      snprintf(name, sizeof name, "net_force_%c", "xyz"[d]);
      add(c, name);
    }
    for (int d = 0; d < s->disc.geom.dim; ++d) {
      snprintf(name, sizeof name, "out_of_balance_%c", "xyz"[d]);
      add(c, name);
    }
    add(c, "out_of_balance");
    add(c, "pd_nodes"); /* grows with FEM->PD switching */
  }
}

char **peri_history_columns(const peri_sim *s, int *count) {
  column_list c = {0};
  if (s->solver.kind == PERI_SOLVER_HEAT) heat_columns(&c, s);
  else mechanical_columns(&c, s);
  *count = c.count;
  return c.names;
}

void peri_history_columns_free(char **names, int count) {
  for (int k = 0; k < count; ++k) free(names[k]);
  free(names);
}

bool peri_history_has_column(const peri_sim *s, const char *name) {
  int n = 0;
  char **names = peri_history_columns(s, &n);
  bool found = false;
  for (int k = 0; k < n && !found; ++k) found = !strcmp(names[k], name);
  peri_history_columns_free(names, n);
  return found;
}

/* Units of docs/deck.md section 16 and docs/heat.md, SI, "1" for ratios and counts; a column
 * is found by its name or, for the per-region and per-axis columns, by its prefix. */
const char *peri_history_unit(const char *column) {
  static const struct {
    const char *prefix, *unit;
    bool whole; /* the whole name, not a prefix */
  } units[] = {
      {"time", "s", true},          {"step", "1", true},           {"kinetic_energy", "J", true},
      {"strain_energy", "J", true}, {"external_work", "J", true},  {"energy_balance", "J", true},
      {"broken_bond_fraction", "1", true}, {"mean_damage", "1", true}, {"mean_yield_index", "1", true}, {"phase", "1", true},   {"dynamic_time", "s", true},
      {"total_heat", "J", true},    {"min_temperature", "K", true}, {"max_temperature", "K", true},
      {"momentum_", "kg*m/s", false}, {"indenter_force_", "N", false}, {"reaction_", "N", false},
      {"displacement_", "m", false}, {"mean_temperature_", "K", false}, {"heat_inflow_", "W", false},
      {"net_force_", "N", false},   {"out_of_balance", "1", false}, {"pd_nodes", "1", true},
      {"max_von_mises_at_", "m", false}, {"max_von_mises_", "Pa", false}, {"mean_stress_", "Pa", false},
  };
  for (size_t k = 0; k < sizeof units / sizeof units[0]; ++k)
    if (units[k].whole ? !strcmp(column, units[k].prefix)
                       : !strncmp(column, units[k].prefix, strlen(units[k].prefix)))
      return units[k].unit;
  return NULL;
}
