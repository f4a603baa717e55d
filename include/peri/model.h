/* The constitutive model interface. A new model is one file in src/model/ plus one line
 * in the table of src/model/model_table.c. Models never know which solver calls them. */
#ifndef PERI_MODEL_H
#define PERI_MODEL_H
#include <stdint.h>

typedef struct peri_sim peri_sim;

/* Receives (part of) row i of the tangent stiffness: for each of the count columns
 * j = cols[c] the 3x3 block K_ij = d f_i / d u_j (row-major, N/m^3 per m; f_i is the internal
 * force density of node i) at blocks[9c .. 9c+8], to be added to the row. i and j are local
 * node indices (owned nodes, then ghosts on MPI ranks). Each column appears once in a call.
 * In 1D and 2D only the dim x dim part of a block is used. */
typedef void (*peri_tangent_add_fn)(void *ctx, int32_t i, int32_t count, const int32_t *cols, const double *blocks);

typedef struct peri_model_ops {
  const char *name;
  /* Which elastic constants define it, for messages ("E or K", ...). */
  const char *description;
  /* Poisson ratio fixed by the model (bond-based), or 0 when free. */
  int fixed_poisson;
  /* Derives per-material constants (after elastic constants are resolved) and allocates
   * and fills model work arrays (e.g. weighted volume). Returns 0 or PERI_ERR_INPUT. */
  int (*init)(peri_sim *s);
  /* Overwrites s->disc.p.f of owned nodes with the internal force density at the current
   * displacement. When s->solver.breaking is set, first breaks every intact bond whose stretch
   * exceeds its critical stretch (symmetric in i and j); returns the number of directed
   * bonds broken in this call. */
  long (*force)(peri_sim *s);
  /* Strain energy density W_i of every owned node into W (bonds as they are). */
  void (*energy)(peri_sim *s, double *W);
  /* Scalar pair force density (t_ij + t_ji), N/m^6, of the intact bond k of node i whose
   * deformed length is r, at the state of the last force() call (dilatation, thermal
   * strain). The force on i is pair * beta V_j * (y_j - y_i)/r. Used by stress recovery. */
  double (*pair_force)(const peri_sim *s, int32_t i, int64_t k, double r);
  /* Node i's own half t_ij of it, where the two ends' halves differ by construction (the
   * position-aware correction); NULL or a half of pair_force otherwise. Stress recovery
   * collapses i's own force state, sum_j t_ij (y_j - y_i)/r (x) xi beta V_j. */
  double (*own_force)(const peri_sim *s, int32_t i, int64_t k, double r);
  /* Tangent stiffness at the current displacement (intact bonds, no breaking), one add call
   * at a time (from any thread). In a single process add is called once for every row. On
   * MPI ranks (collective: every rank calls it; ghost displacements current) a model may
   * also give parts of rows of ghost nodes (terms that need an owned family, for the
   * ghost's owner) and so give a row in several calls, which add up; it must then make those
   * calls in an order that does not depend on the threads (the sums are in that order).
   * Used by the implicit solver; NULL when the model has none. */
  void (*tangent)(const peri_sim *s, peri_tangent_add_fn add, void *ctx);
  /* Reach of the tangent in bonds: 1 when K_ij != 0 only for bonded i, j (bond-based), 2 when
   * neighbours of neighbours couple (state-based). The solver preallocates from it. */
  int tangent_reach;
} peri_model_ops;

/* Tangents of the built-in models (src/model/pmb_tangent.c, lps_tangent.c). */
void peri_pmb_tangent(const peri_sim *s, peri_tangent_add_fn add, void *ctx);
void peri_lps_tangent(const peri_sim *s, peri_tangent_add_fn add, void *ctx);

/* Frees the bond loops' work items (peri_sim.disc.node_blocks). */
struct peri_node_blocks;
void peri_node_blocks_free(struct peri_node_blocks *nb);
struct peri_geometry;
/* Coordinate `axis` of a node at x as the bond loops take it: on a lattice its exact
 * coordinate (peri_exact_coordinate), else x (src/model/node_blocks.c; the GPU's kernels). */
double peri_bond_coordinate(const struct peri_geometry *g, int axis, double x);
/* Share of the owned directed bonds that the bond loops run eight nodes at a time, the
 * bytes per directed bond of the blocks' templates and the share of the bonds in blocks that
 * read their offsets from the lattice's table (node_blocks.h); -1 before the first force
 * evaluation. */
double peri_node_blocks_share(const peri_sim *s, double *template_bytes_per_bond, double *lattice_share);
/* Upper bound of the template bytes per directed bond (for estimates before any is built). */
double peri_node_blocks_bytes_bound(void);

/* The model table. */
const peri_model_ops *peri_model_find(const char *name);
/* NULL-terminated list of model names (for deck choices). */
const char *const *peri_model_names(void);

#endif
