/* Several bodies in one deck (docs/contact.md "Bodies"): which body each node belongs to,
 * and the per-body sums of history.csv (src/post/body_sums.c). */
#ifndef PERI_BODIES_H
#define PERI_BODIES_H
#include <stdbool.h>
#include <stdint.h>

struct peri_sim;

/* Label of a node outside every body. */
#define PERI_NO_BODY (-1)

/* output.penetration of a body (docs/contact.md "Bodies"): its direction of travel and the
 * reference position, along it, of the foremost node of everything else in its path */
typedef struct peri_penetration {
  bool on;
  double direction[3];          /* unit */
  double face;                  /* min X . direction over the other nodes in the body's path */
} peri_penetration;

typedef struct peri_bodies {
  int count;
  int *region;                  /* [count] the region of each body (its name is the region's) */
  int32_t *label;               /* [n] the body of each node, PERI_NO_BODY outside every body */
  peri_penetration *penetration; /* [count] */
} peri_bodies;

/* Per-body sums of history.csv: mass, momentum, kinetic energy, the mass of the damaged
 * (damage index > 0) and of the detached (damage index 1) nodes, and with output.penetration
 * the penetration depth: the largest (x + u) . direction over the body's attached nodes
 * (damage index below 1; all its nodes once every one is detached) minus the face. */
typedef struct peri_body_sums {
  double mass, momentum[3], kinetic_energy, damaged_mass, detached_mass, penetration;
} peri_body_sums;

/* out[b] for every body b, each summed over its nodes in the fixed blocks of the global node
 * order (the same on any thread and rank count); every rank must call it. */
void peri_body_sums_now(const struct peri_sim *s, peri_body_sums *out);
/* After the decomposition over MPI ranks: each node's body label for the rank's owned nodes and
 * ghosts (a no-op in one process or without bodies). */
void peri_bodies_localize(struct peri_sim *s);
void peri_bodies_free(peri_bodies *b);

#endif
