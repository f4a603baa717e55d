/* Contact (docs/contact.md): short-range forces between any two nodes closer than their
 * contact distance, bonded or not, within a body and across bodies. The settings and state;
 * the functions are in short_range.h. */
#ifndef PERI_CONTACT_H
#define PERI_CONTACT_H
#include <stdbool.h>
#include "peri/contact_ghosts.h"
#include "peri/contact_list.h"

/* The LAMMPS form of the short-range force (MODELS.md 17.1; Parks et al. 2008, LAMMPS
 * pair peri/pmb): between nodes closer than d_ij = min(0.9 |x_i - x_j|, 1.35 (r_i + r_j)),
 * r_i = dx/2, the force density on i is (c_S/delta) (d_ij - |y_i - y_j|) V_j along
 * (y_i - y_j)/|y_i - y_j|, with c_S = stiffness_factor x c. */
#define PERI_SHORT_RANGE_RATIO 0.9      /* of the reference distance (LAMMPS pair peri) */
#define PERI_SHORT_RANGE_RADIUS 1.35    /* of r_i + r_j (LAMMPS pair peri, lattice constant) */
#define PERI_SHORT_RANGE_FACTOR 15.0    /* c_S / c, Silling, EMU theory manual (2005) p. 18 */

typedef struct peri_contact {
  bool short_range;             /* contact.short_range given */
  double stiffness_factor;      /* c_S / c */
  double skin;                  /* list margin (m) */
  double prune_skin;            /* margin of the pruned list the forces visit (m), at most skin */
  double *c_material;           /* [materials] c of each material (PMB micromodulus of its K, E) */
  peri_contact_list list;       /* rows: the owned nodes */
  double *y_owned;              /* [3 y_owned_n] the owned nodes' deformed positions, between steps */
  int32_t y_owned_n;
  peri_contact_nodes nodes;     /* the nodes the list was built over: owned and, on MPI ranks, ghosts */
  peri_contact_ghosts ghosts;   /* their exchange (one process: none) */
  double min_ratio;             /* smallest |y_i - y_j| / d_ij of this rank's pairs at the last
                                   evaluation, at most 1 (1: no pair in contact) */
} peri_contact;

#endif
