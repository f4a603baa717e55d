/* Output frames of a running simulation (VTU series) and the end-of-run picture. */
#ifndef PERI_FRAMES_H
#define PERI_FRAMES_H
#include <stddef.h>
#include "peri/sim.h"

typedef struct peri_frames peri_frames;
/* Names of the per-node fields a frame can hold (output.fields), NULL-terminated. */
extern const char *const peri_frame_fields[];
/* Creates the output directory and the .pvd; NULL (with a message) on failure. */
peri_frames *peri_frames_open(const peri_sim *s);
/* Frames that write no file: the buffers of the derived fields alone, for peri_frames_field
 * (the C API reads fields without writing frames). Free with peri_frames_close. */
peri_frames *peri_frames_buffers(const peri_sim *s);
int peri_frames_write(peri_frames *f, peri_sim *s);
/* The field `name` of peri_frame_fields at the current state, owned nodes only, as a frame
 * would write it; derived fields (damage, stress, strain, ...) are computed into the frame's
 * buffers and stay valid until the next call. 1, 0 when this simulation has no such field
 * (dilatation without LPS, temperature without heat), -1 after a message on failure. */
struct peri_field;
int peri_frames_field(peri_frames *f, peri_sim *s, const char *name, struct peri_field *out);
/* A restarted run (docs/restart.md) continues the series: the next frame is number `next`,
 * and the .pvd lists the n_listed frames of the run it restarts first. */
int peri_frames_resume(peri_frames *f, long next, long n_listed, const double *times, char *const *files);
/* Frames written so far (with those of a restarted run). */
long peri_frames_written(const peri_frames *f);
/* Writes <directory>/<field>.png of the picture field; its path into path_out. */
int peri_frames_picture(peri_frames *f, peri_sim *s, char *path_out, size_t n);
void peri_frames_close(peri_frames *f);
/* Components of a frame field in this simulation: 1, 3 or 9, and 0 for a field it does not
 * have (dilatation without LPS, temperature and heat_flux without heat). */
int peri_frame_field_components(const peri_sim *s, const char *name);
/* The SI unit of a frame field ("1" for a dimensionless one, "" for a number such as the
 * material index), docs/deck.md section 15. */
const char *peri_frame_field_unit(const char *name);
/* Each history.csv row of the run (output.format exodus: the file's global variables at the
 * frame of the same time). */
void peri_frames_history(peri_frames *f, const double *row);

#endif
