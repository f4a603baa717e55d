/* Thermomechanics (docs/heat.md): before the force of an explicit step, heat conduction is
 * advanced to the step's time (sub-cycled, src/solver/heat.c) and the thermal strain of
 * every node set from its temperature; the models subtract it from the bond stretch. */
#include "peri/contribution.h"
#include "peri/heat.h"

static bool thermal_active(const peri_sim *s) { return s->thermal != NULL; }

const peri_contribution_ops peri_contribution_thermal_strain = {
    .name = "thermal_strain",
    .active = thermal_active,
    .before_force = peri_thermal_couple,
};
