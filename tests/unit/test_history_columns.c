/* The columns of history.csv (include/peri/history.h): one list for the file and for
 * output.plot. A thermomechanical run has the thermal columns after the mechanical ones and
 * can plot them; a heat run has its own columns; a quasi-static run adds the imposed
 * displacements of its regions. Counts follow from the deck: 8 fixed columns, dim momentum
 * components, dim reactions (and, quasi-static, dim displacements) per named region. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <string.h>
#include "peri/history.h"
#include "peri/history_log.h"
#include "peri/setup.h"
#include "support.h"

static const char *mechanical =
    "dimension: 2\n"
    "materials:\n"
    "  m: {model: pmb, density: 7850, youngs_modulus: 200e9%s}\n"
    "discretization: {spacing: 0.001, m: 3, fill: [{shape: rectangle, min: [0, 0], max: [0.01, 0.005]}]}\n"
    "regions: {left: {shape: rectangle, min: [-1, -1], max: [0.001, 1]}}\n"
    "%s"
    "solver: {type: %s}\n"
    "output: {picture: false%s}\n";

static void build(peri_sim *s, const char *thermal, const char *solver, const char *plot) {
  char text[4096];
  const char *keys = thermal[0] ? ", conductivity: 50, specific_heat: 450, thermal_expansion: 1.2e-5" : "";
  snprintf(text, sizeof text, mechanical, keys, thermal, solver, plot);
  cr_assert_eq(sim_from_string(s, text), 0, "deck:\n%s", text);
}

static int index_of(char **names, int n, const char *name) {
  for (int k = 0; k < n; ++k)
    if (!strcmp(names[k], name)) return k;
  return -1;
}

Test(history_columns, explicit_run) {
  peri_sim s;
  build(&s, "", "explicit, steps: 1", "");
  int n = 0;
  char **names = peri_history_columns(&s, &n);
  cr_assert_eq(n, 8 + 2 + 2, "8 fixed, 2 momentum, 2 reactions of one region; got %d", n);
  cr_assert_eq(index_of(names, n, "time"), 0);
  cr_assert_eq(index_of(names, n, "mean_damage"), index_of(names, n, "broken_bond_fraction") + 1);
  cr_assert_eq(index_of(names, n, "reaction_left_y"), n - 1);
  cr_assert_eq(index_of(names, n, "total_heat"), -1);
  cr_assert(!peri_history_has_column(&s, "displacement_left_x"), "explicit runs have no imposed displacements");
  peri_history_columns_free(names, n);
  peri_sim_free(&s);
}

Test(history_columns, thermomechanics_plots_thermal_columns) {
  peri_sim s;
  build(&s, "thermal: {initial_temperature: 120, reference_temperature: 20, coupling: one_way}\n",
        "explicit, steps: 1", ", plot: {x: time, y: max_temperature}");
  int n = 0;
  char **names = peri_history_columns(&s, &n);
  cr_assert_eq(n, 8 + 2 + 2 + 3, "the 3 thermal columns follow the mechanical ones; got %d", n);
  cr_assert_eq(index_of(names, n, "total_heat"), n - 3);
  cr_assert_eq(index_of(names, n, "max_temperature"), n - 1);
  peri_plot_series series;
  peri_plot_series_init(&series, &s, names, n);
  cr_assert_eq(series.x, 0);
  cr_assert_eq(series.y, n - 1);
  double row[32] = {0};
  row[0] = 2.0, row[n - 1] = 5.0;
  peri_plot_series_add(&series, row);
  cr_assert(series.n == 1 && series.xs[0] == 2.0 && series.ys[0] == 5.0);
  peri_plot_series_free(&series);
  peri_history_columns_free(names, n);
  peri_sim_free(&s);
}

Test(history_columns, quasi_static_adds_imposed_displacements) {
  peri_sim s;
  build(&s, "", "nlcg", "");
  cr_assert(peri_history_has_column(&s, "displacement_left_x"));
  cr_assert(peri_history_has_column(&s, "displacement_left_y"));
  cr_assert(!peri_history_has_column(&s, "phase"), "phase only with a dynamic switch");
  cr_assert(!peri_history_has_column(&s, "bogus"));
  peri_sim_free(&s);
}

/* history_units.csv (docs/output.md): every column of every kind of run has a unit, the one
 * docs/deck.md section 16 gives it. */
static void expect_units(const peri_sim *s) {
  int n = 0;
  char **names = peri_history_columns(s, &n);
  for (int k = 0; k < n; ++k) cr_expect(peri_history_unit(names[k]) != NULL, "column '%s' has no unit", names[k]);
  peri_history_columns_free(names, n);
}

Test(history_columns, every_column_has_its_unit) {
  peri_sim s;
  build(&s, "thermal: {initial_temperature: 120, reference_temperature: 20, coupling: one_way}\n", "nlcg", "");
  expect_units(&s);
  peri_sim_free(&s);
  build(&s, "", "explicit, steps: 1", "");
  expect_units(&s);
  peri_sim_free(&s);
  static const struct {
    const char *column, *unit;
  } known[] = {{"time", "s"}, {"step", "1"}, {"kinetic_energy", "J"}, {"energy_balance", "J"},
               {"broken_bond_fraction", "1"}, {"momentum_y", "kg*m/s"}, {"reaction_left_x", "N"},
               {"displacement_left_y", "m"}, {"indenter_force_z", "N"}, {"phase", "1"}, {"dynamic_time", "s"},
               {"total_heat", "J"}, {"max_temperature", "K"}, {"mean_temperature_hot", "K"},
               {"heat_inflow_hot", "W"}, {"max_von_mises_bi2212", "Pa"}, {"max_von_mises_at_bi2212_x", "m"},
               {"mean_stress_silver", "Pa"}};
  for (size_t k = 0; k < sizeof known / sizeof known[0]; ++k)
    cr_expect_str_eq(peri_history_unit(known[k].column) ? peri_history_unit(known[k].column) : "(none)", known[k].unit,
                     "column %s", known[k].column);
  cr_expect_null(peri_history_unit("bogus"), "a name that is no column has no unit");
}
