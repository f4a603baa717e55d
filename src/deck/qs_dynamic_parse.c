/* solver.dynamic_switch: when a quasi-static run meets unstable crack growth it continues in
 * explicit dynamics at the held load, and returns to load steps when the crack has arrested
 * (docs/solvers.md section 4; keys in docs/deck.md section 14). */
#include <math.h>
#include <string.h>
#include "peri/error.h"
#include "peri/quasistatic.h"
#include "peri/setup.h"

#define TRY(expr)                   \
  do {                              \
    int rc_ = (expr);               \
    if (rc_ != PERI_OK) return rc_; \
  } while (0)

static int count_at_least(const peri_node *map, const char *key, long min, long *out) {
  TRY(peri_deck_int(map, key, false, out));
  if (peri_deck_get(map, key) && *out < min)
    return peri_deck_error(peri_deck_get(map, key), "key '%s': must be >= %ld", key, min);
  return PERI_OK;
}

int peri_qs_dynamic_parse(peri_sim *s, const peri_node *solver) {
  peri_qs_dynamic_switch *d = &s->solver.qs.dynamic;
  memset(d, 0, sizeof *d);
  const peri_node *map = peri_deck_get(solver, "dynamic_switch");
  if (!map) return PERI_OK;
  static const char *const keys[] = {"when_broken_exceeds", "time_step", "safety_factor", "damping",
                                     "arrest_kinetic_energy", "arrest_steps", "max_dynamic_steps",
                                     "history_every", NULL};
  TRY(peri_deck_allow(map, "solver.dynamic_switch", keys));
  if (!s->solver.breaking)
    return peri_deck_error(map, "solver.dynamic_switch: needs bonds that break (solver.breaking: true)");
  d->on = true;
  /* by default the switch takes over where cutting the load step back gives up */
  d->when_broken_exceeds = s->solver.qs.max_broken_per_step;
  d->safety_factor = 0.8;
  d->arrest_kinetic_energy = 1e-3;
  d->max_dynamic_steps = 100000;
  d->history_every = 100;
  TRY(count_at_least(map, "when_broken_exceeds", 0, &d->when_broken_exceeds));
  if (!peri_deck_get(map, "when_broken_exceeds") && d->when_broken_exceeds <= 0)
    return peri_deck_error(map, "solver.dynamic_switch: give 'when_broken_exceeds' (directed bonds broken in "
                                "one load step that start a dynamic phase) or solver.max_broken_per_step");
  TRY(count_at_least(map, "arrest_steps", 0, &d->arrest_steps));
  TRY(count_at_least(map, "max_dynamic_steps", 1, &d->max_dynamic_steps));
  TRY(count_at_least(map, "history_every", 1, &d->history_every));
  TRY(peri_deck_double(map, "time_step", false, &d->time_step));
  if (peri_deck_get(map, "time_step") && !(d->time_step > 0.0))
    return peri_deck_error(peri_deck_get(map, "time_step"), "key 'time_step': must be positive");
  TRY(peri_deck_double(map, "safety_factor", false, &d->safety_factor));
  if (!(d->safety_factor > 0.0 && d->safety_factor <= 1.0))
    return peri_deck_error(peri_deck_get(map, "safety_factor"), "key 'safety_factor': must be in (0, 1]");
  TRY(peri_deck_double(map, "damping", false, &d->damping));
  if (!(d->damping >= 0.0) || !isfinite(d->damping))
    return peri_deck_error(peri_deck_get(map, "damping"), "key 'damping': must be >= 0 (1/s)");
  TRY(peri_deck_double(map, "arrest_kinetic_energy", false, &d->arrest_kinetic_energy));
  if (!(d->arrest_kinetic_energy > 0.0 && d->arrest_kinetic_energy < 1.0))
    return peri_deck_error(peri_deck_get(map, "arrest_kinetic_energy"),
                           "key 'arrest_kinetic_energy': must be in (0, 1) (a fraction of the phase's peak "
                           "kinetic energy)");
  return PERI_OK;
}
