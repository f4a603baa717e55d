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
  int region;                   /* index in sim->regions */
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
} peri_indenter;

typedef struct peri_precrack {
  int dim;                      /* 2: segment a-b; 3: rectangle corner a, edges e1, e2 */
  double a[3], b[3], e1[3], e2[3];
} peri_precrack;

typedef enum { PERI_SOLVER_EXPLICIT = 0 } peri_solver_kind;

typedef struct peri_output {
  char *directory;
  char *basename;               /* deck file name without extension */
  long every;                   /* steps between frames (0: first and last only) */
  int n_fields;
  char **fields;                /* names of fields to write */
  bool compress;
  long history_every;
  bool picture;                 /* PNG at the end (2D) */
  char *picture_field;
  int picture_width;
} peri_output;

typedef struct peri_sim {
  char *deck_path;
  peri_geometry geom;
  peri_particles p;
  peri_bonds bonds;
  peri_family_params family;
  bool analytic_weighted_volume; /* LPS: m from the full-horizon integral (else discrete) */
  const peri_model_ops *model;
  int n_materials;
  peri_material *materials;
  double *pair_s0;              /* [n_materials^2] critical stretch of a bond by end materials */
  double *s0_node;              /* LAMMPS form: s0 of each node for this step (else NULL) */
  int n_regions;
  peri_region *regions;
  int n_bcs;
  peri_bc *bcs;
  int n_precracks;
  peri_precrack *precracks;
  peri_indenter indenter;
  /* solver */
  peri_solver_kind solver;
  double dt;                    /* time step in use */
  double dt_given;              /* 0: estimate */
  double safety_factor;
  long steps;                   /* number of steps (derived from end_time if given) */
  double end_time;
  double damping;               /* viscous damping coefficient (1/s), 0 = none */
  bool breaking;                /* bonds may break */
  /* state */
  double time;
  long step;
  uint8_t *prescribed;          /* [3n] component has a prescribed displacement/velocity */
  double external_work;
  /* output */
  peri_output out;
  bool quiet;
  int threads;
} peri_sim;

/* Reads the deck and builds the simulation: every input error is reported (exit status 2)
 * before any work. `overrides` are "--output DIR" etc. applied after parsing. */
int peri_sim_from_deck(peri_sim *s, const char *path);
void peri_sim_free(peri_sim *s);

#endif
