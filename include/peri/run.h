/* Running a simulation with output: frames, history, picture, summary, progress. */
#ifndef PERI_RUN_H
#define PERI_RUN_H
#include <stdio.h>
#include "peri/sim.h"

/* Prints the first lines of a summary: version and deck, model (with dimension and plane),
 * nodes, bonds (with the count of broken ones, called `broken`), horizon. */
void peri_print_discretization(const peri_sim *s, FILE *out, const char *model, const char *broken);
/* Prints the summary of a built simulation (nodes, bonds, memory, time step, ...). */
void peri_print_summary(const peri_sim *s, FILE *out);
/* The summary's threads line: OpenMP threads per process and the wait policy in force
 * (s->par.omp_wait); nothing when the program did not say which policy. */
void peri_print_threads(const peri_sim *s, FILE *out);
/* Estimated bytes of all node and bond arrays. */
double peri_memory_estimate(const peri_sim *s);
/* Runs the solver with output into s->out.directory. Returns 0, or PERI_ERR_RUN with a
 * message (what was written so far is kept). */
int peri_run(peri_sim *s);

/* What `peri run` does before the first step (src/run/prepare.c): loads the checkpoint
 * `restart` (NULL: none) and checks it against the deck, checks the number of MPI ranks,
 * prints the summary (unless s->out.quiet) and decomposes the nodes over the ranks. PERI_OK,
 * or PERI_ERR_INPUT / PERI_ERR_RUN after a message, before any output. */
int peri_run_prepare(peri_sim *s, const char *restart);

/* peri_run in parts, for a program that stops between steps (the C API, include/peri/api.h):
 * peri_run_open writes the first frame and history row (or continues a checkpoint's),
 * peri_run_advance runs up to a step, peri_run_finish draws the picture and plot and prints
 * the end of the summary (once), peri_run_close finishes and frees. peri_run is open,
 * advance to the end, close. Mechanical runs only (not solver type heat). */
typedef struct peri_run_session peri_run_session;
/* NULL after a message when the output cannot be opened. `keep_history`: the history rows
 * are kept in memory too (peri_run_history). The run's status so far is what
 * peri_run_advance returns. */
peri_run_session *peri_run_open(peri_sim *s, bool keep_history);
/* Runs until the step (explicit) or load step (quasi-static) `until` is done, or to the end
 * of the run. Returns PERI_OK or PERI_ERR_RUN after a message; after an error, once
 * finished, or when step `until` is done already, it runs nothing and returns the status. */
int peri_run_advance(peri_run_session *r, long until);
/* The run's status so far: PERI_OK, or the error of the opening or of a step. */
int peri_run_status(const peri_run_session *r);
/* The history rows recorded so far, row by row (NULL unless opened with keep_history). */
const double *peri_run_history(const peri_run_session *r, long *rows, int *columns);
int peri_run_finish(peri_run_session *r);
int peri_run_close(peri_run_session *r);

/* Summary lines for `peri check` / `run`. */
void peri_thermal_print_summary(const peri_sim *s, FILE *out);
/* Heat-only run driver (solver type heat): frames, history, picture. */
int peri_run_heat(peri_sim *s);

#endif
