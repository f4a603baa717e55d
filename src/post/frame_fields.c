/* The frame fields: their names (output.fields, output.picture), their components in a
 * given simulation and their units (include/peri/frames.h). */
#include <string.h>
#include "peri/frames.h"
#include "peri/tensor_plasticity.h"

/* The fields output.fields and output.picture accept. A new field is its name here and its
 * branch in frame_fields (frames.c). */
const char *const peri_frame_fields[] = {"displacement", "velocity", "force", "damage", "dilatation",
                                         "material", "volume", "strain_energy_density",
                                         "block", "stress", "strain", "von_mises",
                                         "principal_stress", "temperature", "heat_flux", "node_type", "d2u", "horizon",
                                         "yield_index", "plastic_stretch", "spacing", "interface", "body", NULL};

int peri_frame_field_components(const peri_sim *s, const char *name) {
  if (!strcmp(name, "dilatation")) return s->disc.p.theta ? 1 : 0; /* the model has no dilatation */
  if (!strcmp(name, "temperature")) return s->thermal ? 1 : 0;
  if (!strcmp(name, "horizon")) return s->disc.horizon_field ? 1 : 0; /* a horizon per node only */
  if (!strcmp(name, "heat_flux")) return s->thermal ? 3 : 0;
  if (!strcmp(name, "node_type")) return s->coupling ? 1 : 0; /* 1 PD, 0 FEM (docs/coupling.md) */
  if (!strcmp(name, "body")) return s->bodies ? 1 : 0; /* the bodies key (docs/contact.md) */
  if (!strcmp(name, "yield_index") || !strcmp(name, "plastic_stretch")) return peri_has_plasticity(s) ? 1 : 0;
  if (!strcmp(name, "displacement") || !strcmp(name, "velocity") || !strcmp(name, "force") ||
      !strcmp(name, "principal_stress"))
    return 3;
  if (!strcmp(name, "stress") || !strcmp(name, "strain")) return 9;
  for (int k = 0; peri_frame_fields[k]; ++k)
    if (!strcmp(name, peri_frame_fields[k])) return 1;
  return 0;
}

/* The units of docs/deck.md section 15: SI, "1" for a ratio, "" for a number that counts. */
const char *peri_frame_field_unit(const char *name) {
  static const struct {
    const char *name, *unit;
  } units[] = {{"displacement", "m"},     {"velocity", "m/s"},       {"force", "N/m^3"},
               {"damage", "1"},           {"dilatation", "1"},       {"material", ""},
               {"volume", "m^3"},         {"strain_energy_density", "J/m^3"}, {"block", ""},
               {"stress", "Pa"},          {"strain", "1"},           {"von_mises", "Pa"},
               {"principal_stress", "Pa"}, {"temperature", "K"},     {"heat_flux", "W/m^2"},
               {"node_id", ""}, {"node_type", ""}, {"d2u", "1/m"}, {"horizon", "m"}, {"yield_index", "1"}, {"plastic_stretch", "1"}, {"spacing", "m"}, {"interface", ""}, {"body", ""},           {"reference_position", "m"}};
  for (size_t k = 0; k < sizeof units / sizeof units[0]; ++k)
    if (!strcmp(units[k].name, name)) return units[k].unit;
  return "";
}
