/* Exodus II results file (output.format: exodus), the format Peridigm writes and ParaView,
 * VisIt and the SEACAS tools read: the reference configuration once, one SPHERE element per
 * node in element blocks, node variables and global variables at each time step
 * (src/io/exodus_writer.c). The writer knows no simulation: it receives arrays. */
#ifndef PERI_EXODUS_WRITER_H
#define PERI_EXODUS_WRITER_H
#include <stdbool.h>
#include <stdint.h>

typedef struct peri_exodus peri_exodus;

/* Whether this peri was built with the Exodus II library (libexodusii-dev). */
bool peri_exodus_available(void);

/* The mesh of an Exodus file: n nodes at `reference` ([3n]; the first `dim` coordinates are
 * written), node k numbered k + 1; element block b (id block_ids[b] > 0, name block_names[b])
 * holds the nodes with group[k] == b as SPHERE elements of one node each, element k's id being
 * its node's, with the attribute `volume` (volume[k]). */
typedef struct peri_exodus_mesh {
  const char *title;
  int dim;
  int64_t n;
  const double *reference, *volume;
  const int32_t *group;
  int n_blocks;
  const int32_t *block_ids;
  const char *const *block_names;
} peri_exodus_mesh;

/* Creates (replacing) the file at path with the mesh and the names of the node variables
 * and global variables written at each step. NULL with a message naming the path on failure. */
peri_exodus *peri_exodus_create(const char *path, const peri_exodus_mesh *mesh, int n_node_vars,
                                const char *const *node_var_names, int n_global_vars,
                                const char *const *global_var_names);
/* Appends a time step: node_vars[v] holds the n values of node variable v, globals the global
 * variables (NULL: zeros). Flushed to disk, so a run that stops keeps the steps written.
 * Returns 0 or PERI_ERR_RUN with a message. */
int peri_exodus_write_step(peri_exodus *e, double time, const double *const *node_vars, const double *globals);
/* Replaces the global variables of time step `step` (from 1), e.g. when they are known only
 * after the step's node variables. */
int peri_exodus_globals(peri_exodus *e, int step, const double *globals);
/* A restarted run (docs/restart.md): copies the first n_steps time steps of the Exodus file at
 * old_path (written by the run it restarts, with the same nodes and variables) into e.
 * Returns 0 or PERI_ERR_RUN with a message naming old_path. */
int peri_exodus_copy_steps(peri_exodus *e, const char *old_path, int n_steps);
/* Time steps written so far. */
int peri_exodus_steps(const peri_exodus *e);
/* Closes the file; returns 0 or PERI_ERR_RUN with a message. NULL is allowed. */
int peri_exodus_close(peri_exodus *e);

#endif
