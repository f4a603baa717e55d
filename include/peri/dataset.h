/* Graph datasets (docs/datasets.md): a run as a bidirected graph, nodes the particles and
 * edges the directed bonds, written to an HDF5 file every output.dataset.every steps for
 * learned surrogates (docs/surrogates.md). */
#ifndef PERI_DATASET_H
#define PERI_DATASET_H
#include <stdbool.h>
#include <stddef.h>
#include "peri/sim.h"

/* A tag of the run (output.dataset.tags): a number or a text. */
typedef struct peri_dataset_tag {
  char *name;
  char *text;   /* NULL for a number */
  double value;
} peri_dataset_tag;

/* output.dataset: what the deck asks for, and how much of it was written. */
typedef struct peri_dataset_output {
  long every;             /* steps (load steps) between graph frames; the first and last always */
  char *file;             /* the file, relative to the output directory unless absolute */
  int n_tags;
  peri_dataset_tag *tags; /* load magnitude, geometry tags, ...: attributes of /globals/tags */
  long frames;            /* frames written so far */
} peri_dataset_output;

void peri_dataset_output_free(peri_dataset_output *d);
/* The file's path (the output directory joined with output.dataset.file). */
void peri_dataset_path(const peri_sim *s, char *out, size_t size);
/* The graph at the start of a run: creates the file with the run's constants, the nodes'
 * reference data and the edges, then frame 0. Collective on MPI ranks (rank 0 writes what
 * every rank's nodes and families hold, in the global order: the file is the one a single
 * process writes). PERI_OK, or PERI_ERR_RUN after a message; every rank returns the same. */
int peri_dataset_begin(peri_sim *s);
/* After a step (load step): a frame when one is due (every `every` steps and at the last).
 * Collective; PERI_OK or PERI_ERR_RUN as peri_dataset_begin. */
int peri_dataset_after_step(peri_sim *s);
/* Whether the graph dataset records a frame after step `step`. */
bool peri_dataset_due(const peri_sim *s, long step);

#endif
