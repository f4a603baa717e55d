/* Peridynamics coupled with finite elements without overlap (docs/coupling.md; Ongaro 2022,
 * 002_b20c318388227af9.txt ch. 2, MODELS.md section 14): every node is FEM or PD. FEM rows of
 * the stiffness take element contributions only (elements that straddle the interface
 * reference PD nodes in their columns); PD rows take bond contributions only, to every
 * neighbour, FEM or PD. The global stiffness is therefore not symmetric. The PD side is the
 * linear bond-based model with the micromodulus family lambda(|xi|) = gamma c / |xi|^alpha,
 * or a state-based model (lps) linearised: its tangent at u = 0.
 * The FEM mesh is the structured one of the PD lattice: bars (1D), Q4 (2D), Hex8 (3D), or a
 * graded mesh of it (include/peri/fem_mesh.h). */
#ifndef PERI_COUPLING_H
#define PERI_COUPLING_H
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "peri/material.h"
#include "peri/model.h"

typedef struct peri_sim peri_sim;

/* coupling.tractions: a point of a straight interface at which the history reports the
 * discrete nonlocal traction (eqs. A.15, A.34) and the local one of the FEM side (eq. 2.107
 * and its 2D/3D form: the stress of the bilinear field of the lattice nodes around the point) */
typedef struct peri_interface_traction {
  char *name;
  double at[3];            /* on a line of nodes, midway between two nodes along the normal */
  int axis, sign;          /* normal sign e_axis, from the PD side into the FEM side */
  int material;            /* of the FEM node across the interface: E, nu of the local traction */
  double reach[3][2];      /* tangential axis d: the nodes at -reach[d][0], +reach[d][1] (0 or dx) */
} peri_interface_traction;

typedef struct peri_coupling {
  int32_t n_nodes;         /* owned nodes */
  int32_t *node_type;      /* [n] 1: PD node, 0: FEM node (the output field node_type) */
  int32_t n_pd;            /* PD nodes */
  double alpha;            /* micromodulus exponent */
  double gamma;            /* correction factor of the micromodulus (App. A eq. 2.39) */
  double *c;               /* [n_materials] micromodulus constant c of lambda = c / |xi|^alpha */
  int corners;             /* nodes per element of the lattice's own mesh: 2, 4, 8 */
  int32_t n_elements;
  int64_t *element_offset; /* [n_elements + 1]: the corners of e are element_nodes[element_offset[e] ..] */
  int32_t *element_nodes;
  int32_t *element_material;
  double *element_K;       /* the element stiffness matrices: one per material on the lattice's own
                            * mesh (all its cells are alike), one per element on a graded mesh */
  int64_t *element_K_offset; /* [n_elements] where element e's (dim corners)^2 entries start */
  uint8_t *fem_only;       /* [n] 1: a node of a graded mesh that may not become PD (fem_mesh.h); NULL without */
  int32_t coarse_nodes;    /* graded mesh: nodes of coarse elements, lattice nodes left out */
  int32_t removed_nodes;
  char *mesh_file;         /* coupling.mesh: the file of the FEM part's elements, NULL without */
  int64_t *node_offset;    /* [n + 1] elements of node i: node_element[node_offset[i] ...] */
  int32_t *node_element;
  /* exact partial volumes (partial_volume: exact): the family of a PD node is every lattice
   * node whose cell meets its horizon disk (interval in 1D), with beta = the part of the cell
   * inside; the same for every node of the lattice, so kept per lattice offset */
  struct peri_lattice *lattice; /* the node lattice (elements, exact volumes, switching) */
  bool exact_volumes;      /* false: the bonds and the family's partial-volume rule */
  int32_t n_offsets;
  int32_t *offset;         /* [3 n_offsets] lattice offsets of the family */
  double *offset_beta;     /* [n_offsets] */
  /* state-based PD side: the rows of the PD nodes from the model's tangent at u = 0 (the
   * linearised model), kept; NULL for the bond-based rows */
  int32_t *tangent_count;  /* [n] columns of row i (0 for FEM nodes) */
  int32_t **tangent_cols;
  double **tangent_blocks;
  /* adaptive switching (002_b20c318388227af9.txt §2.7, src/fem/switching.c): FEM nodes within
   * switch_radius * delta of a PD node that lost a bond become PD nodes; 0: no switching */
  double switch_radius;
  int32_t n_switch_offsets;
  int32_t *switch_offset;  /* [3 n_switch_offsets] lattice offsets within switch_radius * delta */
  /* coupling.balance_regions: the regions (indices into the deck's regions) whose reactions
   * enter e_r of eqs. 2.114, 2.116 (the supports and load points); 0 regions: none */
  int n_balance_regions;
  int *balance_region;
  int n_tractions;
  peri_interface_traction *traction;
} peri_coupling;

/* Area of the disk of radius r centred at the origin inside the rectangle [x0, x1] x [y0, y1],
 * exact (src/fem/cell_overlap.c). */
double peri_disk_rectangle_area(double x0, double x1, double y0, double y1, double r);

/* The micromodulus constant c of lambda(|xi|) = c/|xi|^alpha that matches the elastic
 * modulus E over a full horizon delta (MODELS.md 2.4; 002_b20c318388227af9.txt eqs. 2.15, 2.34):
 * 1D (3 - alpha) E/(A delta^(3-alpha)), A the cross-section; 2D 4 K2D (6 - alpha)/(pi h delta^(6-alpha))
 * with K2D = 3E/4 (plane stress, nu = 1/3) or 4E/5 (plane strain, nu = 1/4), h the thickness;
 * 3D 3 (7 - alpha) E/(pi delta^(7-alpha)) (nu = 1/4). NaN when alpha is out of range
 * (alpha < 3, 6, 7 in 1D, 2D, 3D). */
double peri_coupling_micromodulus(int dim, peri_plane plane, double E, double alpha, double delta, double thickness,
                                  double cross_section);

/* Builds the coupling of s: the nodes of the ascending list pd_nodes are PD, every other node
 * FEM; the elements of the node lattice (spacing dx) that have an FEM corner. A model with a
 * tangent of reach 2 (state-based) gives the PD rows from its tangent at the current (zero)
 * displacement; alpha, gamma and exact_volumes then do not apply. exact_volumes:
 * the PD families and partial volumes by exact cell-horizon intersection (1D and 2D). On bad
 * input (a node off the lattice, an FEM node in no element, alpha out of range) writes a message
 * naming the node into why (size n) and returns PERI_ERR_INPUT. */
int peri_coupling_build(peri_sim *s, const int32_t *pd_nodes, int32_t n_pd_nodes, double alpha, double gamma,
                        bool exact_volumes, char *why, size_t n);
/* Sets the switching radius r (in horizons; 0: none) and applies it to the bonds broken so far
 * (pre-cracks): every node with a broken bond becomes a PD node, and every node within r delta
 * of one (the initial PD patch around notches). Bond-based PD side with the bonds' partial
 * volumes only. Returns PERI_ERR_INPUT with a message in why (size n) when a node of the patch
 * may not become PD (graded meshes: too near the coarse part). */
int peri_coupling_set_switching(peri_sim *s, double radius, char *why, size_t n);
/* peri_coupling_build with the FEM part's elements from mesh (a graded mesh of the lattice,
 * include/peri/fem_mesh.h) instead of the lattice's own cells: the element stiffness is that of
 * each element's corners; a PD node the mesh marks fem_only is an error naming the node. */
struct peri_fem_mesh;
int peri_coupling_build_on_mesh(peri_sim *s, const struct peri_fem_mesh *mesh, const int32_t *pd_nodes,
                                int32_t n_pd_nodes, double alpha, double gamma, bool exact_volumes, char *why,
                                size_t n);
/* Quasi-static fracture of the coupled model (MODELS.md 12.4, 14.5): breaks every intact bond
 * with a PD end whose linearised stretch xi.(u_j - u_i)/|xi|^2 reaches its critical stretch
 * (both directions; no-fail nodes never), then switches the FEM nodes within r delta of the PD
 * nodes that lost a bond to PD, and refreshes f = K u. Returns the directed bonds broken, or -1
 * after a message when a node to switch may not become PD (it reaches the coarse part of a
 * graded mesh: the run stops there). */
long peri_coupling_break(peri_sim *s);
/* MPI ranks (src/fem/coupling_ranks.c): before peri_decompose, the nodes each row reads
 * beyond its bonds (s->par.reach_*), which become ghosts; after it, the coupling in the
 * rank's local numbering. peri_coupling_localize returns PERI_ERR_RUN, with a message, when a
 * row would read a node that is not on the rank. */
void peri_coupling_set_reach(peri_sim *s);
int peri_coupling_localize(peri_sim *s);
void peri_coupling_free(peri_coupling *c);

/* Rows of the coupled stiffness in the convention of the model tangents (model.h): blocks
 * K_ij = d f_i / d u_j of the force density, FEM rows -K^e / V_i. Linear: it does not depend on
 * the displacement. Broken bonds are left out. */
void peri_coupling_rows(const peri_sim *s, peri_tangent_add_fn add, void *ctx);
/* The rows a node can have in a run that switches (solver.breaking with a switch_radius): its
 * present row and, for an FEM node that may become PD, its PD row too. A node's row depends on
 * its own type only (an FEM row holds the node's elements, none of them all PD; a PD row its
 * intact bonds), so a bound over these rows holds before and after any switch. */
void peri_coupling_switchable_rows(const peri_sim *s, peri_tangent_add_fn add, void *ctx);
/* The internal force density of the coupled model at the current displacement into p->f of
 * the owned nodes: f = K u row by row. */
void peri_coupling_force(peri_sim *s);
/* The discrete nonlocal traction at the point x0 of a straight interface whose normal is
 * the axis `axis` (0 x, 1 y, 2 z) pointing `sign` (+1 or -1) from the PD side into the FEM side
 * (002_b20c318388227af9.txt eqs. A.15, A.34): the bond forces that the FEM nodes across the
 * interface exert on the PD nodes on the line from x0 a depth delta into the PD side, per unit
 * area of the interface (1D: per cross-section A; 2D: per dx h; 3D: per dx^2), at the current
 * displacement. */
void peri_coupling_nonlocal_traction(const peri_sim *s, const double x0[3], int axis, int sign, double out[3]);
/* The local traction t(x0, -n) = -sigma n of the FEM side at tr->at (n = sign e_axis): the
 * stress of the lattice nodes' bilinear field there, its normal derivative (u+ - u-)/dx from
 * the two nodes that straddle the point (eq. 2.107), its tangential ones by central
 * differences over the two rows of nodes (one-sided at a body's edge), with Hooke's law of the
 * material (1D E, 2D plane stress or strain, 3D isotropic). */
void peri_coupling_local_traction(const peri_sim *s, const peri_interface_traction *tr, double out[3]);
/* Checks that tr->at lies on a line of nodes midway between two nodes along the normal and
 * fills its material and reach from the nodes (global numbering, before any decomposition).
 * PERI_ERR_INPUT with a message in why (size n) otherwise. */
int peri_coupling_traction_locate(const peri_sim *s, peri_interface_traction *tr, char *why, size_t n);
/* The balance of the nodal forces F_i = -V_i f_i (= (K u)_i): net[d] = sum_i F_id,
 * ratio[d] = |net_d| / sum_i |F_id| (e_r per axis, eq. 2.40) and ratio[3] = |net| / sum_i |F_i|
 * (e_r, eq. 2.38; in 1D the two agree). */
void peri_coupling_balance(const peri_sim *s, double net[3], double ratio[4]);
/* coupling.gamma: auto (src/fem/linear_field_gamma.c): the gamma of Remark A.2 for the family
 * of the PD rows, the classical stress of a linear field over the discrete one (0.9784710341
 * with the exact partial volumes at m = 3), and the rows' micromoduli rescaled to a gamma. */
double peri_coupling_linear_field_gamma(const peri_sim *s);
void peri_coupling_set_gamma(peri_sim *s, double gamma);

#endif
