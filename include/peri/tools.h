/* Rigid tools (docs/contact.md "Rigid tools", MODELS.md 17.2): sphere, cone-sphere,
 * cylinder, flat punch and plane, moved by expressions of t or, along their direction, by a
 * load (load control); a penalty force on the nodes inside them, the LAMMPS fix indent law
 * k pen^2 along the outward normal, or the kinematic contact of Madenci and Oterkus (the
 * momentum that puts a node back on the surface in one step), and friction: Coulomb's mu
 * and an interfacial shear strength tau0 (Bowden and Tabor: F_t = tau0 A + mu P). */
#ifndef PERI_TOOLS_H
#define PERI_TOOLS_H
#include <stdbool.h>
#include <stdint.h>
#include "peri/expr.h"

struct peri_sim;

typedef enum {
  PERI_TOOL_SPHERE = 0,
  PERI_TOOL_CONE_SPHERE = 1, /* conospherical tip: a cone of half-angle alpha ending in a sphere of radius R */
  PERI_TOOL_CYLINDER = 2,    /* infinite cylinder of radius R about `axis` */
  PERI_TOOL_FLAT_PUNCH = 3,  /* cylinder of radius R along `direction`, flat face at the position */
  PERI_TOOL_PLANE = 4,       /* half-space behind the plane through the position, facing -direction */
} peri_tool_shape;

/* The geometry of one tool relative to its position (the reference point that moves). */
typedef struct peri_tool_geometry {
  peri_tool_shape shape;
  double radius;             /* R: sphere, tip sphere, cylinder, punch */
  double half_angle;         /* cone-sphere: alpha (rad), measured from the axis */
  double direction[3];       /* unit: the way the tool presses (its tip points this way) */
  double axis[3];            /* unit: the cylinder's axis */
} peri_tool_geometry;

/* Penetration of the point y into the tool at `position` (> 0 inside, the distance to leave
 * it by the shortest way) and the unit normal n along which the point leaves. Returns the
 * penetration; n is set only where it is positive. */
double peri_tool_penetration(const peri_tool_geometry *g, const double position[3], const double y[3], double n[3]);
/* Whether the point y may be inside the tool at `position`: false only where
 * peri_tool_penetration gives no penetration (from the same differences, the point beyond the
 * sphere's, cylinder's or punch's radius or in front of the punch's face by a margin of 1e-12
 * of the radius, without a square root), so that a loop over every node calls it for the few
 * near the tool. */
static inline bool peri_tool_may_touch(const peri_tool_geometry *g, const double position[3], const double y[3]) {
  double w[3];
  for (int d = 0; d < 3; ++d) w[d] = y[d] - position[d];
  const double beyond = g->radius * g->radius * (1.0 + 1e-12);
  switch (g->shape) {
  case PERI_TOOL_SPHERE: return w[0] * w[0] + w[1] * w[1] + w[2] * w[2] <= beyond;
  case PERI_TOOL_CYLINDER:
  case PERI_TOOL_FLAT_PUNCH: {
    const double *a = g->shape == PERI_TOOL_CYLINDER ? g->axis : g->direction;
    const double along = w[0] * a[0] + w[1] * a[1] + w[2] * a[2];
    if (g->shape == PERI_TOOL_FLAT_PUNCH && along > 1e-12 * g->radius) return false; /* in front of the face */
    double rho2 = 0.0;
    for (int d = 0; d < 3; ++d) rho2 += (w[d] - along * a[d]) * (w[d] - along * a[d]);
    return rho2 <= beyond;
  }
  default: return true;
  }
}

typedef struct peri_tool {
  char *name;
  peri_tool_geometry geom;
  double stiffness;          /* k (N/m^5): force density k pen^2 (penalty contact) */
  bool kinematic;            /* kinematic contact: force density rho pen / dt^2 instead */
  double friction;           /* Coulomb coefficient mu */
  double shear_strength;     /* tau0 (Pa): a sliding contact node's face, V / dx, is sheared by tau0 */
  peri_expr *position[3];    /* reference point at t (NULL component: 0) */
  /* load control of the position along `direction` (NULL: the position is prescribed) */
  peri_expr *load;           /* normal load P(t) (N) pushing the tool along `direction` */
  double mass, damping;      /* the tool's own equation M q'' = P - P_contact - M c q' */
  double q, q_rate;          /* offset along `direction` and its rate, integrated in the run */
  double load_compliance;    /* dq/dP of the quasi-static load search's last secant (0: none yet) */
  /* state of the last evaluation */
  double at[3], velocity[3]; /* position and velocity */
  double force[3];           /* total force of the nodes on the tool */
  double normal_force;       /* P_contact = -force . direction */
  double tangential_force;   /* |force - (force . direction) direction| */
  double contact_area;       /* A: the faces V / dx of the nodes in contact, summed */
  double sliding;            /* path length of the position across `direction` since t = 0 */
  double last_t;             /* latest time evaluated, for the sliding distance */
  double last_at[3];         /* position at last_t */
  double start[3];           /* position at the first evaluation (t = 0): where the scratch starts */
  double contact_at[3];      /* position at the first evaluation with a contact force */
  bool touched;              /* whether the tool has touched the body yet */
  bool started;
  double *block_force;       /* per-block sums (4 per block: force, contact area) */
  int64_t blocks;
} peri_tool;

typedef struct peri_tools {
  int count;
  peri_tool *tool;
} peri_tools;

void peri_tools_free(peri_tools *t);

#endif
