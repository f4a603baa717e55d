/* Building a simulation from a deck (src/deck/): the whole simulation, and the readers of
 * each section that other parts declare keys for. Every input error is reported at its
 * file:line:column with exit status 2 before any work. */
#ifndef PERI_SETUP_H
#define PERI_SETUP_H
#include "peri/deck.h"
#include "peri/shape.h"
#include "peri/sim.h"

/* Reads the deck and builds the simulation: every input error is reported (exit status 2)
 * before any work. `overrides` are "--output DIR" etc. applied after parsing. */
int peri_sim_from_deck(peri_sim *s, const char *path);
/* The same with "key.path=value" overrides applied to the deck first (--set). */
int peri_sim_from_deck_with(peri_sim *s, const char *path, int n_sets, const char *const *sets);
/* The same from the YAML text of a deck, named `name` in messages; relative paths in it (a
 * node file) are taken from name's folder (the C API, include/peri/api.h). */
int peri_sim_from_string_with(peri_sim *s, const char *text, const char *name, int n_sets, const char *const *sets);
void peri_sim_free(peri_sim *s);

/* Parses a shape mapping such as
 *   {shape: box, min: [0, 0], max: [0.1, 0.04]}
 *   {shape: circle, center: [0.05, 0.02], radius: 0.01}      (alias: disk, sphere)
 *   {shape: cylinder, center: [0,0,0], axis: z, radius: 0.025, inner_radius: 0.02, length: 0.1}
 *   {shape: polygon, vertices: [[0,0], [1,0], [0,1]]}
 *   {shape: all}
 * For dim < 3 the missing coordinates of min/max/center are 0 (boxes are unbounded in the
 * unused directions). `extra_keys` (NULL-terminated, may be NULL) are keys the caller
 * reads from the same mapping (e.g. "material", "name"); they are allowed here.
 * Returns PERI_OK or PERI_ERR_INPUT with a message. */
int peri_shape_parse(const peri_node *map, int dim, const char *section,
                     const char *const *extra_keys, peri_shape *out);

/* Reads the quasi-static keys of the `solver` mapping (type already set in s->solver.kind) and
 * the shared ones it uses (end_time, time_step, safety_factor, damping, breaking); sets
 * s->solver.steps = load_steps. Explicit: rejects the quasi-static keys. Returns PERI_OK or
 * PERI_ERR_INPUT after a positioned message. */
int peri_quasi_static_parse(peri_sim *s, const peri_node *solver);
/* solver.dynamic_switch (docs/solvers.md section 4, src/deck/qs_dynamic_parse.c): reads the
 * mapping into s->solver.qs.dynamic (off when absent). Returns PERI_OK or PERI_ERR_INPUT. */
int peri_qs_dynamic_parse(peri_sim *s, const peri_node *solver);
/* Reads the implicit keys of the `solver` mapping (linear_solver, petsc_preconditioner,
 * newton_tolerance, petsc_options) into s->solver.qs; rejects them for other solver types and
 * rejects type implicit in a build without PETSc. Called by peri_quasi_static_parse after
 * the shared keys. Returns PERI_OK or PERI_ERR_INPUT after a positioned message. */
int peri_implicit_parse(peri_sim *s, const peri_node *solver);

/* Reads output.checkpoint_every and output.checkpoint_file of the `output` mapping.
 * Returns PERI_OK or PERI_ERR_INPUT after a positioned message. */
int peri_checkpoint_parse(peri_sim *s, const peri_node *output);
/* Refuses an output.checkpoint_file that would overwrite a file of the run (history.csv,
 * the .pvd, frames, picture, plot) or one it reads (the deck, its node file), once the
 * output section is read (src/deck/checkpoint_names.c). PERI_OK or PERI_ERR_INPUT after a
 * message at the key. */
int peri_checkpoint_check_names(const peri_sim *s, const peri_node *root);

/* Reads output.dataset (docs/datasets.md) into s->out.dataset (NULL when absent). PERI_OK or
 * PERI_ERR_INPUT after a positioned message (src/deck/dataset_keys.c). */
int peri_dataset_parse(peri_sim *s, const peri_node *output);

/* output.plot: {x: COLUMN, y: COLUMN}. peri_plot_parse reads the names (with the rest of
 * `output`); peri_plot_check, once the whole simulation is set up (thermal columns
 * included), checks that history.csv will have them. Both return PERI_OK or
 * PERI_ERR_INPUT after a positioned message. */
int peri_plot_parse(peri_sim *s, const peri_node *output);
int peri_plot_check(const peri_sim *s, const peri_node *output);

#endif
