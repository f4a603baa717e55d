/* When and where a run writes checkpoints, and how it takes up the output of the run it
 * restarts (src/run/, docs/restart.md). */
#ifndef PERI_CHECKPOINT_SCHEDULE_H
#define PERI_CHECKPOINT_SCHEDULE_H
#include <stdio.h>
#include "peri/checkpoint.h"
#include "peri/frames.h"

/* Path of the checkpoint of the current step: output.checkpoint_file with "{step}"
 * replaced by the step number, relative to the output directory unless absolute;
 * default <directory>/<basename>.h5. */
void peri_checkpoint_path(const peri_sim *s, char *out, size_t size);
/* Summary line of the checkpoint settings (nothing without output.checkpoint_every). */
void peri_checkpoint_print_summary(const peri_sim *s, FILE *out);
/* Writes the checkpoint when one is due after this step (every checkpoint_every steps and
 * at the last step; nothing without output.checkpoint_every). Collective on MPI ranks. */
int peri_checkpoint_after_step(const peri_sim *s, const peri_checkpoint_progress *done);
/* Whether a checkpoint is written after step `step` (output.checkpoint_every, and the last step). */
bool peri_checkpoint_due(const peri_sim *s, long step);
/* A restart's output: applies the checkpoint's state, lists its frames in `frames`, and returns
 * the history.csv rows written before it (rows: their number; -1 on a failure). */
const double *peri_restart_resume(peri_sim *s, struct peri_frames *frames, int n_columns, long *rows);

#endif
