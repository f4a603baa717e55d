/* Conduction-only runs (solver type heat): the summary, the time loop with frames,
 * history.csv and the end-of-run picture. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "peri/checkpoint.h"
#include "peri/checkpoint_schedule.h"
#include "peri/clock.h"
#include "peri/comm.h"
#include "peri/damage.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/frames.h"
#include "peri/heat.h"
#include "peri/heat_quantities.h"
#include "peri/history.h"
#include "peri/history_log.h"
#include "peri/progress.h"
#include "peri/output.h"
#include "peri/run.h"
#include "peri/thermal.h"

typedef struct heat_ctx {
  peri_frames *frames;
  peri_history_log log; /* history.csv and the output.plot series */
} heat_ctx;

static int write_history(peri_sim *s, heat_ctx *c) {
  const peri_thermal *th = s->thermal;
  int k = 0;
  double lo = INFINITY, hi = -INFINITY;
  for (int32_t i = 0; i < th->n; ++i) {
    if (th->T[i] < lo) lo = th->T[i];
    if (th->T[i] > hi) hi = th->T[i];
  }
  c->log.row[k++] = s->state.time;
  c->log.row[k++] = (double)s->state.step;
  c->log.row[k++] = peri_thermal_total_heat(s);
  c->log.row[k++] = peri_comm_min(lo); /* all ranks */
  c->log.row[k++] = peri_comm_max(hi);
  const int64_t n_bonds = peri_global_bonds(s);
  c->log.row[k++] = n_bonds ? (double)peri_global_broken(s) / (double)n_bonds : 0.0;
  double *terms = peri_calloc(2 * (size_t)(th->n > 0 ? th->n : 1), sizeof(double));
  for (int r = 1; r < s->cond.n_regions; ++r) {
    const peri_region *reg = &s->cond.regions[r];
    for (int32_t i = 0; i < th->n; ++i) terms[2 * i] = terms[2 * i + 1] = 0.0;
    for (int32_t a = 0; a < reg->count; ++a) {
      terms[2 * reg->nodes[a]] = th->T[reg->nodes[a]] * th->area[reg->nodes[a]];
      terms[2 * reg->nodes[a] + 1] = th->area[reg->nodes[a]];
    }
    double sums[2]; /* fixed-order blocks: independent of threads and ranks */
    peri_sum_owned(s, terms, 2, sums);
    const double sum = sums[0], vol = sums[1];
    c->log.row[k++] = vol > 0.0 ? sum / vol : 0.0;
    c->log.row[k++] = peri_thermal_region_inflow(s, r);
  }
  free(terms);
  return peri_history_log_record(&c->log);
}

int peri_run_heat(peri_sim *s) {
  peri_thermal *th = s->thermal;
  heat_ctx c = {0};
  c.frames = peri_frames_open(s);
  if (!c.frames) return PERI_ERR_RUN;
  if (peri_comm_max_int(peri_history_log_open(&c.log, s))) { /* collective: rank 0 opens the file */
    peri_frames_close(c.frames);
    peri_history_log_close(&c.log);
    return PERI_ERR_RUN;
  }
  c.log.frames = c.frames; /* the Exodus file's global variables */
  int rc = PERI_OK;
  if (s->state.restart) { /* continue from a checkpoint (docs/restart.md) */
    rc = peri_history_log_resume(&c.log, s, c.frames);
  } else {
    s->state.time = th->time;
    rc = peri_frames_write(c.frames, s);
    if (rc == PERI_OK) rc = write_history(s, &c);
  }
  rc = peri_comm_max_int(rc); /* every rank starts, or none */
  const double t_start = peri_seconds();
  const long first_step = s->state.step; /* a restart's checkpoint, else 0 */
  peri_progress progress;
  peri_progress_begin(&progress, s);
  for (long step = s->state.step; step < s->solver.steps && rc == PERI_OK; ++step) {
    rc = peri_thermal_step(s, s->solver.dt);
    s->state.time = th->time;
    s->state.step = step + 1;
    if (rc != PERI_OK) break;
    const bool last = s->state.step == s->solver.steps;
    const bool frame = (s->out.every > 0 && s->state.step % s->out.every == 0) || last;
    if ((s->state.step % s->out.history_every == 0 || last || (frame && s->out.exodus)) &&
        peri_comm_max_int(write_history(s, &c) != PERI_OK))
      rc = PERI_ERR_RUN; /* every rank stops together */
    if (rc == PERI_OK && frame) rc = peri_frames_write(c.frames, s);
    const peri_checkpoint_progress done = {peri_frames_written(c.frames), c.log.rows};
    if (rc == PERI_OK) rc = peri_checkpoint_after_step(s, &done); /* docs/restart.md */
    if (s->out.progress) s->out.progress(s);
  }
  const double wall = peri_seconds() - t_start;
  peri_progress_end(&progress, s);
  char picture[4300] = "", plot[4400] = "";
  /* drawn even when the run failed: the curve so far */
  if (peri_plot_series_write(&c.log.plot, s, plot, sizeof plot) != PERI_OK) rc = PERI_ERR_RUN;
  if (rc == PERI_OK && s->out.picture && s->disc.geom.dim >= 2 &&
      peri_frames_picture(c.frames, s, picture, sizeof picture) != PERI_OK) {
    rc = PERI_ERR_RUN;
    picture[0] = 0;
  }
  if (!s->out.quiet) {
    printf("  finished     %ld steps in %.3f s: %.1f steps/s (%d threads)\n", s->state.step, wall,
           wall > 0 ? (s->state.step - first_step) / wall : 0.0, omp_get_max_threads());
    printf("  total heat   %.10g J\n", peri_thermal_total_heat(s));
    printf("  output       %s/%s.%s (%s), %s/history.csv%s%s%s%s\n", s->out.directory, s->out.basename,
           s->out.vtu ? "pvd" : "e", s->out.vtu && s->out.exodus ? "VTU series and Exodus II .e" : s->out.vtu ? "VTU series" : "Exodus II",
           s->out.directory, picture[0] ? ", " : "", picture, plot[0] ? ", " : "", plot);
  }
  peri_frames_close(c.frames);
  peri_history_log_close(&c.log);
  return rc;
}
