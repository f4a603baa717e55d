/* Output frames of a running simulation (VTU series) and the end-of-run picture. */
#ifndef PERI_FRAMES_H
#define PERI_FRAMES_H
#include <stddef.h>
#include "peri/sim.h"
#include "peri/solver.h"

typedef struct peri_frames peri_frames;
/* Creates the output directory and the .pvd; NULL (with a message) on failure. */
peri_frames *peri_frames_open(const peri_sim *s);
int peri_frames_write(peri_frames *f, peri_sim *s);
/* Writes <directory>/<field>.png of the picture field; its path into path_out. */
int peri_frames_picture(peri_frames *f, peri_sim *s, char *path_out, size_t n);
void peri_frames_close(peri_frames *f);

#endif
