/* The candidate pairs of short-range contact (docs/contact.md): a Verlet list with a skin,
 * built from a cell list over the deformed positions, rebuilt only when some node has moved
 * more than half the skin since the last build. */
#ifndef PERI_CONTACT_LIST_H
#define PERI_CONTACT_LIST_H
#include <stdbool.h>
#include <stdint.h>

typedef struct peri_contact_list {
  int32_t n;            /* rows of the last build (the nodes whose partners are listed) */
  int64_t *offset;      /* [n+1]: the partners of row i are partner[offset[i] .. offset[i+1]-1] */
  int32_t *partner;     /* indices among the nodes of the build, sorted within each row */
  double *reach;        /* [entries] contact distance d_ij of each entry */
  int64_t capacity;     /* entries allocated */
  double *u_built;      /* [3n] displacement of the rows at the last build */
  long builds;          /* number of builds so far */
} peri_contact_list;

/* The reach of a pair: d_ij = min(ratio |x_i - x_j|, max_reach) (reference positions). */
typedef struct peri_contact_reach {
  double ratio;         /* 0.9 in the LAMMPS form */
  double max_reach;     /* 1.35 (r_i + r_j) */
  double skin;          /* list margin: pairs within d_ij + skin are listed */
} peri_contact_reach;

/* Whether the list must be (re)built for displacements u of its rows 0..n-1: never built, a
 * different row count, or some row moved more than skin/2 since the build (on MPI ranks the
 * caller combines the ranks' answers: a node's partners on other ranks move too). */
bool peri_contact_list_stale(const peri_contact_list *l, const double *u, int32_t n, double skin);
/* Builds, over n nodes of reference positions x and deformed positions y, the list of every
 * pair (i, j), i one of the rows first_row .. first_row + rows - 1 and j != i any of the n
 * nodes, with |y_i - y_j| < d_ij + skin, from a cell list; each row's partners in index
 * order (the same list for any thread count). u_rows: the rows' displacements, kept for
 * peri_contact_list_stale. */
void peri_contact_list_build(peri_contact_list *l, const double *x, const double *y, int32_t n, int32_t first_row,
                             int32_t rows, const double *u_rows, const peri_contact_reach *reach);
void peri_contact_list_free(peri_contact_list *l);

#endif
