/* Progress of a run (src/run/progress.c): on a terminal a live line rewritten in place;
 * otherwise (a batch job, a pipe, a file) or with --progress, a line every
 * s->out.progress_every seconds to stderr. Only rank 0 prints. */
#ifndef PERI_PROGRESS_H
#define PERI_PROGRESS_H
#include <stdbool.h>
#include "peri/sim.h"

typedef struct peri_progress {
  bool live;           /* the \r line on a terminal */
  bool lines;          /* whole lines every `every` seconds */
  double every;        /* seconds between lines */
  double t_start, t_last;
  long first_step;     /* step or load step the run started from */
  double first_time;   /* simulated (or pseudo-) time at the start */
  bool shown;          /* a live line is on the screen */
  long load_steps_done; /* quasi-static: load steps done (state.step is the integrator's in a dynamic phase) */
} peri_progress;

/* Chooses live line, lines or nothing from s->out (quiet, progress_every, progress_lines)
 * and whether stderr is a terminal, starts the clock and sets s->out.progress. */
void peri_progress_begin(peri_progress *p, peri_sim *s);
/* Prints a line when one is due (cheap otherwise: one clock read). */
void peri_progress_tick(peri_sim *s);
/* Clears the live line; unsets s->out.progress. */
void peri_progress_end(peri_progress *p, peri_sim *s);
/* The text of a progress line, for tests and the two forms: step or load step, time, elapsed,
 * rate, ETA, and for quasi-static runs the solve (iteration, residual), broken bonds and phase. */
void peri_progress_format(const peri_sim *s, const peri_progress *p, double now, char *buf, size_t size);

#endif
