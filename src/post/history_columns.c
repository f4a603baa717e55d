/* The columns of history.csv: the one list behind the file's header, output.plot and the
 * deck checks (include/peri/history.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/bodies.h"
#include "peri/contact.h"
#include "peri/coupling.h"
#include "peri/error.h"
#include "peri/heat_quantities.h"
#include "peri/history.h"
#include "peri/j_integral.h"
#include "peri/thermal.h"
#include "peri/tools.h"
#include "peri/tensor_plasticity.h"

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

/* Per body (docs/contact.md "Bodies"), named by its region: mass, momentum, kinetic energy,
 * mean velocity, mass of the damaged nodes (phi > 0) and of the detached ones (phi = 1), and
 * with output.penetration its penetration depth. */
static void body_columns(column_list *c, const peri_sim *s) {
  char buf[300];
  for (int b = 0; s->bodies && b < s->bodies->count; ++b) {
    const char *name = s->cond.regions[s->bodies->region[b]].name;
    snprintf(buf, sizeof buf, "mass_%s", name);
    add(c, buf);
    for (int d = 0; d < s->disc.geom.dim; ++d) {
      snprintf(buf, sizeof buf, "momentum_%s_%c", name, "xyz"[d]);
      add(c, buf);
    }
    snprintf(buf, sizeof buf, "kinetic_energy_%s", name);
    add(c, buf);
    for (int d = 0; d < s->disc.geom.dim; ++d) {
      snprintf(buf, sizeof buf, "mean_velocity_%s_%c", name, "xyz"[d]);
      add(c, buf);
    }
    snprintf(buf, sizeof buf, "damaged_mass_%s", name);
    add(c, buf);
    snprintf(buf, sizeof buf, "detached_mass_%s", name);
    add(c, buf);
    if (s->bodies->penetration[b].on) { /* output.penetration */
      snprintf(buf, sizeof buf, "penetration_%s", name);
      add(c, buf);
    }
  }
}

/* Per rigid tool (docs/contact.md "Rigid tools"): the force of the body on it, its position,
 * normal and tangential force, their ratio (the coefficient of friction), the distance
 * slid across its direction, its contact area and the wear depth of its scratch. */
static void tool_columns(column_list *c, const peri_sim *s) {
  char buf[300];
  for (int k = 0; s->tools && k < s->tools->count; ++k) {
    const char *name = s->tools->tool[k].name;
    for (int d = 0; d < s->disc.geom.dim; ++d) {
      snprintf(buf, sizeof buf, "tool_%s_force_%c", name, "xyz"[d]);
      add(c, buf);
    }
    for (int d = 0; d < s->disc.geom.dim; ++d) {
      snprintf(buf, sizeof buf, "tool_%s_position_%c", name, "xyz"[d]);
      add(c, buf);
    }
    static const char *const each[] = {"normal_force", "tangential_force", "cof", "sliding_distance", "contact_area", "wear_depth",
                                       "speed", "penetration"};
    for (size_t j = 0; j < sizeof each / sizeof each[0]; ++j) {
      snprintf(buf, sizeof buf, "tool_%s_%s", name, each[j]);
      add(c, buf);
    }
  }
}

/* Mechanical runs, explicit and quasi-static (src/run/run.c). */
static void mechanical_columns(column_list *c, const peri_sim *s) {
  static const char *const fixed[] = {"time", "step", "kinetic_energy", "strain_energy", "external_work",
                                      "energy_balance", "broken_bond_fraction"};
  for (size_t k = 0; k < sizeof fixed / sizeof fixed[0]; ++k) add(c, fixed[k]);
  add(c, "mean_damage"); /* the mean damage index of the nodes */
  if (peri_has_plasticity(s)) add(c, "mean_yield_index"); /* docs/plasticity.md */
  char buf[300];
  for (int d = 0; d < s->disc.geom.dim; ++d) {
    snprintf(buf, sizeof buf, "momentum_%c", "xyz"[d]);
    add(c, buf);
  }
  for (int d = 0; s->cond.indenter.on && d < s->disc.geom.dim; ++d) {
    snprintf(buf, sizeof buf, "indenter_force_%c", "xyz"[d]);
    add(c, buf);
  }
  tool_columns(c, s);
  if (s->contact && s->contact->short_range) add(c, "short_range_min_ratio"); /* docs/contact.md */
  add_per_region_axis(c, s, "reaction");
  body_columns(c, s);
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
  if (s->out.region_energy) /* per region (docs/thin_films.md) */
    for (int r = 1; r < s->cond.n_regions; ++r) {
      snprintf(buf, sizeof buf, "strain_energy_%s", s->cond.regions[r].name);
      add(c, buf);
    }
  if (s->out.interface_history) { /* interfaces between materials (docs/thin_films.md) */
    add(c, "broken_interface_bonds");
    add(c, "max_interface_stress");
    add(c, "max_interface_traction");
  }
  if (s->out.wrinkle_region > 0) { /* the film's deflection profile (docs/thin_films.md) */
    add(c, "wrinkle_amplitude");
    add(c, "wrinkle_wavelength");
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
  if (s->out.j_integral) { /* J over each contour and the crack extension (docs/plasticity.md) */
    for (int k = 0; k < s->out.j_integral->n_contours; ++k) {
      snprintf(buf, sizeof buf, "j_integral_%d", k + 1);
      add(c, buf);
    }
    add(c, "crack_extension");
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
    for (int d = 0; s->coupling->n_balance_regions > 0 && d < s->disc.geom.dim; ++d) {
      snprintf(name, sizeof name, "out_of_balance_reactions_%c", "xyz"[d]); /* coupling.balance_regions */
      add(c, name);
    }
    for (int k = 0; k < s->coupling->n_tractions; ++k) /* coupling.tractions */
      for (int kind = 0; kind < 2; ++kind)
        for (int d = 0; d < s->disc.geom.dim; ++d) {
          snprintf(name, sizeof name, "%s_traction_%s_%c", kind ? "local" : "nonlocal", s->coupling->traction[k].name,
                   "xyz"[d]);
          add(c, name);
        }
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
      {"net_force_", "N", false},   {"j_integral_", "J/m^2", false}, {"crack_extension", "m", true},   {"out_of_balance", "1", false}, {"pd_nodes", "1", true},
      {"max_von_mises_at_", "m", false},
      {"mass_", "kg", false}, {"kinetic_energy_", "J", false}, {"mean_velocity_", "m/s", false},
      {"damaged_mass_", "kg", false}, {"detached_mass_", "kg", false}, {"penetration_", "m", false}, {"max_von_mises_", "Pa", false}, {"mean_stress_", "Pa", false},
      {"strain_energy_", "J", false}, {"broken_interface_bonds", "1", true}, {"max_interface_stress", "Pa", true},
      {"max_interface_traction", "Pa", true}, {"nonlocal_traction_", "Pa", false}, {"local_traction_", "Pa", false},
      {"wrinkle_amplitude", "m", true}, {"wrinkle_wavelength", "m", true}, {"short_range_min_ratio", "1", true},
  };
  if (!strncmp(column, "tool_", 5)) { /* tool_NAME_WHAT: the unit of WHAT */
    static const struct {
      const char *suffix, *unit;
    } tool_units[] = {{"_normal_force", "N"}, {"_tangential_force", "N"}, {"_cof", "1"}, {"_sliding_distance", "m"}, {"_contact_area", "m^2"}, {"_wear_depth", "m"},
                      {"_speed", "m/s"}, {"_penetration", "m"},
                      {"_force_x", "N"}, {"_force_y", "N"}, {"_force_z", "N"},
                      {"_position_x", "m"}, {"_position_y", "m"}, {"_position_z", "m"}};
    const size_t len = strlen(column);
    for (size_t k = 0; k < sizeof tool_units / sizeof tool_units[0]; ++k) {
      const size_t sl = strlen(tool_units[k].suffix);
      if (len > sl && !strcmp(column + len - sl, tool_units[k].suffix)) return tool_units[k].unit;
    }
  }
  for (size_t k = 0; k < sizeof units / sizeof units[0]; ++k)
    if (units[k].whole ? !strcmp(column, units[k].prefix)
                       : !strncmp(column, units[k].prefix, strlen(units[k].prefix)))
      return units[k].unit;
  return NULL;
}
