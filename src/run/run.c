/* The run driver: solver + history + frames + picture + summary + progress line. */
#include <limits.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "peri/bodies.h"
#include "peri/contact.h"
#include "peri/short_range.h"
#include "peri/tools.h"
#include "peri/wear_depth.h"
#include "peri/checkpoint_schedule.h"
#include "peri/clock.h"
#include "peri/comm.h"
#include "peri/coupling.h"
#include "peri/checkpoint.h"
#include "peri/damage.h"
#include "peri/damage_index.h"
#include "peri/dataset.h"
#include "peri/decompose.h"
#include "peri/energies.h"
#include "peri/error.h"
#include "peri/gpu.h"
#include "peri/film_quantities.h"
#include "peri/film_series.h"
#include "peri/frames.h"
#include "peri/heat_quantities.h"
#include "peri/history.h"
#include "peri/history_log.h"
#include "peri/interface_strength.h"
#include "peri/j_integral.h"
#include "peri/model.h"
#include "peri/output.h"
#include "peri/phase_stress.h"
#include "peri/plastic_fields.h"
#include "peri/progress.h"
#include "peri/run.h"
#include "peri/solver.h"
#include "peri/quasistatic.h"
#include "peri/stress.h"
#include "peri/thermal.h"
#include "peri/tensor_plasticity.h"

typedef struct run_ctx {
  peri_frames *frames;
  peri_history_log log;         /* history.csv and the output.plot series */
  double t_start;
  peri_progress progress;       /* live line or lines (src/run/progress.c) */
  int failed;
  long first_step;              /* step the solver started from (a restart's checkpoint) */
  long stop_at;                 /* the step (or load step) after which the solver returns */
  peri_film_series film;        /* output.wrinkles: the film's rows, for the onsets at the end */
} run_ctx;

/* Mean displacement of a region's nodes (quasi-static history: the imposed displacement),
 * over the owned nodes of every rank in fixed-order sums. */
static void region_displacement(const peri_sim *s, int region, double out[3]) {
  const peri_region *r = &s->cond.regions[region];
  const int32_t n = s->disc.p.n_owned;
  double *terms = peri_calloc(4 * (size_t)(n > 0 ? n : 1), sizeof(double)); /* u, 1 */
  for (int32_t a = 0; a < r->count; ++a) {
    const int32_t i = r->nodes[a];
    if (i >= n) continue; /* a ghost: its owner counts it */
    for (int d = 0; d < 3; ++d) terms[4 * (size_t)i + d] = s->disc.p.u[3 * (size_t)i + d];
    terms[4 * (size_t)i + 3] = 1.0;
  }
  double sum[4];
  peri_sum_owned(s, terms, 4, sum);
  free(terms);
  for (int d = 0; d < 3; ++d) out[d] = sum[3] > 0.0 ? sum[d] / sum[3] : 0.0;
}

/* A quasi-static run that may switch to dynamics has the columns phase and dynamic_time. */
static bool qs_dynamic_columns(const peri_sim *s) { return peri_is_quasi_static(s) && s->solver.qs.dynamic.on; }

static int write_history(peri_sim *s, run_ctx *c) {
  int k = 0;
  double ke = peri_kinetic_energy(s);
  double se = peri_strain_energy(s);
  c->log.row[k++] = s->state.time;
  c->log.row[k++] = (double)s->state.step;
  c->log.row[k++] = ke;
  c->log.row[k++] = se;
  c->log.row[k++] = s->state.external_work;
  c->log.row[k++] = ke + se - s->state.external_work;
  const int64_t n_bonds = peri_global_bonds(s); /* all ranks (docs/parallel.md) */
  c->log.row[k++] = n_bonds ? (double)peri_global_broken(s) / (double)n_bonds : 0.0;
  c->log.row[k++] = peri_mean_damage(s); /* the mean of the damage field */
  if (peri_has_plasticity(s)) c->log.row[k++] = peri_mean_yield_index(s); /* docs/plasticity.md */
  double momentum[3];
  peri_linear_momentum(s, momentum);
  for (int d = 0; d < s->disc.geom.dim; ++d) c->log.row[k++] = momentum[d];
  if (s->cond.indenter.on)
    for (int d = 0; d < s->disc.geom.dim; ++d) c->log.row[k++] = s->cond.indenter.force[d];
  double *phi = NULL; /* the damage index, for the tools' wear depth */
  if (s->tools) {
    phi = peri_malloc(sizeof(double) * (size_t)(s->disc.p.n_owned > 0 ? s->disc.p.n_owned : 1));
    peri_damage_index(s, phi);
  }
  for (int j = 0; s->tools && j < s->tools->count; ++j) { /* rigid tools (docs/contact.md) */
    const peri_tool *tl = &s->tools->tool[j];
    for (int d = 0; d < s->disc.geom.dim; ++d) c->log.row[k++] = tl->force[d];
    for (int d = 0; d < s->disc.geom.dim; ++d) c->log.row[k++] = tl->at[d];
    c->log.row[k++] = tl->normal_force;
    c->log.row[k++] = tl->tangential_force;
    c->log.row[k++] = tl->normal_force > 0.0 ? tl->tangential_force / tl->normal_force : 0.0; /* CoF = F_t / P */
    c->log.row[k++] = tl->sliding;
    c->log.row[k++] = tl->contact_area;
    c->log.row[k++] = peri_tool_wear_depth(s, tl, phi);
    double speed = 0.0, depth = 0.0; /* along `direction`; the depth since the first contact */
    for (int d = 0; d < 3; ++d) {
      speed += tl->velocity[d] * tl->geom.direction[d];
      if (tl->touched) depth += (tl->at[d] - tl->contact_at[d]) * tl->geom.direction[d];
    }
    c->log.row[k++] = speed;
    c->log.row[k++] = depth;
  }
  free(phi);
  if (s->contact && s->contact->short_range) c->log.row[k++] = peri_contact_min_ratio(s); /* every rank's pairs */
  for (int r = 1; r < s->cond.n_regions; ++r) {
    double reaction[3];
    peri_region_reaction(s, r, reaction);
    for (int d = 0; d < s->disc.geom.dim; ++d) c->log.row[k++] = reaction[d];
  }
  if (s->bodies) { /* per body: mass, momentum, kinetic energy, mean velocity, damaged and detached mass */
    peri_body_sums *sums = peri_malloc(sizeof *sums * (size_t)s->bodies->count);
    peri_body_sums_now(s, sums);
    for (int b = 0; b < s->bodies->count; ++b) {
      const peri_body_sums *o = &sums[b];
      c->log.row[k++] = o->mass;
      for (int d = 0; d < s->disc.geom.dim; ++d) c->log.row[k++] = o->momentum[d];
      c->log.row[k++] = o->kinetic_energy;
      for (int d = 0; d < s->disc.geom.dim; ++d) c->log.row[k++] = o->mass > 0.0 ? o->momentum[d] / o->mass : 0.0;
      c->log.row[k++] = o->damaged_mass;
      c->log.row[k++] = o->detached_mass;
      if (s->bodies->penetration[b].on) c->log.row[k++] = o->penetration;
    }
    free(sums);
  }
  if (peri_is_quasi_static(s)) /* quasi-static: the imposed displacements */
    for (int r = 1; r < s->cond.n_regions; ++r) {
      double disp[3];
      region_displacement(s, r, disp);
      for (int d = 0; d < s->disc.geom.dim; ++d) c->log.row[k++] = disp[d];
    }
  if (qs_dynamic_columns(s)) { /* static (0) or dynamic (1) phase, time in dynamics (docs/solvers.md) */
    c->log.row[k++] = (double)s->solver.qs.phase;
    c->log.row[k++] = s->solver.qs.dynamic_time;
  }
  if (s->out.phase_stress) { /* per material: largest von Mises stress, where, mean stress (docs/microstructures.md) */
    peri_phase_stress *phases = peri_malloc(sizeof *phases * (size_t)s->mat.n_materials);
    if (peri_phase_stresses_now(s, phases) != PERI_OK) c->failed = 1;
    for (int m = 0; m < s->mat.n_materials; ++m) {
      const bool any = phases[m].max_von_mises > -INFINITY; /* a material without body nodes: zeros */
      c->log.row[k++] = any ? phases[m].max_von_mises : 0.0;
      for (int d = 0; d < s->disc.geom.dim; ++d) c->log.row[k++] = any ? phases[m].where[d] : 0.0;
      c->log.row[k++] = phases[m].mean_stress;
    }
    free(phases);
  }
  if (s->out.region_energy) /* per region, from the densities peri_strain_energy left (docs/thin_films.md) */
    for (int r = 1; r < s->cond.n_regions; ++r) c->log.row[k++] = peri_region_strain_energy(s, r);
  if (s->out.interface_history) { /* broken interface bonds and sigma_int (docs/thin_films.md) */
    long broken = 0;
    double stress = 0.0;
    peri_interface_history(s, &broken, &stress);
    c->log.row[k++] = (double)broken;
    c->log.row[k++] = stress;
    c->log.row[k++] = peri_interface_max_traction(s); /* the normal traction of Mei's Eq. 4.6 */
  }
  if (s->out.wrinkle_region > 0) { /* amplitude and wavelength of the film's deflection */
    peri_wrinkle_profile(s, s->out.wrinkle_region, &c->log.row[k], &c->log.row[k + 1]);
    peri_film_series_add(&c->film, s, c->log.row[k], c->log.row[k + 1]);
    k += 2;
  }
  peri_thermal_history_values(s, c->log.row + k); /* total heat, temperature range (docs/heat.md) */
  k += peri_thermal_history_count(s);
  if (s->out.j_integral) { /* J over each contour, crack extension (docs/plasticity.md) */
    if (peri_j_integral_values(s, s->out.j_integral, c->log.row + k, c->log.row + k + s->out.j_integral->n_contours) !=
        PERI_OK)
      c->failed = 1;
    k += s->out.j_integral->n_contours + 1;
  }
  if (s->coupling) { /* sum of K u and e_r of the PD-FEM coupling (docs/coupling.md) */
    double net[3], ratio[4];
    peri_coupling_balance(s, net, ratio);
    for (int d = 0; d < s->disc.geom.dim; ++d) c->log.row[k++] = net[d];
    for (int d = 0; d < s->disc.geom.dim; ++d) c->log.row[k++] = ratio[d];
    c->log.row[k++] = ratio[3];
    c->log.row[k++] = (double)s->coupling->n_pd;
    if (s->coupling->n_balance_regions > 0) { /* e_r of eqs. 2.114, 2.116 over the chosen reactions */
      double by_region[3];
      peri_coupling_region_balance(s, by_region);
      for (int d = 0; d < s->disc.geom.dim; ++d) c->log.row[k++] = by_region[d];
    }
    for (int t = 0; t < s->coupling->n_tractions; ++t) { /* eqs. A.15, A.34 and 2.107 at each point */
      const peri_interface_traction *tr = &s->coupling->traction[t];
      double tau[3], local[3];
      peri_coupling_nonlocal_traction(s, tr->at, tr->axis, tr->sign, tau);
      peri_coupling_local_traction(s, tr, local);
      for (int d = 0; d < s->disc.geom.dim; ++d) c->log.row[k++] = tau[d];
      for (int d = 0; d < s->disc.geom.dim; ++d) c->log.row[k++] = local[d];
    }
  }
  return peri_history_log_record(&c->log);
}

/* Whether the step hook writes a frame and a history row after step `step`. */
static void step_output(const peri_sim *s, long step, bool *frame, bool *history) {
  const bool last = step == s->solver.steps;
  *frame = (s->out.every > 0 && step % s->out.every == 0) || last;
  /* an Exodus frame holds the history row of its step as global variables */
  *history = step % s->out.history_every == 0 || last || (*frame && s->out.exodus);
}

/* Whether the hook after `step` of an explicit run only ticks the progress line: nothing
 * written, nothing read of the state, no stop (peri_step_quiet). */
static bool step_hook_quiet(const peri_sim *s, long step, void *ctx) {
  const run_ctx *c = ctx;
  bool frame, history;
  step_output(s, step, &frame, &history);
  return !frame && !history && step < c->stop_at && !peri_dataset_due(s, step) && !peri_checkpoint_due(s, step);
}

static int step_hook(peri_sim *s, void *ctx) {
  run_ctx *c = ctx;
  if (peri_is_quasi_static(s) && s->solver.qs.phase == PERI_QS_PHASE_DYNAMIC) { /* inside a load step: a row only */
    if (write_history(s, c) != PERI_OK) c->failed = 1;
    return peri_comm_max_int(c->failed);
  }
  bool frame, history;
  step_output(s, s->state.step, &frame, &history);
  if (history && write_history(s, c) != PERI_OK) c->failed = 1;
  /* only rank 0 writes history.csv: the ranks agree before the collective frame write */
  if (history) c->failed = peri_comm_max_int(c->failed);
  if (!c->failed && frame && peri_frames_write(c->frames, s) != PERI_OK) c->failed = 1;
  if (!c->failed && peri_dataset_after_step(s) != PERI_OK) c->failed = 1; /* docs/datasets.md (collective) */
  const peri_checkpoint_progress done = {peri_frames_written(c->frames), c->log.rows};
  if (!c->failed && peri_checkpoint_after_step(s, &done) != PERI_OK) { /* docs/restart.md */
    c->failed = 1;
    return 1;
  }
  if ((history || frame) && peri_comm_max_int(c->failed)) { /* every rank stops together */
    c->failed = 1;
    return 1;
  }
  if (s->out.progress) s->out.progress(s);
  return s->state.step >= c->stop_at; /* peri_run_advance: stop after this step */
}

/* A run in progress: the context of the step hook and the status so far (include/peri/run.h). */
struct peri_run_session {
  peri_sim *s;
  run_ctx c;
  int rc;
  bool finished;
};

peri_run_session *peri_run_open(peri_sim *s, bool keep_history) {
  run_ctx c = {0};
  c.frames = peri_frames_open(s);
  if (!c.frames) return NULL;
  if (peri_comm_max_int(peri_history_log_open(&c.log, s))) { /* collective: rank 0 opens the file */
    peri_frames_close(c.frames);
    peri_history_log_close(&c.log);
    return NULL;
  }
  c.log.frames = c.frames; /* the Exodus file's global variables */
  c.log.keep = keep_history;
  peri_apply_initial_conditions(s);
  peri_apply_loads(s, s->state.time);
  peri_exchange_state(s); /* ghost displacements (MPI ranks, docs/parallel.md) */
  int rc = PERI_OK;
  const bool restarted = s->state.restart != NULL;
  if (restarted) { /* continue from a checkpoint (docs/restart.md) */
    rc = peri_history_log_resume(&c.log, s, c.frames);
    if (rc == PERI_OK) rc = peri_dataset_begin(s); /* (refuses: docs/datasets.md) */
  } else {
    if (s->coupling) peri_coupling_force(s); /* PD-FEM coupling (docs/coupling.md) */
    else s->mat.model->force(s);
    rc = peri_frames_write(c.frames, s);
    if (rc == PERI_OK) rc = write_history(s, &c);
    if (rc == PERI_OK) rc = peri_dataset_begin(s); /* the graph dataset's file and frame 0 (docs/datasets.md) */
    /* (writing reads the forces and leaves them: the explicit solver starts from them) */
    s->state.forces_current = !peri_is_quasi_static(s);
  }
  rc = peri_comm_max_int(rc);
  /* a restart: the loads again, at the state just read (collective: the tools sum over ranks);
   * a quasi-static run's external work starts from them */
  if (rc == PERI_OK && restarted) peri_apply_loads(s, s->state.time);
  c.t_start = peri_seconds();
  c.first_step = s->state.step;
  c.stop_at = LONG_MAX;
  peri_run_session *r = peri_calloc(1, sizeof *r);
  *r = (peri_run_session){.s = s, .c = c, .rc = rc};
  peri_progress_begin(&r->c.progress, s); /* the solvers tick it through s->out.progress */
  return r;
}

int peri_run_advance(peri_run_session *r, long until) {
  peri_sim *s = r->s;
  if (r->rc != PERI_OK || r->finished || s->state.step >= until) return r->rc;
  r->c.stop_at = until;
  int rc = peri_is_quasi_static(s)              ? peri_solve_quasi_static(s, step_hook, &r->c)
           : s->par.device == PERI_DEVICE_GPU ? peri_solve_explicit_gpu(s, step_hook, step_hook_quiet, &r->c)
                                              : peri_solve_explicit_hooked(s, step_hook, step_hook_quiet, &r->c);
  if (r->c.failed) rc = PERI_ERR_RUN;
  return r->rc = rc;
}

int peri_run_status(const peri_run_session *r) { return r->rc; }

const double *peri_run_history(const peri_run_session *r, long *rows, int *columns) {
  *rows = r->c.log.rows;
  *columns = r->c.log.n_columns;
  return r->c.log.kept;
}

int peri_run_finish(peri_run_session *r) {
  if (r->finished) return r->rc;
  peri_sim *s = r->s;
  const run_ctx c = r->c;
  int rc = r->rc;
  r->finished = true;
  double wall = peri_seconds() - c.t_start;
  peri_progress_end(&r->c.progress, s);
  char picture[4300] = "", plot[4400] = "";
  /* drawn even when the run failed: the curve so far */
  if (peri_plot_series_write(&c.log.plot, s, plot, sizeof plot) != PERI_OK) rc = PERI_ERR_RUN;
  if (rc == PERI_OK && s->out.picture && s->disc.geom.dim >= 2) {
    if (peri_frames_picture(c.frames, s, picture, sizeof picture) != PERI_OK) rc = PERI_ERR_RUN, picture[0] = 0;
  }
  char onsets[4400] = "";
  if (s->out.wrinkle_region > 0 && peri_film_series_write(&c.film, s, onsets, sizeof onsets) != PERI_OK) rc = PERI_ERR_RUN;
  rc = peri_comm_max_int(rc); /* one status for all ranks */
  if (!s->out.quiet) {
    double updates = (double)peri_global_bonds(s) * (s->state.step - c.first_step);
    const long broken = peri_global_broken(s);
    if (peri_is_quasi_static(s))
      printf("  finished     %ld load steps in %.3f s: %ld solves, %ld iterations, %ld force evaluations, "
             "%ld cut-backs, residual %.3g (%d threads)\n", s->state.step, wall, s->solver.qs.solves, s->solver.qs.iterations,
             s->solver.qs.force_evaluations, s->solver.qs.cutbacks, s->solver.qs.residual, omp_get_max_threads());
    if (s->solver.kind == PERI_SOLVER_IMPLICIT) /* the iterations above are Newton's */
      printf("  linear       %ld Krylov iterations in all, %.1f per Newton iteration\n", s->solver.qs.linear_iterations,
             s->solver.qs.iterations > 0 ? (double)s->solver.qs.linear_iterations / (double)s->solver.qs.iterations : 0.0);
    if (qs_dynamic_columns(s))
      printf("  dynamic      %ld phase%s, %ld explicit steps, %.4g s of dynamics\n", s->solver.qs.dynamic_phases,
             s->solver.qs.dynamic_phases == 1 ? "" : "s", s->solver.qs.dynamic_steps, s->solver.qs.dynamic_time);
    if (!peri_is_quasi_static(s))
      printf("  finished     %ld steps in %.3f s: %.1f steps/s, %.3g bond updates/s (%d threads)\n", s->state.step,
             wall, wall > 0 ? (s->state.step - c.first_step) / wall : 0.0, wall > 0 ? updates / wall : 0.0,
             omp_get_max_threads());
    if (s->par.device == PERI_DEVICE_GPU && s->par.gpu_steps > 0) /* docs/gpu.md */
      printf("  gpu          %ld steps in %.3f s on the device: %.4g directed-bond updates/s; %.3g GB on the device "
             "(%.1f bytes per bond)\n", s->par.gpu_steps, s->par.gpu_seconds,
             s->par.gpu_seconds > 0 ? (double)peri_global_bonds(s) * (double)s->par.gpu_steps / s->par.gpu_seconds : 0.0,
             s->par.gpu_bytes / 1e9, s->par.gpu_bytes_per_bond);
    printf("  broken bonds %ld of %lld\n", broken, (long long)peri_global_bonds(s));
    if (s->contact && s->contact->short_range) { /* the pair list's builds (docs/contact.md), the same on every rank */
      const long pairs = peri_contact_pairs(s), pruned = peri_contact_pruned_pairs(s), ghosts = peri_contact_ghost_count(s);
      printf("  contact      short-range forces, pair list built %ld times (skin %g m), %ld pairs in the last; pruned %ld "
             "times (skin %g m), %ld pairs in the last", s->contact->list.builds, s->contact->skin, pairs,
             s->contact->list.prunes, s->contact->prune_skin, pruned);
      if (peri_comm_size() > 1) printf(", %ld contact ghosts on the ranks", ghosts);
      printf("\n");
    }
    double tpl_bytes = 0.0, on_lattice = 0.0;
    const double in_blocks = peri_node_blocks_share(s, &tpl_bytes, &on_lattice);
    if (in_blocks >= 0.0) /* of this rank's bonds (rank 0's on MPI ranks) */
      printf("  bond loops   %.1f%% of the bonds eight nodes at a time (node blocks, %.2f bytes per bond; %.1f%% of "
             "them with the lattice's offsets)\n", 100.0 * in_blocks, tpl_bytes, 100.0 * on_lattice);
    peri_print_stress_summary(s, stdout); /* per-material maxima over every rank */
    if (s->out.wrinkle_region > 0) peri_film_series_print(&c.film, s);
    printf("  output       %s/%s.%s (%s), %s/history.csv%s%s%s%s%s%s\n", s->out.directory, s->out.basename,
           s->out.vtu ? "pvd" : "e", s->out.vtu && s->out.exodus ? "VTU series and Exodus II .e" : s->out.vtu ? "VTU series" : "Exodus II",
           s->out.directory, picture[0] ? ", " : "", picture, plot[0] ? ", " : "", plot, onsets[0] ? ", " : "", onsets);
  }
  return r->rc = rc;
}

int peri_run_close(peri_run_session *r) {
  if (!r) return PERI_OK;
  const int rc = peri_run_finish(r);
  peri_film_series_free(&r->c.film);
  peri_frames_close(r->c.frames);
  peri_history_log_close(&r->c.log);
  free(r);
  return rc;
}

int peri_run(peri_sim *s) {
  if (s->solver.kind == PERI_SOLVER_HEAT) return peri_run_heat(s); /* conduction only (docs/heat.md) */
  peri_run_session *r = peri_run_open(s, false);
  if (!r) return PERI_ERR_RUN;
  peri_run_advance(r, LONG_MAX);
  return peri_run_close(r);
}
