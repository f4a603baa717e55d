/* Contributions: what a step adds to the model's internal force (external loads, the
 * indenter, the thermal strain of thermomechanics; later contact, coupling, tools). Each is
 * one file in src/solver/contributions/ that defines a peri_contribution_ops, plus its line
 * in the table of src/solver/contributions/contributions.c. The solvers never name a
 * contribution: they call the peri_contributions_* functions below, which go through the
 * active entries of the table in order. */
#ifndef PERI_CONTRIBUTION_H
#define PERI_CONTRIBUTION_H
#include <stdbool.h>
#include "peri/model.h"
#include "peri/sim.h"

typedef struct peri_contribution_ops {
  const char *name;
  /* Whether the simulation has it (from the deck). */
  bool (*active)(const peri_sim *s);
  /* Before the model's force of an explicit step ending at t (step number `step`): what the
   * internal force depends on, e.g. the thermal strain. 0, or PERI_ERR_RUN with a message.
   * NULL: nothing to do. */
  int (*before_force)(peri_sim *s, long step, double t);
  /* Adds its external force density at time t to b of the owned nodes. With `sets` it is the
   * first load of the evaluation and writes b of every owned node instead of adding (b was
   * not cleared for it); it is called so only when `sets_every_node` is true. NULL: no load. */
  void (*add_load)(peri_sim *s, double t, bool sets);
  bool sets_every_node;
  /* The load depends on the displacement (a rigid tool pressing on the body): quasi-static
   * solvers evaluate it again at every force evaluation. */
  bool follows_deformation;
  /* d(load)/du at the present state, row by row as the model tangent (model.h), for the
   * implicit solver. NULL: the load does not depend on u. */
  void (*tangent)(const peri_sim *s, peri_tangent_add_fn add, void *ctx);
} peri_contribution_ops;

/* The contributions of the table (src/solver/contributions/). */
extern const peri_contribution_ops peri_contribution_external_loads;
extern const peri_contribution_ops peri_contribution_indenter;
extern const peri_contribution_ops peri_contribution_thermal_strain;
extern const peri_contribution_ops peri_contribution_short_range;
extern const peri_contribution_ops peri_contribution_tools;

/* External force density at time t into p->b: b = 0, then the loads of the active
 * contributions in table order. */
void peri_apply_loads(peri_sim *s, double t);
/* The before_force step of every active contribution; stops at the first failure. */
int peri_contributions_before_force(peri_sim *s, long step, double t);
/* Whether an active load depends on the displacement (quasi-static: re-evaluate the loads). */
bool peri_loads_follow_deformation(const peri_sim *s);
/* The tangents of the active contributions, added through `add` (implicit solver). */
void peri_contributions_tangent(const peri_sim *s, peri_tangent_add_fn add, void *ctx);

#endif
