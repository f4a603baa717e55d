/* The candidate pairs of short-range contact (docs/contact.md): a Verlet list with a skin,
 * built from a cell list over the deformed positions, rebuilt only when some node has moved
 * more than half the skin since the last build. */
#ifndef PERI_CONTACT_LIST_H
#define PERI_CONTACT_LIST_H
#include <stdbool.h>
#include <stdint.h>

typedef struct peri_contact_list {
  int32_t n;            /* nodes of the last build */
  int64_t *offset;      /* [n+1]: the partners of node i are partner[offset[i] .. offset[i+1]-1] */
  int32_t *partner;     /* sorted by index within each node */
  double *reach;        /* [entries] contact distance d_ij of each entry */
  int64_t capacity;     /* entries allocated */
  double *u_built;      /* [3n] displacement at the last build */
  long builds;          /* number of builds so far */
} peri_contact_list;

/* The reach of a pair: d_ij = min(ratio |x_i - x_j|, max_reach) (reference positions). */
typedef struct peri_contact_reach {
  double ratio;         /* 0.9 in the LAMMPS form */
  double max_reach;     /* 1.35 (r_i + r_j) */
  double skin;          /* list margin: pairs within d_ij + skin are listed */
} peri_contact_reach;

/* Whether the list must be (re)built for displacements u of nodes 0..n-1: never built, a
 * different node count, or some node moved more than skin/2 since the build. */
bool peri_contact_list_stale(const peri_contact_list *l, const double *u, int32_t n, double skin);
/* Builds the list of every ordered pair (i, j), i != j, with |y_i - y_j| < d_ij + skin,
 * y = x + u, from a cell list; each node's partners in index order (the same list for any
 * thread count). */
void peri_contact_list_build(peri_contact_list *l, const double *x, const double *u, int32_t n,
                             const peri_contact_reach *reach);
void peri_contact_list_free(peri_contact_list *l);

#endif
