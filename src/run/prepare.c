/* What a run does between building the simulation and its first step, shared by `peri run`
 * (app/peri.c) and the C API (src/api/api.c): the checkpoint to continue from, the check of
 * the number of MPI ranks, the summary, and the decomposition over the ranks. */
#include <stdio.h>
#include "peri/bodies.h"
#include "peri/checkpoint.h"
#include "peri/comm.h"
#include "peri/coupling.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/gpu.h"
#include "peri/history_log.h"
#include "peri/quasistatic.h"
#include "peri/run.h"

int peri_run_prepare(peri_sim *s, const char *restart) {
  int rc = PERI_OK;
  if (restart) rc = peri_restart_load(s, restart); /* checked before any output (docs/restart.md) */
  if (rc == PERI_OK && restart) rc = peri_restart_check_history(s); /* the same history.csv columns */
  if (rc == PERI_OK) rc = peri_solver_check_ranks(s, peri_comm_size()); /* MPI ranks */
  if (rc == PERI_OK) peri_gpu_settle(s); /* --device gpu on a deck the GPU does not take (docs/gpu.md) */
  if (rc == PERI_OK && !s->out.quiet) {
    peri_print_summary(s, stdout);
    peri_print_threads(s, stdout);
  }
  if (rc == PERI_OK && restart && !s->out.quiet) peri_restart_print(s, stdout);
  if (rc == PERI_OK) {
    fflush(stdout);
    /* a PD-FEM coupling's rows read the corners of their elements too (docs/coupling.md) */
    if (s->coupling && peri_comm_size() > 1) peri_coupling_set_reach(s);
    rc = peri_decompose(s); /* MPI ranks (docs/parallel.md); nothing in one process */
    if (rc == PERI_OK) rc = peri_coupling_localize(s);
    if (rc == PERI_OK) peri_bodies_localize(s); /* the bodies' labels of the rank's nodes */
    if (rc == PERI_OK && !s->out.quiet) peri_print_decomposition(s, stdout);
  }
  return rc;
}
