/* The summary a run prints before it starts (and `peri check` prints): the discretization,
 * the memory estimate, materials, time step or quasi-static settings, heat conduction and
 * checkpoints. */
#include <omp.h>
#include <stdio.h>
#include "peri/checkpoint.h"
#include "peri/checkpoint_schedule.h"
#include "peri/coupling.h"
#include "peri/contact.h"
#include "peri/short_range.h"
#include "peri/damage.h"
#include "peri/energies.h"
#include "peri/gpu.h"
#include "peri/model.h"
#include "peri/quasistatic.h"
#include "peri/run.h"
#include "peri/solver.h"
#include "peri/thermal.h"
#include "peri/tensor_plasticity.h"

static const char *const kernel_names[] = {"conical", "constant"};
static const char *const quad_names[] = {"bonds", "bobaru2012"};
static const char *const self_names[] = {"none", "cell", "bobaru2012"};
static const char *const rule_names[] = {"lower", "harmonic"};
static const char *const integrator_names[] = {"rk4", "euler"};
static const char *const coupling_names[] = {"two_way", "one_way"};
static const char *const insulation_names[] = {"natural", "algebraic"};

void peri_thermal_print_summary(const peri_sim *s, FILE *out) {
  const peri_thermal *th = s->thermal;
  if (!th) return;
  if (s->solver.kind == PERI_SOLVER_HEAT) {
    peri_print_discretization(s, out, "heat conduction", "cut");
    fprintf(out, "  memory       %.1f MB estimated\n",
            (peri_memory_estimate(s) + 16.0 * (double)s->disc.bonds.n_bonds + 80.0 * s->disc.p.n) / 1e6);
    for (int m = 0; m < s->mat.n_materials; ++m) {
      const peri_material *mat = &s->mat.materials[m];
      fprintf(out, "  material     %s: rho %g, conductivity %g, specific heat %g, diffusivity %g\n", mat->name,
              mat->density, mat->conductivity, mat->specific_heat,
              mat->conductivity / (mat->density * mat->specific_heat));
    }
  }
  fprintf(out, "  thermal      kernel %s, quadrature %s, self term %s, insulation %s, bonds between "
          "materials %s\n", kernel_names[th->kernel], quad_names[th->quadrature], self_names[th->self_term],
          insulation_names[th->insulation], rule_names[th->bond_rule]);
  if (s->solver.kind == PERI_SOLVER_HEAT) {
    fprintf(out, "  time step    %g s (%s, stable estimate %g s from the largest row sum %g 1/s), %ld steps "
            "to t = %g s\n", s->solver.dt, integrator_names[th->integrator], th->dt_stable, th->max_row_sum, s->solver.steps,
            s->solver.dt * s->solver.steps);
  } else {
    fprintf(out, "  heat step    %g s (%s, stable estimate %g s), coupling %s%s\n", th->dt,
            integrator_names[th->integrator], th->dt_stable, coupling_names[th->coupling],
            th->n_growing ? ", growing cracks" : "");
  }
}

/* The deviatoric rule's bytes per directed bond beside the sublayers: the reverse bond's index,
 * the slot of its plastic term, the term and its reverse's slot (counted as one slot a bond: a
 * block of nodes whose families differ keeps a few more, 6.5% more on a 24 x 12 x 12 block at
 * m = 3) and, where it is stored, the bond's weight (docs/plasticity.md section 8). */
static int deviatoric_bytes(const peri_sim *s) {
  return s->state.plastic_reverse ? (s->state.plastic_bond_weight ? 40 : 32) : 0;
}

double peri_memory_estimate(const peri_sim *s) {
  const double n = s->disc.p.n, nb = (double)s->disc.bonds.n_bonds;
  /* x u v f b (5 x 3 doubles), volume, damage, material, block, flags, + model arrays */
  double per_node = 15 * 8 + 8 + 8 + 4 + 4 + 1 + 3;
  if (s->disc.p.theta) per_node += 3 * 8;
  if (s->mat.s0_node) per_node += 2 * 8;
  per_node += peri_tensor_bytes_per_node(s); /* the tensor yield rule (docs/plasticity.md section 10) */
  per_node += 6 * 8; /* the bond loops' copies of x and u (src/model/node_blocks.c) */
  /* sublayer plastic stretches and, for the deviatoric rule, the reverse bond's index, the
   * plastic term, the slots and, where it is stored, the bond's weight (docs/plasticity.md) */
  const double plastic = 8.0 * s->state.plastic_layers + deviatoric_bytes(s);
  return n * per_node + (n + 1) * 8 +
         nb * (peri_bonds_bytes_per_bond(&s->disc.bonds) + peri_node_blocks_bytes_bound() + plastic);
}

static const char *model_plane(const peri_sim *s) {
  if (s->disc.geom.dim != 2) return "";
  return s->disc.geom.plane == PERI_PLANE_STRAIN ? ", plane strain" : ", plane stress";
}

void peri_print_discretization(const peri_sim *s, FILE *out, const char *model, const char *broken) {
  fprintf(out, "peri %s: %s\n", PERI_VERSION, s->deck_path);
  fprintf(out, "  model        %s, %dD%s\n", model, s->disc.geom.dim, s->solver.kind == PERI_SOLVER_HEAT ? "" : model_plane(s));
  fprintf(out, "  nodes        %d\n", s->disc.p.n);
  /* (the GPU tests take the scale of the momentum from it, tests/gpu) */
  fprintf(out, "  mass         %.6g kg\n", peri_total_mass(s));
  if (s->coupling) { /* PD-FEM coupling (docs/coupling.md) */
    static const char *const element[] = {"", "bar", "Q4", "Hex8"};
    fprintf(out, "  coupling     %d PD nodes, %d FEM nodes, %d %s elements%s\n", (int)s->coupling->n_pd,
            (int)(s->disc.p.n - s->coupling->n_pd), (int)s->coupling->n_elements,
            s->coupling->mesh_file ? "mesh file" : s->coupling->fem_only ? "graded (Q4 and triangles)" : element[s->disc.geom.dim],
            s->coupling->exact_volumes ? ", exact partial volumes" : "");
    if (s->coupling->mesh_file)
      fprintf(out, "  mesh file    %s: %d nodes with their elements' volumes, %d PD grid nodes left out\n",
              s->coupling->mesh_file, (int)s->coupling->coarse_nodes, (int)s->coupling->removed_nodes);
    else if (s->coupling->fem_only)
      fprintf(out, "  graded mesh  %d nodes of coarse elements, %d lattice nodes left out\n",
              (int)s->coupling->coarse_nodes, (int)s->coupling->removed_nodes);
    if (s->solver.breaking)
      fprintf(out, "  switching    FEM nodes within %g horizons of a PD node with a broken bond become PD\n",
              s->coupling->switch_radius);
  }
  fprintf(out, "  bonds        %lld directed (%.1f per node), %ld %s\n", (long long)s->disc.bonds.n_bonds,
          s->disc.p.n ? (double)s->disc.bonds.n_bonds / s->disc.p.n : 0.0, peri_broken_count(&s->disc.bonds), broken);
  fprintf(out, "  horizon      %g (m = %.4g, spacing %g)\n", s->disc.geom.horizon, s->disc.geom.horizon / s->disc.geom.spacing,
          s->disc.geom.spacing);
}

/* The nodes of material m (counted where the "nodes" line is: before the nodes are distributed). */
static long material_nodes(const peri_sim *s, int m) {
  long count = 0;
  for (int i = 0; i < s->disc.p.n; ++i) count += s->disc.p.material[i] == m;
  return count;
}

void peri_print_summary(const peri_sim *s, FILE *out) {
  if (s->solver.kind == PERI_SOLVER_HEAT) { /* conduction only (docs/heat.md) */
    peri_thermal_print_summary(s, out);
    peri_checkpoint_print_summary(s, out); /* docs/restart.md */
    return;
  }
  peri_print_discretization(s, out, s->mat.model->name, "broken");
  fprintf(out, "  memory       %.1f MB estimated (%.1f bytes per directed bond, node blocks at most %.2f more)\n",
          peri_memory_estimate(s) / 1e6, peri_bonds_bytes_per_bond(&s->disc.bonds), peri_node_blocks_bytes_bound());
  for (int m = 0; m < s->mat.n_materials; ++m) {
    const peri_material *mat = &s->mat.materials[m];
    char count[48] = ""; /* several materials: how many nodes each has (defects change it) */
    if (s->mat.n_materials > 1) snprintf(count, sizeof count, "%ld nodes, ", material_nodes(s, m));
    fprintf(out, "  material     %s: %srho %g, E %g, nu %.4g, K %g, critical stretch %g%s\n", mat->name, count,
            mat->density, mat->E, mat->nu, mat->K, mat->lammps_s0 ? mat->s00 : mat->critical_stretch,
            mat->lammps_s0 ? " (s00, compression-dependent)" : "");
    const peri_sublayers *sl = mat->sublayers;
    if (!sl) continue;
    if (sl->deviatoric)
      fprintf(out, "  plasticity   %s: %s yield rule, %d sublayers (W, e_y):", mat->name,
              sl->tensor ? "deviatoric tensor" : "deviatoric", sl->n);
    else
      fprintf(out, "  plasticity   %s: %d sublayers (W, s_y):", mat->name, sl->n);
    for (int k = 0; k < sl->n; ++k) fprintf(out, " (%.4f, %.4g)", sl->weight[k], sl->yield[k]);
    fprintf(out, "\n");
  }
  if (s->state.plastic_reverse)
    fprintf(out, "  plastic state about %d bytes per directed bond (%d plastic deviatoric stretches, the reverse bond's "
                 "index, the plastic term, its reverse's and its own slot%s)\n",
            8 * s->state.plastic_layers + deviatoric_bytes(s), s->state.plastic_layers,
            s->state.plastic_bond_weight ? ", the weight" : "");
  else if (s->state.plastic_stretch)
    fprintf(out, "  plastic state %d bytes per directed bond (%d plastic stretches)\n", 8 * s->state.plastic_layers,
            s->state.plastic_layers);
  else if (s->state.plastic_tensor)
    fprintf(out, "  plastic state %.0f bytes per node, none per bond (%d plastic tensors of 6 components, the plastic "
                 "term, the family's moments)\n",
            peri_tensor_bytes_per_node(s), s->state.plastic_tensor->layers);
  if (peri_is_quasi_static(s)) peri_print_quasi_static_summary(s, out);
  else
    fprintf(out, "  time step    %g s (stable estimate %g s), %ld steps to t = %g s\n", s->solver.dt,
            peri_stable_dt(s), s->solver.steps, s->solver.dt * s->solver.steps);
  if (s->contact && s->contact->short_range) /* docs/contact.md */
    fprintf(out, "  contact      short-range forces: c_S = %g c, d = min(%g |xi|, %g m), list skin %g m, pruned with %g m\n",
            s->contact->stiffness_factor, PERI_SHORT_RANGE_RATIO, peri_contact_max_reach(s), s->contact->skin,
            s->contact->prune_skin);
  if (s->thermal) peri_thermal_print_summary(s, out); /* thermomechanics (docs/heat.md) */
  peri_checkpoint_print_summary(s, out);               /* docs/restart.md */
}

void peri_print_threads(const peri_sim *s, FILE *out) {
  if (!s->par.omp_wait) return;
  const int threads = omp_get_max_threads();
  fprintf(out, "  threads      %d OpenMP thread%s per process, %s\n", threads, threads == 1 ? "" : "s",
          s->par.omp_wait);
  if (s->par.device == PERI_DEVICE_GPU) { /* docs/gpu.md */
    double bytes, peak;
    peri_gpu_memory_estimate(s, &bytes, &peak);
    fprintf(out, "  device       GPU: %s; the explicit steps run there (%.3g GB on the device, %.3g GB while the "
            "families are laid out), the set-up and output on the CPU\n", s->par.device_name, bytes / 1e9, peak / 1e9);
  }
}
