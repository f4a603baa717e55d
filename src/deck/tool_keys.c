/* The tools section of the deck (docs/deck.md section 23, docs/contact.md "Rigid tools"):
 * rigid tools of five shapes, their motion by expressions of t or by a load along their
 * direction, their penalty stiffness and friction coefficient. */
#include <math.h>
#include <string.h>
#include "peri/error.h"
#include "peri/tools.h"
#include "setup_parts.h"

#define TRY(x) do { int rc_ = (x); if (rc_ != PERI_OK) return rc_; } while (0)

/* A node of the body may start at most this deep in a tool, in node spacings: the half
 * cell of the node itself. Deeper, the first step would throw it out with a force of
 * k pen^2, which is a deck error, not contact. */
#define START_DEPTH_SPACINGS 0.5

static const char *const shapes[] = {"sphere", "cone_sphere", "cylinder", "flat_punch", "plane", NULL};

/* A unit vector of the dimension's components from key `key` (a zero vector is an error). */
static int unit_vector(const peri_node *map, const char *key, int dim, double out[3]) {
  double v[3] = {0.0, 0.0, 0.0};
  TRY(peri_deck_vector(map, key, true, dim, v));
  const double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (!(len > 0.0) || !isfinite(len))
    return peri_deck_error(peri_deck_get(map, key), "key '%s': expected a nonzero direction", key);
  for (int d = 0; d < 3; ++d) out[d] = v[d] / len;
  return PERI_OK;
}

static int parse_load(peri_sim *s, const peri_node *it, peri_tool *tl) {
  const peri_node *load = peri_deck_get(it, "load");
  if (!load) return PERI_OK;
  static const char *const keys[] = {"value", "mass", "damping", "velocity", NULL};
  TRY(peri_deck_allow(load, "tools.load", keys));
  TRY(peri_deck_expr(load, "value", true, &tl->load));
  TRY(peri_deck_double(load, "mass", true, &tl->mass));
  TRY(peri_deck_double(load, "damping", false, &tl->damping));
  /* the rate of the offset at t = 0: a free rigid impactor is {value: 0, mass, velocity} */
  TRY(peri_deck_double(load, "velocity", false, &tl->q_rate));
  if (!isfinite(tl->q_rate))
    return peri_deck_error(peri_deck_get(load, "velocity"), "key 'velocity': must be a finite speed (m/s)");
  if (!(tl->mass > 0.0) || !isfinite(tl->mass))
    return peri_deck_error(peri_deck_get(load, "mass"), "key 'mass': the tool's mass must be positive (kg)");
  if (!(tl->damping >= 0.0) || !isfinite(tl->damping))
    return peri_deck_error(peri_deck_get(load, "damping"), "key 'damping': must be zero or positive (1/s)");
  if (s->solver.kind != PERI_SOLVER_EXPLICIT && s->solver.kind != PERI_SOLVER_ADR &&
      s->solver.kind != PERI_SOLVER_DYNAMIC_RELAXATION && s->solver.kind != PERI_SOLVER_NLCG)
    return peri_deck_error(load, "tool '%s': load control runs with solver.type explicit, adr, dynamic_relaxation or "
                                 "nlcg; prescribe the position for another solver",
                           tl->name);
  if (s->solver.kind != PERI_SOLVER_EXPLICIT && tl->q_rate != 0.0)
    return peri_deck_error(peri_deck_get(load, "velocity"), "tool '%s': key 'velocity': a quasi-static run has no "
                                                            "speed; only with solver.type explicit", tl->name);
  /* the degree of freedom under load must be free: no prescribed motion along `direction` */
  const peri_node *pos = peri_deck_get(it, "position");
  for (int d = 0; d < s->disc.geom.dim; ++d)
    if (tl->geom.direction[d] != 0.0 && tl->position[d] && !peri_expr_is_constant(tl->position[d]))
      return peri_deck_error(pos->items[d], "tool '%s': load control needs its degree of freedom along direction "
                                            "free, but position component %c is an expression of t; give it as a "
                                            "number (the start) or drop the load",
                             tl->name, "xyz"[d]);
  return PERI_OK;
}

static int parse_tool(peri_sim *s, const peri_node *it, peri_tool *tl) {
  static const char *const keys[] = {"name", "shape", "radius", "half_angle", "direction", "axis",
                                     "position", "stiffness", "friction", "shear_strength", "load", "contact", NULL};
  TRY(peri_deck_allow(it, "tools", keys));
  const char *name = NULL;
  TRY(peri_deck_string(it, "name", true, &name));
  tl->name = peri_strdup(name);
  int shape = 0;
  TRY(peri_deck_choice(it, "shape", true, shapes, &shape));
  peri_tool_geometry *g = &tl->geom;
  g->shape = (peri_tool_shape)shape;
  const int dim = s->disc.geom.dim;
  TRY(unit_vector(it, "direction", dim, g->direction));
  if (g->shape != PERI_TOOL_PLANE) {
    TRY(peri_deck_double(it, "radius", true, &g->radius));
    if (!(g->radius > 0.0) || !isfinite(g->radius))
      return peri_deck_error(peri_deck_get(it, "radius"), "key 'radius': must be a positive length (m)");
  } else if (peri_deck_get(it, "radius")) {
    return peri_deck_error(peri_deck_key_node(it, "radius"), "key 'radius': a plane has none");
  }
  if (g->shape == PERI_TOOL_CONE_SPHERE) {
    double deg = NAN;
    TRY(peri_deck_double(it, "half_angle", true, &deg));
    if (!(deg > 0.0 && deg < 90.0))
      return peri_deck_error(peri_deck_get(it, "half_angle"), "key 'half_angle': degrees between 0 and 90, exclusive");
    g->half_angle = deg * M_PI / 180.0;
  } else if (peri_deck_get(it, "half_angle")) {
    return peri_deck_error(peri_deck_key_node(it, "half_angle"), "key 'half_angle': only for shape cone_sphere");
  }
  if (g->shape == PERI_TOOL_CYLINDER) TRY(unit_vector(it, "axis", dim, g->axis));
  else if (peri_deck_get(it, "axis"))
    return peri_deck_error(peri_deck_key_node(it, "axis"), "key 'axis': only for shape cylinder");
  const peri_node *pos = peri_deck_get(it, "position");
  if (!pos) return peri_deck_error(it, "missing key 'position' in tools");
  if (pos->kind != PERI_NODE_SEQUENCE || pos->count != dim)
    return peri_deck_error(pos, "key 'position': expected a list of %d numbers or expressions of t", dim);
  for (int d = 0; d < dim; ++d) TRY(peri_deck_node_expr(pos->items[d], "position", &tl->position[d]));
  static const char *const contact_laws[] = {"penalty", "kinematic", NULL};
  int law = 0;
  TRY(peri_deck_choice(it, "contact", false, contact_laws, &law));
  tl->kinematic = law == 1;
  if (tl->kinematic) {
    if (peri_deck_get(it, "stiffness"))
      return peri_deck_error(peri_deck_key_node(it, "stiffness"), "key 'stiffness': only for contact: penalty (kinematic "
                                                                  "contact takes its stiffness from the density and the time step)");
    if (s->solver.kind != PERI_SOLVER_EXPLICIT)
      return peri_deck_error(peri_deck_get(it, "contact"), "tool '%s': kinematic contact runs with solver.type explicit "
                                                           "(it is the momentum of one time step); use contact: penalty",
                             tl->name);
  } else {
    TRY(peri_deck_double(it, "stiffness", true, &tl->stiffness));
    if (!(tl->stiffness > 0.0) || !isfinite(tl->stiffness))
      return peri_deck_error(peri_deck_get(it, "stiffness"), "key 'stiffness': must be positive (N/m^5)");
  }
  TRY(peri_deck_double(it, "friction", false, &tl->friction));
  if (!(tl->friction >= 0.0) || !isfinite(tl->friction))
    return peri_deck_error(peri_deck_get(it, "friction"), "key 'friction': the Coulomb coefficient must be zero or positive");
  TRY(peri_deck_double(it, "shear_strength", false, &tl->shear_strength));
  if (!(tl->shear_strength >= 0.0) || !isfinite(tl->shear_strength))
    return peri_deck_error(peri_deck_get(it, "shear_strength"),
                           "key 'shear_strength': the interfacial shear strength must be zero or positive (Pa)");
  return parse_load(s, it, tl);
}

/* A node deeper than half a spacing inside a tool at t = 0 is a deck error (exit 2). */
static int check_start(const peri_sim *s, const peri_node *it, const peri_tool *tl) {
  const peri_particles *p = &s->disc.p;
  double at[3];
  for (int d = 0; d < 3; ++d) at[d] = tl->position[d] ? peri_expr_eval(tl->position[d], 0.0, 0.0, 0.0, 0.0) : 0.0;
  const double limit = START_DEPTH_SPACINGS * s->disc.geom.spacing;
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double y[3], n[3];
    for (int d = 0; d < 3; ++d) y[d] = p->x[3 * (size_t)i + d] + p->u[3 * (size_t)i + d];
    const double pen = peri_tool_penetration(&tl->geom, at, y, n);
    if (pen > limit)
      return peri_deck_error(peri_deck_get(it, "position"), "tool '%s' is inside the body at t = 0: the node at (%g, %g, %g) is %g m deep, more "
                                 "than the contact distance of half a spacing (%g m); move the tool's position out",
                             tl->name, y[0], y[1], y[2], pen, limit);
  }
  return PERI_OK;
}

int peri_setup_tools(peri_sim *s, const peri_node *root) {
  const peri_node *list = peri_deck_get(root, "tools");
  if (!list) return PERI_OK;
  if (list->kind != PERI_NODE_SEQUENCE || list->count < 1)
    return peri_deck_error(list, "key 'tools': expected a list of tools, got %s", peri_deck_kind_name(list));
  if (s->solver.kind == PERI_SOLVER_IMPLICIT || s->solver.kind == PERI_SOLVER_HEAT)
    return peri_deck_error(list, "key 'tools': not with solver.type %s (%s)",
                           s->solver.kind == PERI_SOLVER_HEAT ? "heat" : "implicit",
                           s->solver.kind == PERI_SOLVER_HEAT ? "a heat run has no forces" : "no tangent of the tools");
  peri_tools *tools = peri_calloc(1, sizeof *tools);
  tools->tool = peri_calloc((size_t)list->count, sizeof(peri_tool));
  s->tools = tools;
  for (int k = 0; k < list->count; ++k) {
    const peri_node *it = list->items[k];
    tools->count = k + 1; /* freed with the simulation, also on an error */
    TRY(parse_tool(s, it, &tools->tool[k]));
    for (int j = 0; j < k; ++j)
      if (!strcmp(tools->tool[j].name, tools->tool[k].name))
        return peri_deck_error(peri_deck_get(it, "name"), "tools: two tools are named '%s'", tools->tool[k].name);
    TRY(check_start(s, it, &tools->tool[k]));
  }
  return PERI_OK;
}
