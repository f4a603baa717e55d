/* Explicit dynamics on a GPU (docs/gpu.md): the velocity-Verlet step of explicit.c with the
 * state on the device (src/gpu/gpu_kernels.h). The host evaluates what the deck's expressions
 * give (the prescribed motion of the held nodes, loads that change in time, the indenter's
 * centre) and hands the device those numbers; it copies the state back only before a step
 * whose output reads it (frames, history rows, checkpoints, datasets) and at the end. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/comm.h"
#include "peri/contribution.h"
#include "peri/model.h"
#include "peri/error.h"
#include "peri/gpu.h"
#include "peri/solver.h"
#include "peri/tensor_plasticity.h"
#include "gpu/gpu_kernels.h"

static bool is_model(const peri_sim *s, const char *name) { return !strcmp(s->mat.model->name, name); }

bool peri_gpu_runs(const peri_sim *s, char *why, size_t size) {
  const char *reason = NULL;
  if (s->solver.kind != PERI_SOLVER_EXPLICIT) reason = "only explicit dynamics runs on the GPU";
  else if (!is_model(s, "pmb") && !is_model(s, "lps")) reason = "only the pmb and lps models run on the GPU";
  else if (s->par.dd || peri_comm_size() > 1) reason = "the GPU path runs in one process (no MPI ranks)";
  else if (s->disc.p.n != s->disc.p.n_owned) reason = "nodes beyond the owned ones (ghosts) run on the CPU";
  else if (s->thermal || s->state.thermal_strain) reason = "heat conduction and thermal strain run on the CPU";
  else if (s->coupling) reason = "a PD-FEM coupling runs on the CPU";
  else if (s->contact) reason = "short-range contact forces run on the CPU";
  else if (s->tools) reason = "rigid tools run on the CPU";
  else if (s->bodies) reason = "several bodies run on the CPU";
  else if (peri_has_plasticity(s)) reason = "sublayer plasticity runs on the CPU";
  else if (s->disc.bonds.surface_G) reason = "surface corrections run on the CPU";
  else if (s->disc.horizon_field || s->disc.family.node_horizon) reason = "a horizon that varies runs on the CPU";
  else if (s->mat.interface_moduli || s->mat.pair_strength) reason = "interface moduli and strengths run on the CPU";
  else if (s->mat.n_materials > PERI_GPU_MAX_MATERIALS) reason = "more than 16 materials run on the CPU";
  else
    for (int m = 0; m < s->mat.n_materials && !reason; ++m)
      if (s->mat.materials[m].sublayers) reason = "sublayer plasticity runs on the CPU";
  if (reason) snprintf(why, size, "%s", reason);
  return reason == NULL;
}

bool peri_gpu_device(char *name, size_t size) { return peri_gpu_probe(name, size); }

void peri_gpu_memory_estimate(const peri_sim *s, double *bytes, double *peak) {
  const int32_t n = s->disc.p.n_owned;
  peri_gpu_bytes(n, s->disc.bonds.offset[n], peri_bonds_longest_family(&s->disc.bonds, n), is_model(s, "lps"), bytes,
                 peak);
}

void peri_gpu_settle(peri_sim *s) {
  char why[200];
  if (s->par.device != PERI_DEVICE_GPU || peri_gpu_runs(s, why, sizeof why)) return;
  /* (the GPU itself was checked with the command line) */
  peri_warning("--device gpu: %s; this run takes the CPU", why);
  s->par.device = PERI_DEVICE_CPU;
}

/* The indenter's centre at time t (contributions/indenter.c). */
static void indenter_centre(const peri_sim *s, double t, double c[3]) {
  for (int d = 0; d < 3; ++d)
    c[d] = s->cond.indenter.on && s->cond.indenter.center[d] ? peri_expr_eval(s->cond.indenter.center[d], 0, 0, 0, t) : 0.0;
}

/* Whether a body force or traction changes in time (else b_ext is set once). */
static bool loads_follow_time(const peri_sim *s) {
  for (int k = 0; k < s->cond.n_bcs; ++k) {
    const peri_bc *bc = &s->cond.bcs[k];
    if (bc->kind != PERI_BC_BODY_FORCE && bc->kind != PERI_BC_TRACTION) continue;
    for (int d = 0; d < 3; ++d)
      if (bc->value[d] && peri_expr_uses_time(bc->value[d])) return true;
  }
  return false;
}

/* The loads other than the indenter's at time t into p->b (external_loads.c). */
static void external_loads(peri_sim *s, double t) {
  peri_particles *p = &s->disc.p;
  memset(p->b, 0, sizeof(double) * 3 * (size_t)p->n);
  if (peri_contribution_external_loads.active(s)) peri_contribution_external_loads.add_load(s, t, true);
}

/* The problem the device takes, from the sim; the arrays it points to are the sim's, or
 * allocated into *owned_mask and *owned_nodes and *owned_flags (freed by the caller). */
static void problem_of(const peri_sim *s, peri_gpu_problem *q, uint8_t **owned_mask, int32_t **owned_nodes,
                       uint8_t **owned_flags, double **owned_x) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const int32_t n = p->n_owned;
  memset(q, 0, sizeof *q);
  q->model = is_model(s, "pmb") ? PERI_GPU_PMB : PERI_GPU_LPS;
  q->n = n, q->n_bonds = b->offset[n];
  /* the bond loops' positions: a lattice's nodes at its exact coordinates (node_blocks.c) */
  const peri_geometry *geom = &s->disc.geom;
  double *x = peri_malloc(sizeof(double) * 3 * (size_t)(n > 0 ? n : 1));
  for (size_t c = 0; c < 3 * (size_t)n; ++c)
    x[c] = peri_bond_coordinate(geom, (int)(c % 3), p->x[c]);
  *owned_x = x;
  q->x = x, q->x_given = p->x, q->volume = p->volume, q->offset = b->offset, q->neighbor = b->neighbor, q->broken = b->broken;
  q->material = p->material, q->wvol = p->wvol;
  uint8_t *no_fail = peri_malloc((size_t)(n > 0 ? n : 1));
  for (int32_t i = 0; i < n; ++i) no_fail[i] = p->flags[i] & PERI_NODE_NO_FAIL ? 1 : 0;
  q->no_fail = no_fail;
  *owned_flags = no_fail;
  const int nm = s->mat.n_materials;
  q->n_materials = nm;
  for (int m = 0; m < nm; ++m) {
    const peri_material *mat = &s->mat.materials[m];
    q->density[m] = mat->density, q->micromodulus[m] = mat->micromodulus;
    q->n_theta[m] = mat->n_theta, q->K_theta[m] = mat->K_theta, q->alpha_m[m] = mat->alpha_m;
    q->peer_force_state[m] = mat->peer_force_state, q->s00[m] = mat->s00, q->alpha_s[m] = mat->alpha_s;
  }
  for (int k = 0; k < nm * nm; ++k) q->pair_s0[k] = s->mat.pair_s0[k];
  q->lammps_s0 = s->mat.s0_node != NULL;
  /* the family's rules as the bond loops evaluate them (src/model/bond_kernel.h) */
  const peri_family_params *f = &b->family;
  q->beta0 = 1.0, q->inv_dx = 0.0, q->inv_delta2 = 1.0 / (f->horizon * f->horizon), q->influence = (int)f->influence;
  if (f->rule != PERI_PV_NONE && f->spacing > 0) q->beta0 = 0.5 + f->horizon / f->spacing, q->inv_dx = 1.0 / f->spacing;
  q->dt = s->solver.dt, q->damping = s->solver.damping;
  q->breaking = s->solver.breaking, q->break_after_force = s->solver.break_after_force;
  q->indenter = s->cond.indenter.on;
  q->indenter_radius = s->cond.indenter.radius, q->indenter_stiffness = s->cond.indenter.stiffness;
  uint8_t *mask = peri_calloc((size_t)(n > 0 ? n : 1), 1);
  int32_t count = 0;
  for (int32_t i = 0; i < n; ++i) {
    for (int d = 0; d < 3; ++d)
      if (s->cond.prescribed[3 * (size_t)i + d]) mask[i] |= (uint8_t)(1u << d);
    count += mask[i] != 0;
  }
  int32_t *nodes = peri_malloc(sizeof(int32_t) * (size_t)(count > 0 ? count : 1));
  count = 0;
  for (int32_t i = 0; i < n; ++i)
    if (mask[i]) nodes[count++] = i;
  q->held_mask = mask, q->held_count = count, q->held_node = nodes;
  *owned_mask = mask, *owned_nodes = nodes;
}

/* A failed call of the device: its message, and the run's status. */
static int device_failed(const peri_gpu *g) {
  peri_error("GPU: %s", peri_gpu_error(g));
  return PERI_ERR_RUN;
}

/* The device's state into the sim: what output and checkpoints read. */
static int state_to_host(peri_sim *s, peri_gpu *g) {
  peri_particles *p = &s->disc.p;
  const int rc = peri_gpu_download(g, p->u, p->v, p->f, p->b, s->disc.bonds.broken, s->mat.s0_node, s->state.step_load);
  s->disc.bonds.broken_edits++; /* the CPU loops' copies of the flags follow (node_blocks.c) */
  return rc == 0 ? PERI_OK : device_failed(g);
}

int peri_solve_explicit_gpu(peri_sim *s, peri_step_hook hook, peri_step_quiet quiet, void *ctx) {
  peri_particles *p = &s->disc.p;
  const int32_t n = p->n_owned;
  const double dt = s->solver.dt;
  peri_gpu_problem q;
  uint8_t *mask = NULL, *no_fail = NULL;
  int32_t *held_node = NULL;
  double *x = NULL;
  problem_of(s, &q, &mask, &held_node, &no_fail, &x);
  char err[600];
  peri_gpu *g = peri_gpu_create(&q, err, sizeof err);
  free(no_fail);
  free(x);
  if (!g) {
    free(mask), free(held_node);
    peri_error("GPU: %s", err);
    return PERI_ERR_RUN;
  }
  const int32_t held_count = q.held_count;
  double *held = peri_malloc(sizeof(double) * 6 * (size_t)(held_count > 0 ? held_count : 1));
  if (!s->state.step_load) s->state.step_load = peri_calloc(3 * (size_t)(n > 0 ? n : 1), sizeof(double));
  const bool time_loads = loads_follow_time(s);
  double *b_keep = peri_malloc(sizeof(double) * 3 * (size_t)(n > 0 ? n : 1));
  memcpy(b_keep, p->b, sizeof(double) * 3 * (size_t)n);
  external_loads(s, s->state.time);
  int status = peri_gpu_upload(g, p->u, p->v, s->state.step > 0 ? p->f : NULL, p->b,
                               s->mat.s0_node, s->state.step_load) == 0
                   ? PERI_OK
                   : device_failed(g);
  memcpy(p->b, b_keep, sizeof(double) * 3 * (size_t)n);
  free(b_keep);
  /* the first step's force, evaluated on the device even where the host has it (the first
   * frame's), so that a run's arithmetic is the GPU's throughout; a restart resumes with the
   * checkpoint's forces and load */
  double centre[3];
  indenter_centre(s, s->state.time, centre);
  if (status == PERI_OK && peri_gpu_start(g, centre, s->state.step == 0, s->state.step == 0) < 0)
    status = device_failed(g);
  s->state.forces_current = false;
  /* the energy put into the body so far (explicit.c; no heat source runs on the GPU) */
  double energy_in = peri_explicit_energy_in(s);
  const long first_step = s->state.step;
  bool on_host = true; /* the host's copy is the device's state */
  for (long step = s->state.step; status == PERI_OK && step < s->solver.steps; ++step) {
    s->state.time += dt;
    s->state.step = step + 1;
    /* the held components' new values, from the host's copy of them (the device never moves
     * them, so the host's are current) */
    peri_apply_prescribed_motion(s, s->state.time, dt);
    for (int32_t h = 0; h < held_count; ++h)
      for (int d = 0; d < 3; ++d) {
        held[6 * h + d] = p->u[3 * (size_t)held_node[h] + d];
        held[6 * h + 3 + d] = p->v[3 * (size_t)held_node[h] + d];
      }
    if (time_loads) {
      external_loads(s, s->state.time);
      if (peri_gpu_set_loads(g, p->b) != 0) {
        status = device_failed(g);
        break;
      }
    }
    indenter_centre(s, s->state.time, centre);
    peri_gpu_step_sums sums;
    if (peri_gpu_step(g, held, centre, &sums) != 0) {
      status = device_failed(g);
      break;
    }
    on_host = false;
    for (int d = 0; d < 3; ++d) s->cond.indenter.force[d] = sums.indenter_force[d];
    s->state.external_work += sums.work;
    energy_in += fabs(sums.work);
    status = peri_explicit_check_step(s, sums.nonfinite == 0.0, sums.kinetic, energy_in, true);
    if (status != PERI_OK) break;
    if (hook) {
      /* the output after this step reads the state: copy it back first */
      if (!quiet || !quiet(s, s->state.step, ctx)) {
        if (state_to_host(s, g) != PERI_OK) {
          status = PERI_ERR_RUN;
          break;
        }
        on_host = true;
      }
      if (hook(s, ctx)) break;
    }
  }
  /* the last state, also after a failure (a run that fails midway keeps what it wrote) */
  if (!on_host && state_to_host(s, g) != PERI_OK) status = PERI_ERR_RUN;
  const double seconds = peri_gpu_step_seconds(g);
  const long steps = s->state.step - first_step;
  double bytes, per_bond;
  peri_gpu_memory(g, &bytes, &per_bond);
  s->par.gpu_seconds = seconds, s->par.gpu_steps = steps, s->par.gpu_bytes = bytes, s->par.gpu_bytes_per_bond = per_bond;
  peri_gpu_free(g);
  free(held);
  free(mask);
  free(held_node);
  return status;
}
