/* The GPU interface of a build without CUDA (gpu_kernels.h): no device, and every call says
 * so. CMake compiles this file instead of explicit_kernels.cu when it finds no CUDA compiler
 * or no GPU (PERI_CUDA, docs/gpu.md). */
#include <stdio.h>
#include "gpu_kernels.h"

static const char *absent = "this peri was built without CUDA (docs/gpu.md: cmake -DPERI_CUDA=ON on a machine with nvcc)";

bool peri_gpu_probe(char *name, size_t size) {
  snprintf(name, size, "%s", absent);
  return false;
}

peri_gpu *peri_gpu_create(const peri_gpu_problem *problem, char *err, size_t size) {
  (void)problem;
  snprintf(err, size, "%s", absent);
  return NULL;
}

/* (no peri_gpu can exist in this build: the calls below are never reached) */
int peri_gpu_upload(peri_gpu *g, const double *u, const double *v, const double *f, const double *b_ext,
                    const double *s0_node, const double *step_load) {
  (void)g, (void)u, (void)v, (void)f, (void)b_ext, (void)s0_node, (void)step_load;
  return -1;
}
int peri_gpu_set_loads(peri_gpu *g, const double *b_ext) {
  (void)g, (void)b_ext;
  return -1;
}
int peri_gpu_start(peri_gpu *g, const double centre[3], bool force, bool step_load) {
  (void)g, (void)centre, (void)force, (void)step_load;
  return -1;
}
int peri_gpu_step(peri_gpu *g, const double *held, const double centre[3], peri_gpu_step_sums *sums) {
  (void)g, (void)held, (void)centre, (void)sums;
  return -1;
}
int peri_gpu_download(peri_gpu *g, double *u, double *v, double *f, double *b, uint8_t *broken, double *s0_node,
                      double *step_load) {
  (void)g, (void)u, (void)v, (void)f, (void)b, (void)broken, (void)s0_node, (void)step_load;
  return -1;
}
const char *peri_gpu_error(const peri_gpu *g) {
  (void)g;
  return absent;
}
void peri_gpu_memory(const peri_gpu *g, double *bytes, double *per_bond) {
  (void)g;
  *bytes = *per_bond = 0.0;
}
double peri_gpu_step_seconds(peri_gpu *g) {
  (void)g;
  return 0.0;
}
void peri_gpu_free(peri_gpu *g) { (void)g; }
