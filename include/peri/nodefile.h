/* Node files: positions, volumes and materials of nodes from a text file (src/io/nodefile.c). */
#ifndef PERI_NODEFILE_H
#define PERI_NODEFILE_H
#include "peri/particles.h"

/* Reads a node file in the Peridigm/PeriLab text format: one node per line,
 * "x y [z] block volume" (dim + 2 columns), '#' comments and blank lines skipped.
 * block_to_material maps block ids (1-based) to material indices; blocks beyond
 * n_blocks are an error. Errors name path:line and exit status 2 (returns PERI_ERR_INPUT). */
int peri_nodefile_read(peri_particles *p, const char *path, int dim,
                       const int32_t *block_to_material, int n_blocks);

#endif
