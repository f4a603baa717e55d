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
/* Estimated bytes of all node and bond arrays. */
double peri_memory_estimate(const peri_sim *s);
/* Runs the solver with output into s->out.directory. Returns 0, or PERI_ERR_RUN with a
 * message (what was written so far is kept). */
int peri_run(peri_sim *s);

/* Summary lines for `peri check` / `run`. */
void peri_thermal_print_summary(const peri_sim *s, FILE *out);
/* Heat-only run driver (solver type heat): frames, history, picture. */
int peri_run_heat(peri_sim *s);

#endif
