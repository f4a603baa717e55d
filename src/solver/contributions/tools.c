/* Rigid tools (include/peri/tools.h, docs/contact.md "Rigid tools"): on a node at y inside a
 * tool, the force density k pen^2 n (LAMMPS fix indent's law, pen the penetration and n the
 * way out) and the friction (mu f_n + min(tau0 / dx, f_n)) against the node's sliding on the
 * tool, -t/|t| with t the part of v_node - v_tool across n: Coulomb's mu, and the interfacial
 * shear strength tau0 acting on the node's face V / dx (Bowden and Tabor's F_t = tau0 A + mu P,
 * A the contact area), capped by the node's pressure f_n dx where that is lower (the edge of
 * the contact). The tool's force is summed per block of nodes in node order
 * (independent of threads and ranks). Under load control the tool's offset q along its
 * direction follows M q'' = P(t) - P_contact - M c q' (explicit runs). */
#include <math.h>
#include <stdlib.h>
#include "peri/contribution.h"
#include "peri/decompose.h"
#include "peri/discretize.h"
#include "peri/error.h"
#include "peri/tools.h"

/* Position of the tool at t (its expressions plus the load-controlled offset). */
static void tool_position(peri_tool *tl, double t, double out[3]) {
  for (int d = 0; d < 3; ++d) {
    out[d] = tl->position[d] ? peri_expr_eval(tl->position[d], 0.0, 0.0, 0.0, t) : 0.0;
    out[d] += tl->q * tl->geom.direction[d];
  }
}

/* Velocity of the tool at t: in explicit runs the central difference of its expressions over
 * half a step (exact for the linear and quadratic motions of a deck), plus the offset's rate;
 * in quasi-static runs (no time step) the backward difference, the way the tool came to t, so
 * that a load step that ends where a slide begins (a kink in the motion) has no friction yet. */
static void tool_velocity(const peri_sim *s, peri_tool *tl, double t, double out[3]) {
  const bool explicit_step = !peri_is_quasi_static(s) || s->solver.qs.phase == PERI_QS_PHASE_DYNAMIC;
  const double h = explicit_step ? 0.25 * s->solver.dt : 1e-6 * s->solver.end_time / (double)s->solver.qs.load_steps;
  for (int d = 0; d < 3; ++d) {
    out[d] = tl->q_rate * tl->geom.direction[d];
    if (tl->position[d] && !peri_expr_is_constant(tl->position[d])) {
      const double ahead = peri_expr_eval(tl->position[d], 0.0, 0.0, 0.0, explicit_step ? t + h : t);
      out[d] += (ahead - peri_expr_eval(tl->position[d], 0.0, 0.0, 0.0, t - h)) / (explicit_step ? 2.0 * h : h);
    }
  }
}

static void apply_tool(peri_sim *s, peri_tool *tl, double t) {
  peri_particles *p = &s->disc.p;
  double at[3], vt[3];
  tool_position(tl, t, at);
  tool_velocity(s, tl, t, vt);
  const double *dir = tl->geom.direction;
  if (!tl->started) {
    tl->started = true;
    tl->last_t = t;
    for (int d = 0; d < 3; ++d) tl->start[d] = at[d], tl->last_at[d] = at[d];
  } else if (t > tl->last_t) { /* the path across `direction` since the last, earlier time (a
                                 * solver that evaluates an earlier time again adds nothing) */
    double step[3], along = 0.0, len2 = 0.0;
    for (int d = 0; d < 3; ++d) step[d] = at[d] - tl->last_at[d], along += step[d] * dir[d];
    for (int d = 0; d < 3; ++d) len2 += (step[d] - along * dir[d]) * (step[d] - along * dir[d]);
    tl->sliding += sqrt(len2);
    tl->last_t = t;
    for (int d = 0; d < 3; ++d) tl->last_at[d] = at[d];
  }
  for (int d = 0; d < 3; ++d) tl->at[d] = at[d], tl->velocity[d] = vt[d];
  const int32_t n = p->n_owned;
  const int64_t n_blocks = peri_sum_blocks_owned(s);
  if (tl->blocks != n_blocks) {
    free(tl->block_force);
    tl->block_force = peri_malloc(sizeof(double) * 4 * (size_t)(n_blocks > 0 ? n_blocks : 1));
    tl->blocks = n_blocks;
  }
  const double k = tl->stiffness, mu = tl->friction, tau0 = tl->shear_strength;
  const peri_geometry *grid = &s->disc.geom;
  /* kinematic contact (MODELS.md 17.2, after Madenci & Oterkus): the force density rho pen / dt^2 is the
   * momentum change rho (v_bar - v) / dt that, over the step, puts the node back on the
   * surface (v_bar - v = pen / dt), so the tool's force is -sum rho (v_bar - v) V / dt */
  const double inv_dt2 = tl->kinematic ? 1.0 / (s->solver.dt * s->solver.dt) : 0.0;
  const peri_material *mats = s->mat.materials;
  const peri_tool_geometry *g = &tl->geom;
#pragma omp parallel for schedule(static)
  for (int64_t blk = 0; blk < n_blocks; ++blk) {
    const int32_t i0 = (int32_t)(blk * PERI_SUM_BLOCK), i1 = i0 + PERI_SUM_BLOCK < n ? i0 + PERI_SUM_BLOCK : n;
    double sum[4] = {0.0, 0.0, 0.0, 0.0};
    for (int32_t i = i0; i < i1; ++i) {
      double y[3], nrm[3];
      for (int d = 0; d < 3; ++d) y[d] = p->x[3 * (size_t)i + d] + p->u[3 * (size_t)i + d];
      if (!peri_tool_may_touch(g, at, y)) continue;
      const double pen = peri_tool_penetration(g, at, y, nrm);
      if (!(pen > 0.0)) continue;
      /* the node's face on the tool: its volume over its own spacing (dx^2 in 3D, dx h in 2D) */
      const double dx = peri_grid_node_spacing(p->volume[i], grid->dim, grid->thickness, grid->cross_section);
      sum[3] += p->volume[i] / dx;
      const double fn = tl->kinematic ? mats[p->material[i]].density * inv_dt2 * pen : k * pen * pen;
      double f[3];
      for (int d = 0; d < 3; ++d) f[d] = fn * nrm[d];
      if (mu > 0.0 || tau0 > 0.0) { /* friction: against the node's sliding on the tool */
        double rel[3], vn = 0.0, tt = 0.0;
        for (int d = 0; d < 3; ++d) rel[d] = p->v[3 * (size_t)i + d] - vt[d], vn += rel[d] * nrm[d];
        for (int d = 0; d < 3; ++d) rel[d] -= vn * nrm[d], tt += rel[d] * rel[d];
        if (tt > 0.0) {
          /* the shear traction tau0, but never more than the node's pressure fn dx: it grows
           * from 0 as a node enters the contact, so the force has no jump there */
          const double shear = tau0 / dx < fn ? tau0 / dx : fn;
          const double scale = (mu * fn + shear) / sqrt(tt);
          for (int d = 0; d < 3; ++d) f[d] -= scale * rel[d];
        }
      }
      for (int d = 0; d < 3; ++d) {
        p->b[3 * (size_t)i + d] += f[d];
        sum[d] -= f[d] * p->volume[i];
      }
    }
    for (int d = 0; d < 4; ++d) tl->block_force[4 * blk + d] = sum[d];
  }
  double total[4];
  peri_sum_blocks(s, tl->block_force, 4, total);
  for (int d = 0; d < 3; ++d) tl->force[d] = total[d];
  tl->contact_area = total[3];
  double along = 0.0, tangential = 0.0;
  for (int d = 0; d < 3; ++d) along += tl->force[d] * dir[d];
  for (int d = 0; d < 3; ++d) tangential += (tl->force[d] - along * dir[d]) * (tl->force[d] - along * dir[d]);
  tl->normal_force = -along; /* the body pushes the tool back against `direction` */
  if (!tl->touched && tl->normal_force > 0.0) { /* where the penetration depth counts from */
    tl->touched = true;
    for (int d = 0; d < 3; ++d) tl->contact_at[d] = at[d];
  }
  tl->tangential_force = sqrt(tangential);
}

static void add_tools(peri_sim *s, double t, bool sets) {
  (void)sets; /* sets_every_node is false */
  for (int k = 0; k < s->tools->count; ++k) apply_tool(s, &s->tools->tool[k], t);
}

/* Load control: the tool's offset by its damped equation over the step ending at t, from the
 * contact force of the step before (semi-implicit Euler). */
static int advance_tools(peri_sim *s, long step, double t) {
  (void)step;
  const double dt = s->solver.dt;
  for (int k = 0; k < s->tools->count; ++k) {
    peri_tool *tl = &s->tools->tool[k];
    if (!tl->load) continue;
    const double P = peri_expr_eval(tl->load, 0.0, 0.0, 0.0, t);
    const double acc = (P - tl->normal_force) / tl->mass - tl->damping * tl->q_rate;
    tl->q_rate += acc * dt;
    tl->q += tl->q_rate * dt;
    if (!isfinite(tl->q)) {
      peri_error("tool '%s': its load-controlled position is no longer finite at t = %g s; a larger mass or "
                 "damping, or a smaller time step, keeps it stable (docs/contact.md)", tl->name, t);
      return PERI_ERR_RUN;
    }
  }
  return PERI_OK;
}

static bool tools_active(const peri_sim *s) { return s->tools && s->tools->count > 0; }

const peri_contribution_ops peri_contribution_tools = {
    .name = "rigid tools",
    .active = tools_active,
    .before_force = advance_tools,
    .add_load = add_tools,
    .sets_every_node = false,
    .follows_deformation = true,
};
