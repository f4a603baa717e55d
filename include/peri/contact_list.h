/* The candidate pairs of short-range contact (docs/contact.md): a Verlet list with a skin,
 * built from a cell list over the deformed positions, rebuilt only when some node has moved
 * more than half the skin since the last build; and, within it, a pruned list with a smaller
 * skin that the forces visit, pruned again from the full list (no cells) when some node has
 * moved more than half of that skin since the last prune. */
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
  /* the pruned list: row i's partners within d_ij + prune skin at the last prune, in index
   * order, are pruned_partner[offset[i] .. pruned_end[i]-1] (the front of the row's range) */
  int64_t *pruned_end;      /* [n] */
  int32_t *pruned_partner;  /* [capacity] */
  double *pruned_reach;     /* [capacity] */
  double *u_pruned;         /* [3n] displacement of the rows at the last prune */
  long prunes;              /* number of prunes so far (each build is followed by one) */
} peri_contact_list;

/* What the list needs before the next force evaluation. */
typedef enum { PERI_CONTACT_LIST_FRESH = 0, PERI_CONTACT_LIST_PRUNE = 1, PERI_CONTACT_LIST_BUILD = 2 } peri_contact_list_need;

/* The reach of a pair: d_ij = min(ratio |x_i - x_j|, max_reach) (reference positions). */
typedef struct peri_contact_reach {
  double ratio;         /* 0.9 in the LAMMPS form */
  double max_reach;     /* 1.35 (r_i + r_j) */
  double skin;          /* list margin: pairs within d_ij + skin are listed */
} peri_contact_reach;

/* What the list needs for displacements u of its rows 0..n-1 (reference positions x): a build
 * if it was never built, has a different row count, or some row moved more than skin/2 since
 * the build; else a prune if some row moved more than prune_skin/2 since the last prune (on
 * MPI ranks the caller combines the ranks' answers, the largest need: a node's partners on
 * other ranks move too). Writes the rows' deformed positions x + u to y on the way. */
peri_contact_list_need peri_contact_list_needs(const peri_contact_list *l, const double *x, const double *u, int32_t n,
                                               double skin, double prune_skin, double *y);
/* Builds, over n nodes of reference positions x and deformed positions y, the list of every
 * pair (i, j), i one of the rows first_row .. first_row + rows - 1 and j != i any of the n
 * nodes, with |y_i - y_j| < d_ij + skin, from a cell list; each row's partners in index
 * order (the same list for any thread count). u_rows: the rows' displacements, kept for
 * peri_contact_list_needs. The caller prunes it next. */
void peri_contact_list_build(peri_contact_list *l, const double *x, const double *y, int32_t n, int32_t first_row,
                             int32_t rows, const double *u_rows, const peri_contact_reach *reach);
/* Prunes the built list over deformed positions y of its n nodes: of each row's partners,
 * those with |y_i - y_j| < d_ij + prune_skin, in index order. Every pair in contact until a
 * node moves prune_skin/2 from u_rows (the rows' displacements, kept) is in the pruned list,
 * since the pair's distance changes by less than prune_skin by then. */
void peri_contact_list_prune(peri_contact_list *l, const double *y, int32_t first_row, const double *u_rows,
                             double prune_skin);
void peri_contact_list_free(peri_contact_list *l);

#endif
