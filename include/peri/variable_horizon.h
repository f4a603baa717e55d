/* The models with a horizon per node (src/model/variable_horizon.c, docs/variable_horizon.md). */
#ifndef PERI_VARIABLE_HORIZON_H
#define PERI_VARIABLE_HORIZON_H
#include "peri/model.h"

/* The variant of a model of the table for a horizon that varies over the body
 * (s->disc.horizon_field set), or NULL when the model has none. It has the model's name and
 * no tangent stiffness. */
const peri_model_ops *peri_variable_horizon_model(const peri_model_ops *model);

#endif
