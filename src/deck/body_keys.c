/* The bodies key of the deck (docs/deck.md section 20, docs/contact.md "Bodies"): a list of
 * regions, each a separate body. A body keeps its own geometry (the fill items or mesh blocks
 * its region holds), material and initial velocity (an initial_velocity condition on its
 * region); what makes it a body is that no bond joins it to another body, so the bodies
 * interact only through contact. */
#include <stdlib.h>
#include "peri/bodies.h"
#include "peri/comm.h"
#include "peri/error.h"
#include "setup_parts.h"

#define TRY(x) do { int rc_ = (x); if (rc_ != PERI_OK) return rc_; } while (0)

/* Label of a node outside every body: such nodes keep their bonds among themselves. */
#define NO_BODY PERI_NO_BODY

int peri_setup_bodies(peri_sim *s, const peri_node *root) {
  const peri_node *list = peri_deck_get(root, "bodies");
  if (!list) return PERI_OK;
  if (list->kind != PERI_NODE_SEQUENCE || list->count < 1)
    return peri_deck_error(list, "key 'bodies': expected a list of region names, got %s",
                           peri_deck_kind_name(list));
  /* a region holds only the owned nodes of a rank, so a ghost's body is unknown there */
  if (peri_comm_size() > 1)
    return peri_deck_error(list, "key 'bodies': runs in one process (threads), not on %d MPI ranks; "
                                 "run without mpirun", peri_comm_size());
  const peri_node *regions = peri_deck_get(root, "regions");
  const peri_particles *p = &s->disc.p;
  int32_t *label = peri_malloc(sizeof(int32_t) * (size_t)(p->n > 0 ? p->n : 1));
  int32_t *first = peri_malloc(sizeof(int32_t) * (size_t)list->count); /* region of each body */
  for (int32_t i = 0; i < p->n; ++i) label[i] = NO_BODY;
  int rc = PERI_OK;
  for (int k = 0; k < list->count && rc == PERI_OK; ++k) {
    const peri_node *it = list->items[k];
    if (it->kind != PERI_NODE_SCALAR) {
      rc = peri_deck_error(it, "bodies: expected a region name, got %s", peri_deck_kind_name(it));
      break;
    }
    const int r = peri_setup_find_region(s, regions, it, it->scalar);
    if (r < 0) { rc = -r; break; }
    first[k] = r;
    for (int b = 0; b < k; ++b)
      if (first[b] == r) {
        rc = peri_deck_error(it, "bodies: region '%s' is listed twice", it->scalar);
        break;
      }
    const peri_region *reg = &s->cond.regions[r];
    if (rc == PERI_OK && reg->count == 0)
      rc = peri_deck_error(it, "bodies: region '%s' contains no node; a body needs nodes", reg->name);
    for (int32_t a = 0; a < reg->count && rc == PERI_OK; ++a) {
      const int32_t i = reg->nodes[a];
      if (label[i] != NO_BODY) {
        const double *x = &p->x[3 * i];
        rc = peri_deck_error(it, "bodies: bodies '%s' and '%s' overlap at t = 0: both hold the node at "
                                 "(%g, %g, %g); a node belongs to at most one body, so separate their regions",
                             s->cond.regions[first[label[i]]].name, reg->name, x[0], x[1], x[2]);
        break;
      }
      label[i] = k;
    }
  }
  if (rc != PERI_OK) {
    free(first);
    free(label);
    return rc;
  }
  peri_bonds_keep_within(&s->disc.bonds, label);
  /* kept for the body output field and the per-body sums of history.csv */
  peri_bodies *bodies = peri_calloc(1, sizeof *bodies);
  *bodies = (peri_bodies){.count = list->count, .region = first, .label = label};
  s->bodies = bodies;
  return PERI_OK;
}
