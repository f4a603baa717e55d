/* The Exodus II series of the frames (frames_exodus.c), used by frames.c. */
#ifndef PERI_FRAMES_PARTS_H
#define PERI_FRAMES_PARTS_H
#include "peri/output.h"
#include "peri/sim.h"

typedef struct peri_frames_exodus peri_frames_exodus;
/* Collective: gathers the reference configuration to rank 0, which creates the file at path
 * with the node variables of `fields` (the frame fields of this run, in order) and the
 * history columns as global variables. NULL on every rank when any failed (with a message). */
peri_frames_exodus *peri_frames_exodus_open(const peri_sim *s, const char *path, const char *create_path);
/* Collective: one time step of the frame fields (each rank's owned nodes, gathered to rank 0). */
int peri_frames_exodus_write(peri_frames_exodus *x, const peri_sim *s, const peri_field *fields, int n_fields);
/* A history row: the global variables of the step of the same time. */
void peri_frames_exodus_history(peri_frames_exodus *x, const double *row);
/* A restarted run: the first `next` steps of the file at path are copied into the new file,
 * which then replaces it. */
int peri_frames_exodus_resume(peri_frames_exodus *x, long next);
void peri_frames_exodus_close(peri_frames_exodus *x);

#endif
