/* Checkpoints and restart (docs/restart.md): the state of a run in an HDF5 file, written
 * every output.checkpoint_every steps and at the end, and read back by
 * `peri run DECK --restart FILE` to continue the run bitwise as if it had not stopped.
 *
 * Per-node arrays are stored whole, in the node order of the discretization (a
 * deterministic function of the deck), and per-bond arrays in bond order: a checkpoint
 * does not depend on how the nodes were split between processes. On MPI ranks, rank 0
 * gathers every rank's owned nodes and families and writes the file a single process would
 * write; a restart on any number of ranks takes each rank's nodes and bonds from it. */
#ifndef PERI_CHECKPOINT_H
#define PERI_CHECKPOINT_H
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include "peri/sim.h"

/* Version of the file layout; a reader takes this version and older ones. */
#define PERI_CHECKPOINT_FORMAT_VERSION 1

/* What the run's output held at the checkpoint: a restart keeps exactly this much of the
 * .pvd series and of history.csv and continues after it. */
typedef struct peri_checkpoint_progress {
  long frames;       /* VTU frames written (the next one is NAME_<frames>.vtu) */
  long history_rows; /* history.csv rows written after the header */
} peri_checkpoint_progress;

/* Whether this build reads and writes checkpoints (it was built with HDF5). */
bool peri_checkpoint_supported(void);

/* Writes the state of s to path (through path.tmp and a rename, so a crash never leaves a
 * half-written file). On MPI ranks it is collective: rank 0 gathers the arrays in global
 * order and writes, and every rank returns the same status. Returns PERI_OK, or
 * PERI_ERR_RUN with a message. */
int peri_checkpoint_write(const peri_sim *s, const char *path, const peri_checkpoint_progress *done);

/* Reads the checkpoint `path` for the simulation s, built from the deck as usual (with the
 * output directory already final; on MPI ranks every rank reads it, before peri_decompose,
 * on the whole discretization), checks that the deck builds the same discretization
 * and solver, and keeps its state in s->state.restart; reads the history.csv rows and .pvd
 * frames of the output directory written up to the checkpoint. Writes nothing. Returns
 * PERI_OK, or PERI_ERR_INPUT with a message (missing, damaged or mismatched checkpoint,
 * or a build without HDF5). */
int peri_restart_load(peri_sim *s, const char *path);

/* One summary line: the checkpoint, its step and time. */
void peri_restart_print(const peri_sim *s, FILE *out);

/* Puts the checkpoint's state into s (after peri_apply_initial_conditions, which marks the
 * prescribed components): time, step, fields, broken bonds, solver and heat state. On MPI
 * ranks (after peri_decompose) each rank takes its local nodes, owned and ghosts, by
 * global index, and the bonds of its families. Call it once: it then frees the
 * checkpoint's arrays (whole-problem copies on every rank). */
void peri_restart_apply(peri_sim *s);

/* The history.csv rows kept from before the checkpoint ([rows][n_columns], row-major), or
 * NULL when there are none. */
const double *peri_restart_history(const peri_sim *s, long *rows, int *n_columns);
/* The column names of the history.csv those rows come from (NULL when no row is kept). */
char *const *peri_restart_history_names(const peri_sim *s, int *n_columns);

/* The frames of the .pvd kept from before the checkpoint: the number of frames written by
 * then (the index of the next frame), and those of them listed in the output directory's
 * .pvd (times and file names). */
long peri_restart_frames(const peri_sim *s, long *n_listed, const double **times, char *const **files);

/* A restarted run's start, shared by the mechanical and heat drivers: puts the checkpoint's
 * state into s, continues the .pvd series in frames, and returns the history.csv rows to
 * replay ([*rows][n_columns]; NULL with *rows = 0 when there are none or when they have
 * another number of columns, with a warning). Returns NULL with *rows = -1 on an output
 * failure. */
struct peri_frames;

void peri_restart_free(struct peri_restart *r);

/* What a run wrote into `directory` up to its checkpoint (src/io/checkpoint_output.c):
 * the first `rows` rows of history.csv into *history ([*history_rows][*history_columns]) and
 * its column names into *history_names
 * and the first `frames` frames listed in <basename>.pvd (times and file names). A missing
 * file gives a warning and nothing; one with fewer entries than the checkpoint records is
 * the output of another run: an error, PERI_ERR_INPUT (what was read is returned all the
 * same, for the caller to free). */
int peri_restart_read_output(const char *directory, const char *basename, long rows, long frames,
                             double **history, long *history_rows, int *history_columns, char ***history_names,
                             double **frame_times, char ***frame_files, long *frames_listed);

#endif
