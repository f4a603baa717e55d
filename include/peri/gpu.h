/* Explicit dynamics on an NVIDIA GPU (docs/gpu.md): `peri run DECK --device gpu`. */
#ifndef PERI_GPU_H
#define PERI_GPU_H
#include <stdbool.h>
#include <stddef.h>
#include "peri/solver.h"

/* Where the explicit steps run (s->par.device). */
typedef enum { PERI_DEVICE_CPU = 0, PERI_DEVICE_GPU = 1 } peri_device;

/* Whether the deck's run can take the GPU path; else why not, into why (a deck the path does
 * not take runs on the CPU, with that reason in a warning). */
bool peri_gpu_runs(const peri_sim *s, char *why, size_t size);
/* A run asked for the GPU (s->par.device) that the GPU path does not take goes to the CPU,
 * with a warning that says why. */
void peri_gpu_settle(peri_sim *s);
/* The bytes the GPU path will take on the device for this sim, and their peak during the
 * set-up (the summary's device line). */
void peri_gpu_memory_estimate(const peri_sim *s, double *bytes, double *peak);
/* Whether this build has CUDA and a GPU is present: the GPU's name, or why not, into name. */
bool peri_gpu_device(char *name, size_t size);
/* peri_solve_explicit_hooked on the GPU, for a deck peri_gpu_runs takes. */
int peri_solve_explicit_gpu(peri_sim *s, peri_step_hook hook, peri_step_quiet quiet, void *ctx);

#endif
