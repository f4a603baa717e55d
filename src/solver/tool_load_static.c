/* Load control of rigid tools in the quasi-static solvers (docs/contact.md "Load control"):
 * at each load step the offset q of every load-controlled tool along its direction is found
 * such that the body pushes back with the load, P_contact(q) = P(t), each P_contact taken
 * at equilibrium of the nodes with the tool held at q (the solver's own solve, warm-started
 * from the previous one). Secant steps inside a bracket, bisection where the secant leaves
 * it; before the first contact the tool advances a tenth of a spacing per solve (a solve
 * without contact converges at once). A search opens with the compliance dq/dP of the last
 * secant (the contact's stiffness changes little between load steps and break rounds).
 * Where P_contact(q) jumps across P (a node entering or leaving the tool, a contact node
 * switching between stick and slip) no offset meets the load: once the bracket is narrower
 * than BRACKET_WIDTH spacings the search ends at the bracket's last point, with a warning
 * that gives the jump. */
#include <math.h>
#include "peri/error.h"
#include "peri/quasistatic.h"
#include "peri/tools.h"

/* |P_contact - P| <= this fraction of |P| ends the search: 1e-3, well below the 10% of the
 * comparisons it serves (Hertz, friction) and above what a solve at tolerance 1e-6 resolves. */
#define LOAD_TOLERANCE 1.0e-3
#define MAX_LOAD_SOLVES 100
/* A bracket this narrow (in spacings) is a jump of P_contact, not a slope: 1e-6, the solves'
 * relative tolerance, and some 17 bisections from the tenth of a spacing a search opens with. */
#define BRACKET_WIDTH 1.0e-6

typedef struct {
  double lo, p_lo, hi, p_hi; /* bracket: offsets with P_contact below and above the load */
  bool has_lo, has_hi;
  double q_prev, p_prev;     /* the previous point, for the secant */
  bool has_prev;
  int same_side;             /* points in a row on the same side of the load */
} load_search;

static bool load_controlled(const peri_sim *s) {
  if (!s->tools) return false;
  for (int k = 0; k < s->tools->count; ++k)
    if (s->tools->tool[k].load) return true;
  return false;
}

/* Records the present point (q, P_contact) in the bracket. */
static void bracket_update(load_search *ls, double q, double pc, double P) {
  if (pc < P) {
    if (!ls->has_lo || q > ls->lo) ls->lo = q, ls->p_lo = pc, ls->has_lo = true;
  } else if (!ls->has_hi || q < ls->hi) {
    ls->hi = q, ls->p_hi = pc, ls->has_hi = true;
  }
}

/* Whether the bracket has closed on a jump of P_contact (below `width` in offset). */
static bool bracket_closed(const load_search *ls, double width) {
  return ls->has_lo && ls->has_hi && ls->hi - ls->lo <= width;
}

/* The next offset of one tool from its present point (q, P_contact), already in the bracket,
 * and the load P;
 * *compliance: dq/dP of the last secant between two points in contact (updated here). */
static double next_offset(load_search *ls, double q, double pc, double P, double step_free, double *compliance) {
  double next;
  if (!(pc > 0.0)) next = q + step_free; /* no contact yet: move towards the body */
  else if (ls->has_prev && ls->p_prev > 0.0 && pc != ls->p_prev) {
    /* a secant between two points in contact (one from the last point before the contact
     * would take the first touch's tiny force for a slope and leap far beyond the body) */
    const double slope = (q - ls->q_prev) / (pc - ls->p_prev);
    if (slope > 0.0) *compliance = slope;
    next = q + (P - pc) * slope;
  } else if (*compliance > 0.0) next = q + (P - pc) * *compliance;
  else next = q + (pc < P ? step_free : -step_free);
  /* a secant that keeps landing on one side (a kink or a jump: regula falsi's stagnation)
   * gives way to bisection on the third point in a row */
  ls->same_side = ls->has_prev && (pc < P) == (ls->p_prev < P) ? ls->same_side + 1 : 0;
  if (ls->has_lo && ls->has_hi && (ls->same_side >= 2 || !(next > ls->lo && next < ls->hi)))
    next = 0.5 * (ls->lo + ls->hi);
  else if (ls->has_lo && !(next > ls->lo)) next = ls->lo + step_free;
  else if (ls->has_hi && !(next < ls->hi)) next = ls->hi - step_free;
  ls->q_prev = q, ls->p_prev = pc, ls->has_prev = true;
  return next;
}

peri_qs_status peri_tools_load_equilibrium(peri_sim *s, peri_qs_status (*solve)(peri_sim *)) {
  peri_qs_status st = solve(s);
  if (st != PERI_QS_CONVERGED || !load_controlled(s)) return st;
  peri_tools *tools = s->tools;
  load_search search[tools->count];
  bool held[tools->count]; /* tools whose search ended on a jump: they keep their offset */
  double load[tools->count]; /* P(t) of each load-controlled tool */
  for (int k = 0; k < tools->count; ++k) {
    search[k] = (load_search){0}, held[k] = false;
    const peri_tool *tl = &tools->tool[k];
    load[k] = tl->load ? peri_expr_eval(tl->load, 0.0, 0.0, 0.0, s->state.time) : 0.0;
  }
  const double step_free = 0.1 * s->disc.geom.spacing;
  const double width = BRACKET_WIDTH * s->disc.geom.spacing;
  for (int solves = 1;; ++solves) {
    bool done = true;
    for (int k = 0; k < tools->count; ++k) {
      peri_tool *tl = &tools->tool[k];
      if (!tl->load || held[k]) continue;
      const double P = load[k];
      if (fabs(tl->normal_force - P) <= LOAD_TOLERANCE * fabs(P)) continue;
      bracket_update(&search[k], tl->q, tl->normal_force, P);
      if (bracket_closed(&search[k], width)) {
        held[k] = true;
        peri_warning("load control: the contact force on tool '%s' jumps from %g to %g N within %g m of "
                     "offset at t = %g, across the load %g N; the step goes on with %g N",
                     tl->name, search[k].p_lo, search[k].p_hi, search[k].hi - search[k].lo, s->state.time, P,
                     tl->normal_force);
        continue;
      }
      done = false;
    }
    if (done) return PERI_QS_CONVERGED;
    if (solves >= MAX_LOAD_SOLVES) {
      peri_error("load control: the tools' contact forces do not reach their loads after %d solves at t = %g",
                 MAX_LOAD_SOLVES, s->state.time);
      return PERI_QS_NOT_CONVERGED;
    }
    for (int k = 0; k < tools->count; ++k) {
      peri_tool *tl = &tools->tool[k];
      if (!tl->load || held[k]) continue;
      tl->q = next_offset(&search[k], tl->q, tl->normal_force, load[k], step_free, &tl->load_compliance);
    }
    st = solve(s);
    if (st != PERI_QS_CONVERGED) return st;
  }
}
