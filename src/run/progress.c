/* Progress lines (include/peri/progress.h). A batch job's log gets a line every
 * out.progress_every seconds (10 by default) so that a long run, or a hard quasi-static
 * solve, can be told from a stuck one; a terminal gets the live line. The solvers call
 * s->out.progress at every step or iteration; this file reads the clock and prints when a
 * line is due, from values every rank already has (no collective: only rank 0 prints). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/ioctl.h>
#include <unistd.h>
#include "peri/clock.h"
#include "peri/comm.h"
#include "peri/progress.h"

/* The live line is rewritten at most this often (seconds), and only after the first second. */
#define LIVE_EVERY 0.5

void peri_progress_begin(peri_progress *p, peri_sim *s) {
  memset(p, 0, sizeof *p);
  const bool terminal = isatty(STDERR_FILENO);
  const bool on = !s->out.quiet && s->out.progress_every > 0.0 && peri_comm_rank() == 0;
  p->lines = on && (!terminal || s->out.progress_lines);
  p->live = on && !p->lines;
  p->every = s->out.progress_every;
  p->t_start = p->t_last = peri_seconds();
  p->first_step = s->state.step;
  p->first_time = s->state.time;
  p->load_steps_done = s->state.step;
  s->out.progress_state = p;
  s->out.progress = p->live || p->lines ? peri_progress_tick : NULL;
}

/* "12 s", "3 min 20 s", "2 h 05 min" */
static void duration(double seconds, char *buf, size_t size) {
  if (!isfinite(seconds) || seconds < 0) snprintf(buf, size, "?");
  else if (seconds < 10) snprintf(buf, size, "%.1f s", seconds);
  else if (seconds < 100) snprintf(buf, size, "%.0f s", seconds);
  else if (seconds < 6000) snprintf(buf, size, "%.0f min %02.0f s", floor(seconds / 60), fmod(seconds, 60));
  else snprintf(buf, size, "%.0f h %02.0f min", floor(seconds / 3600), floor(fmod(seconds, 3600) / 60));
}

void peri_progress_format(const peri_sim *s, const peri_progress *p, double now, char *buf, size_t size) {
  const double elapsed = now - p->t_start;
  char el[32], eta[32];
  duration(elapsed, el, sizeof el);
  if (peri_is_quasi_static(s)) {
    const peri_quasi_static *q = &s->solver.qs;
    const bool dynamic = q->phase == PERI_QS_PHASE_DYNAMIC;
    /* inside a load step the step under way is the next one; during a dynamic phase
     * state.step and state.time are the explicit integrator's, so report the load step */
    const long steps_done = dynamic ? p->load_steps_done : s->state.step;
    const long load_step = steps_done < q->load_steps ? steps_done + 1 : q->load_steps;
    const double T = s->solver.end_time;
    const double t = s->state.time;
    const long done = steps_done - p->first_step;
    /* ETA from the load steps done; none before the first one */
    const double rate = elapsed > 0 ? (double)done / elapsed : 0.0;
    duration(done > 0 && !dynamic ? (double)(q->load_steps - s->state.step) / rate : NAN, eta, sizeof eta);
    int k = 0;
    if (dynamic)
      k = snprintf(buf, size, "load step %ld/%ld, dynamic phase: %ld explicit steps in all, %.4g s of dynamics",
                   load_step, q->load_steps, q->dynamic_steps, q->dynamic_time);
    else
      k = snprintf(buf, size, "load step %ld/%ld  t = %.4g of %.4g", load_step, q->load_steps, t, T);
    if (k < 0 || (size_t)k >= size) return;
    snprintf(buf + k, size - (size_t)k,
             "  elapsed %s  %.3g load steps/s  eta %s  solve %ld: iteration %ld, residual %.3g (tolerance %.3g)"
             "  broken bonds %ld  cut-backs %ld  phase %s",
             el, rate, eta, q->solves, q->solve_iterations, q->residual, q->tolerance, q->broken_in_run, q->cutbacks,
             dynamic ? "dynamic" : "static");
  } else {
    const long done = s->state.step - p->first_step;
    const double rate = elapsed > 0 ? (double)done / elapsed : 0.0;
    duration(rate > 0 ? (double)(s->solver.steps - s->state.step) / rate : NAN, eta, sizeof eta);
    snprintf(buf, size, "step %ld/%ld (%.0f%%)  t = %.4g s  elapsed %s  %.3g steps/s  eta %s", s->state.step,
             s->solver.steps, s->solver.steps > 0 ? 100.0 * (double)s->state.step / (double)s->solver.steps : 100.0,
             s->state.time, el, rate, eta);
  }
}

void peri_progress_tick(peri_sim *s) {
  peri_progress *p = s->out.progress_state;
  if (!p || !(p->live || p->lines)) return;
  if (peri_is_quasi_static(s) && s->solver.qs.phase == PERI_QS_PHASE_STATIC) p->load_steps_done = s->state.step;
  const double now = peri_seconds();
  if (p->lines ? now - p->t_last < p->every : now - p->t_last < LIVE_EVERY || now - p->t_start < 1.0) return;
  char line[512];
  peri_progress_format(s, p, now, line, sizeof line);
  if (p->lines) {
    fprintf(stderr, "progress: %s\n", line);
  } else {
    struct winsize ws;
    const int width = ioctl(STDERR_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 10 ? ws.ws_col : 80;
    /* one screen line, or \r cannot rewrite it; \033[K erases what a longer line left */
    fprintf(stderr, "\r  %.*s\033[K", width - 3, line);
    p->shown = true;
  }
  fflush(stderr);
  p->t_last = now;
}

void peri_progress_end(peri_progress *p, peri_sim *s) {
  if (p->live && p->shown) fprintf(stderr, "\r\033[K");
  s->out.progress = NULL;
  s->out.progress_state = NULL;
}
