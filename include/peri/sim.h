/* A simulation: the discretization, materials, conditions, and solver and output
 * settings a deck describes. */
#ifndef PERI_SIM_H
#define PERI_SIM_H
#include <stdbool.h>
#include "peri/particles.h"
#include "peri/bonds.h"
#include "peri/material.h"
#include "peri/model.h"
#include "peri/region.h"
#include "peri/expr.h"

typedef enum {
  PERI_BC_DISPLACEMENT,         /* prescribed displacement per component, expr of x,y,z,t */
  PERI_BC_VELOCITY,             /* prescribed velocity per component */
  PERI_BC_INITIAL_DISPLACEMENT,
  PERI_BC_INITIAL_VELOCITY,
  PERI_BC_BODY_FORCE,           /* force density (N/m^3) */
  PERI_BC_TRACTION,             /* traction (N/m^2) spread over a layer: b = T / layer */
} peri_bc_kind;

typedef struct peri_bc {
  peri_bc_kind kind;
  int region;                   /* index in sim->cond.regions */
  peri_expr *value[3];          /* per component, NULL = not prescribed */
  double layer;                 /* traction: layer depth (default dx) */
} peri_bc;

/* Rigid spherical indenter (LAMMPS fix indent): force density k (R - r)^2 outward for
 * r < R, centre moving by expressions of t. */
typedef struct peri_indenter {
  bool on;
  double radius, stiffness;
  peri_expr *center[3];
  double force[3];              /* total force on the indenter in the last evaluation */
  double *block_force;          /* reactions summed per block of nodes (3 per PERI_SUM_BLOCK) */
  int64_t blocks;
} peri_indenter;

typedef struct peri_precrack {
  int dim;                      /* 2: segment a-b; 3: rectangle corner a, edges e1, e2 */
  double a[3], b[3], e1[3], e2[3];
} peri_precrack;

typedef enum {
  PERI_SOLVER_EXPLICIT = 0,
  PERI_SOLVER_ADR = 1,                /* adaptive dynamic relaxation (docs/model_reference.md 12.2) */
  PERI_SOLVER_DYNAMIC_RELAXATION = 2, /* damped velocity-Verlet (docs/model_reference.md 12.1) */
  PERI_SOLVER_NLCG = 3,               /* nonlinear conjugate gradients, PR+ (docs/model_reference.md 12.3) */
  PERI_SOLVER_IMPLICIT = 4,           /* Newton with the assembled tangent, PETSc (docs/solvers.md) */
  PERI_SOLVER_HEAT = 10,              /* heat conduction only (docs/heat.md) */
} peri_solver_kind;

/* Switch of a quasi-static run to explicit dynamics while a crack grows unstably, and back
 * when it arrests (docs/solvers.md section 4). */
typedef struct peri_qs_dynamic_switch {
  bool on;
  long when_broken_exceeds;     /* directed bonds broken at one load step that start a dynamic phase */
  double time_step;             /* 0: safety_factor x the stable estimate */
  double safety_factor;
  double damping;               /* mass-proportional damping (1/s) of the dynamic phase */
  double arrest_kinetic_energy; /* arrested: kinetic energy below this fraction of the phase's peak */
  long arrest_steps;            /* ... or no bond broke for this many steps (0: the wave-crossing default) */
  long max_dynamic_steps;       /* steps of one dynamic phase at most */
  long history_every;           /* a history row every this many dynamic steps */
} peri_qs_dynamic_switch;

/* Phase of a quasi-static run, the history column `phase`. */
typedef enum { PERI_QS_PHASE_STATIC = 0, PERI_QS_PHASE_DYNAMIC = 1 } peri_qs_phase;

/* Quasi-static solver settings (docs/solvers.md) and what the last run did. */
typedef struct peri_quasi_static {
  long load_steps;              /* pseudo-time t = end_time * n / load_steps, n = 1..load_steps */
  double tolerance;             /* relative residual |V(f+b)| / |reference force| */
  long max_iterations;          /* per solve */
  double stiffness_factor;      /* ADR: f_s in the fictitious density */
  double bond_damping;          /* dynamic_relaxation: pairwise damping gamma (Le 2014 eq. 2.43) */
  bool preconditioner;          /* nlcg: Jacobi with the ADR density */
  long max_broken_per_step;     /* cut the load step back when more bonds break (0: no limit) */
  int max_cutbacks;             /* halvings of one load step */
  long max_fracture_iterations; /* re-solves at one load (break, solve, ...) */
  /* implicit (docs/solvers.md): Newton with the tangent stiffness, linear solves by PETSc */
  int linear_solver;            /* peri_linear_solver (include/peri/implicit.h) */
  int petsc_preconditioner;     /* peri_petsc_preconditioner */
  char petsc_options[1024];     /* solver.petsc_options, for PetscOptionsInsertString */
  long linear_iterations;       /* statistics: Krylov iterations over all solves */
  peri_qs_dynamic_switch dynamic; /* solver.dynamic_switch (src/solver/qs_dynamic.c) */
  peri_qs_phase phase;          /* static, or inside a dynamic phase */
  double dynamic_time;          /* physical time spent in dynamic phases (s) */
  long dynamic_phases, dynamic_steps; /* statistics of the dynamic phases */
  /* statistics of the run */
  long iterations, solves, force_evaluations, cutbacks;
  double residual;              /* last relative residual */
  long solve_iterations;        /* iterations of the solve under way (progress lines) */
  long broken_in_run;           /* directed bonds broken by the load steps (all ranks) */
  double reference, last_reference; /* reference force norm: largest at a converged state, and
                                   the current one (after a break-through the load may vanish) */
} peri_quasi_static;

typedef struct peri_output {
  char *directory;
  char *basename;               /* deck file name without extension */
  long every;                   /* steps between frames (0: first and last only) */
  int n_fields;
  char **fields;                /* names of fields to write */
  bool compress;
  long history_every;
  int history_digits;           /* significant digits of history.csv's values (output.history_digits) */
  bool picture;                 /* PNG at the end (2D) */
  char *picture_field;
  int picture_width;
  char *plot_x, *plot_y;         /* history columns of the end-of-run line plot (NULL: none) */
  peri_expr *plot_reference;     /* output.plot.reference: a curve of x drawn with it (NULL: none) */
  long checkpoint_every;        /* steps between checkpoints (0: none; docs/restart.md) */
  char *checkpoint_file;        /* checkpoint path, "{step}" = step number (NULL: <basename>.h5) */
  bool quiet;                   /* no summary and no progress line */
  bool vtu, exodus;             /* output.format: the VTU series, the Exodus II file (docs/output.md) */
  bool phase_stress;            /* output.phase_stress: per-material stress columns in history.csv (docs/microstructures.md) */
  /* films on substrates (docs/thin_films.md): history columns of the interfaces between
   * materials, the strain energy of every region, and the wrinkles of a film region (its
   * index in cond.regions, 0: none) */
  bool interface_history, region_energy;
  int wrinkle_region;
  struct peri_j_integral *j_integral; /* the j_integral section: J and crack extension columns (docs/plasticity.md), NULL: none */
  struct peri_dataset_output *dataset; /* output.dataset: the graph dataset (docs/datasets.md), NULL without */
  int picture_normal;           /* 3D pictures: axis normal to the picture plane (0 x, 1 y, 2 z) */
  bool picture_projection;      /* 3D pictures: every node seen along the normal (else a slice) */
  bool picture_at_given;        /* 3D slice: at picture_at (else the middle of the body) */
  double picture_at;
  /* progress (docs/deck.md section 1, --progress): on a terminal a live line, otherwise a
   * line every progress_every seconds to stderr (0: none); progress_lines asks for the lines
   * on a terminal too. The run driver sets `progress`, which the solvers call at every
   * iteration (src/run/progress.c decides when to print). */
  double progress_every;
  bool progress_lines;
  void (*progress)(struct peri_sim *s);
  void *progress_state;
} peri_output;

/* The discretization: geometry, nodes, bonds and the bond loops' work items. */
typedef struct peri_discretization {
  peri_geometry geom;
  peri_particles p;
  peri_bonds bonds;
  peri_family_params family;
  bool analytic_weighted_volume; /* LPS: m from the full-horizon integral (else discrete) */
  int surface_correction;       /* peri_surface_correction (docs/models.md 4.1) */
  /* work items of the bond loops (src/model/node_blocks.c), built on first use */
  struct peri_node_blocks *node_blocks;
  bool generic_bond_loops;      /* tests: every node by the one-node path */
  struct peri_horizon_field *horizon_field; /* a horizon per node (docs/variable_horizon.md), else NULL */
} peri_discretization;

/* The constitutive model and the materials with their resolved constants. */
typedef struct peri_materials {
  const peri_model_ops *model;
  int n_materials;
  peri_material *materials;
  double *pair_s0;              /* [n_materials^2] critical stretch of a bond by end materials */
  double *pair_strength;        /* [n_materials^2] interface normal strength (Pa, 0: none); NULL: no pair has one */
  struct peri_interface_moduli *interface_moduli; /* PMB bonds between two materials with their own modulus
                                                   (include/peri/interface_moduli.h); NULL: none */
  double *s0_node;              /* LAMMPS form: s0 of each node for this step (else NULL) */
} peri_materials;

/* Regions and what the deck sets on them: boundary conditions and loads, pre-cracks, the
 * indenter. */
typedef struct peri_conditions {
  int n_regions;
  peri_region *regions;
  int n_bcs;
  peri_bc *bcs;
  int n_precracks;
  peri_precrack *precracks;
  peri_indenter indenter;
  uint8_t *prescribed;          /* [3n] component has a prescribed displacement/velocity */
} peri_conditions;

/* Surface corrections (docs/models.md 4.1): none, the energy-ratio factors of Madenci and
 * Oterkus, or the family-volume ratio (PMB). */
typedef enum { PERI_SURFACE_NONE = 0, PERI_SURFACE_ENERGY = 1, PERI_SURFACE_VOLUME = 2,
               PERI_SURFACE_POSITION_AWARE = 3 } peri_surface_correction;

/* Solver settings: which solver, the time step and the number of steps, damping, breaking,
 * and the quasi-static settings. */
typedef struct peri_solver_settings {
  peri_solver_kind kind;
  double dt;                    /* time step in use */
  double dt_given;              /* 0: estimate */
  double safety_factor;
  long steps;                   /* number of steps (derived from end_time if given) */
  double end_time;
  double damping;               /* viscous damping coefficient (1/s), 0 = none */
  bool breaking;                /* bonds may break */
  bool break_after_force;       /* LAMMPS order: a step's force with the bonds of its start, then
                                   the cut (docs/models.md 5.1); else the cut, then the force */
  peri_quasi_static qs;          /* quasi-static solvers */
} peri_solver_settings;

/* The state of a run beyond the node fields: time, step, work, and what a checkpoint keeps. */
typedef struct peri_state {
  double time;
  long step;
  bool forces_current;          /* p->f holds the forces of the present state (set by a caller
                                   that evaluated them; the explicit solver then does not
                                   evaluate them again at its first step, and clears it) */
  double external_work;
  double *step_load;            /* explicit: [3n] external load density of the last step, the left
                                   end of the next step's work integral (kept for checkpoints) */
  double *thermal_strain;       /* [n] alpha_T,eff (T - T_ref) per node, NULL without thermomechanics */
  /* sublayer plasticity (docs/plasticity.md): plastic_layers plastic stretches per directed
   * bond (bond k's at plastic_stretch[k * plastic_layers], or in the deviatoric rule's slots:
   * plastic_slots below), NULL when no material is plastic */
  double *plastic_stretch;
  int plastic_layers;
  /* quasi-static solvers: the plastic stretches of the last accepted load step, from which
   * every iteration maps (so the iterations' path leaves no plastic trace); NULL in dynamics,
   * whose steps map from the previous step in place */
  double *plastic_committed;
  /* [n] 1 for a node some bond of which has a nonzero plastic stretch (or had one: never
   * cleared), and the longest bond: the plastic loops' screen (src/model/plastic_bonds.c),
   * built from the state when NULL; whoever sets the state from outside the loops frees it */
  uint8_t *plastic_nodes;
  double plastic_reach;
  /* the deviatoric yield rule (docs/plasticity.md section 8): [n_bonds] the index of bond
   * j -> i for bond k = i -> j (a node's force reads its neighbours' plastic term of the
   * bond); on MPI ranks, where j is a ghost, n_bonds + k. NULL for the bond rule */
  int64_t *plastic_reverse;
  /* the deviatoric yield rule: for bond k = i -> j node i's plastic term alpha_i sum_l W_l
   * s^dp_l,ij at plastic_bond_term[plastic_slots.bond_slot[k]], written by i's return mapping
   * (recomputed at every force evaluation by every node that has a plastic state, 0 for the
   * others); on MPI ranks entry n_slots + k of a bond into a ghost holds the ghost's term of
   * the bond (the bond halo). Allocated with the slots at the first return; NULL before and for
   * the bond rule */
  double *plastic_bond_term;
  /* where the terms and the plastic state are (src/model/deviatoric_plasticity.c): a block of
   * eight nodes keeps its bonds' in template order, entry a's lanes at item_slot[item] + 8 a +
   * lane, so that its loops store and load them as vectors; the other nodes in family order.
   * Built at the first return for the node blocks' items of one build (generation; 0: not built) */
  struct peri_plastic_slots {
    uint64_t generation;
    bool state_in_slots;    /* plastic_stretch (and plastic_committed) in the slots' order too:
                               bond k's layer l at peri_plastic_layer_index(bond_slot[k], l, L,
                               block_slots);
                               else in bond rows, k L + l (before the first return, after a
                               checkpoint is read: peri_plastic_row reads either) */
    int64_t n_slots;
    int64_t block_slots;    /* the blocks' slots (template order) come first, then the others' */
    int64_t *item_slot;     /* [n_items] each item's first slot */
    int64_t *bond_slot;     /* [n_bonds] bond k's slot */
    int64_t *entry_reverse; /* [n_slots] the slot of the reverse of the bond in each slot (n_slots + k for
                               a bond k into a ghost: its entry for the bond halo), 0 in an unused one */
  } plastic_slots;
  /* the deviatoric yield rule: [n_bonds] omega beta V_j of each bond i -> j, its weight in the
   * family sums (fixed by the reference configuration), where the eight-lane kernels do not
   * evaluate it (Gaussian influence, builds without them); NULL otherwise and for the bond rule */
  double *plastic_bond_weight;
  /* the tensor yield rule (docs/plasticity.md section 10, src/model/tensor_plasticity.c): a
   * plastic deviatoric strain tensor per node and sublayer; NULL for the other rules */
  struct peri_tensor_plasticity *plastic_tensor;
  struct peri_restart *restart; /* checkpoint to continue from (--restart), NULL otherwise */
} peri_state;

/* Threads and distributed runs (docs/parallel.md). */
typedef struct peri_parallel {
  int threads;
  /* the OpenMP wait policy in force and how to change it, for the summary's threads line
   * (set by the program, app/omp_wait.c; NULL: no line) */
  const char *omp_wait;
  /* this rank's part, NULL in a single process */
  struct peri_decomposition *dd;
  /* the nodes whose values the equations of node g read beyond its bonds, in the built
   * (global) numbering: reach_node[reach_offset[g] .. reach_offset[g+1]-1] (the corners of its
   * elements in a PD-FEM coupling). peri_decompose makes them ghosts too, and frees them;
   * NULL when the bonds are all. */
  int64_t *reach_offset;
  int32_t *reach_node;
  /* copies the owners' values of a per-node field (ncomp doubles per node) into the ghost
   * slots; NULL in a single process. Call it through peri_sim_exchange. */
  void (*exchange)(struct peri_sim *s, double *field, int ncomp);
  /* where the explicit steps run (peri_device, include/peri/gpu.h: --device gpu) and, after a
   * GPU run, the device's name, its steps and their seconds and its memory (the summary's gpu
   * line, docs/gpu.md) */
  int device;
  char device_name[160];
  long gpu_steps;
  double gpu_seconds, gpu_bytes, gpu_bytes_per_bond;
} peri_parallel;

/* A simulation, one member per subsystem: a new subsystem adds one member. */
typedef struct peri_sim {
  char *deck_path;
  peri_discretization disc;
  peri_materials mat;
  peri_conditions cond;
  peri_solver_settings solver;
  peri_state state;
  peri_output out;
  peri_parallel par;
  struct peri_thermal *thermal;  /* heat conduction (docs/heat.md), NULL without */
  struct peri_coupling *coupling; /* PD-FEM coupling (docs/coupling.md), NULL without */
  struct peri_contact *contact;  /* contact (docs/contact.md), NULL without */
  struct peri_bodies *bodies;    /* the bodies key (docs/contact.md "Bodies"), NULL without */
  struct peri_tools *tools;      /* rigid tools (docs/contact.md "Rigid tools"), NULL without */
} peri_sim;

/* Whether the solver is one of the quasi-static ones (adr, dynamic_relaxation, nlcg, implicit). */
static inline bool peri_is_quasi_static(const peri_sim *s) {
  return s->solver.kind == PERI_SOLVER_ADR || s->solver.kind == PERI_SOLVER_DYNAMIC_RELAXATION || s->solver.kind == PERI_SOLVER_NLCG ||
         s->solver.kind == PERI_SOLVER_IMPLICIT;
}

/* Ghost values of a per-node field from their owners (a no-op in a single process). A
 * kernel that reads field[j] of a neighbour j calls it after the pass that computes the
 * field of the owned nodes. */
static inline void peri_sim_exchange(peri_sim *s, double *field, int ncomp) {
  if (s->par.exchange) s->par.exchange(s, field, ncomp);
}

#endif
