/* Deck expressions on top of muparser's C API.
 *
 * muparser reads variables through pointers, so each expression owns its x y z t and
 * binds them once at parse time. Expressions that use none of them are evaluated once
 * and their muparser handle is released: evaluating a constant is then free and
 * thread-safe. */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <muParserDLL.h>
#include "peri/error.h"
#include "peri/expr.h"

struct peri_expr {
  char *text;
  bool constant;
  bool uses_time;          /* t is one of its variables */
  double value;            /* the cached value when constant */
  muParserHandle_t parser; /* NULL when constant */
  double x, y, z, t;       /* muparser reads these by address */
};

static const char *const variable_names[] = {"x", "y", "z", "t"};
enum { VARIABLE_COUNT = 4 };

static void set_error(char *err, size_t errlen, const char *fmt, const char *arg) {
  if (err && errlen) snprintf(err, errlen, fmt, arg);
}

/* muparser messages read "Unexpected token ... at position 2."; fit them into our
 * "reason" style: lower-case start, no final period. */
static void set_parser_error(char *err, size_t errlen, const char *message) {
  if (!err || !errlen) return;
  snprintf(err, errlen, "%s", message ? message : "invalid expression");
  if (isupper((unsigned char)err[0]) && !(err[1] && isupper((unsigned char)err[1])))
    err[0] = (char)tolower((unsigned char)err[0]);
  size_t n = strlen(err);
  if (n && err[n - 1] == '.') err[n - 1] = '\0';
}

static bool is_allowed_variable(const char *name) {
  for (int i = 0; i < VARIABLE_COUNT; i++)
    if (strcmp(name, variable_names[i]) == 0) return true;
  return false;
}

/* muparser accepts "x = 3" as an assignment to a variable; in a deck that is always a
 * typo for "==", and it would silently change the evaluation point. */
static bool has_assignment(const char *text) {
  for (const char *p = text; *p; p++) {
    if (*p != '=') continue;
    bool part_of_comparison = (p > text && strchr("<>!=", p[-1])) || p[1] == '=';
    if (!part_of_comparison) return true;
  }
  return false;
}

peri_expr *peri_expr_constant(double value) {
  peri_expr *e = peri_calloc(1, sizeof *e);
  char text[32];
  snprintf(text, sizeof text, "%.17g", value);
  e->text = peri_strdup(text);
  e->constant = true;
  e->value = value;
  return e;
}

peri_expr *peri_expr_parse(const char *text, char *err, size_t errlen) {
  if (!text) {
    set_error(err, errlen, "%s", "expression is empty");
    return NULL;
  }
  if (has_assignment(text)) {
    set_error(err, errlen, "%s", "assignment '=' is not allowed (use '==' to compare)");
    return NULL;
  }
  peri_expr *e = peri_calloc(1, sizeof *e);
  e->text = peri_strdup(text);
  e->parser = mupCreate(muBASETYPE_FLOAT);
  if (!e->parser) {
    set_error(err, errlen, "%s", "cannot create an expression parser");
    peri_expr_free(e);
    return NULL;
  }
  mupDefineVar(e->parser, "x", &e->x);
  mupDefineVar(e->parser, "y", &e->y);
  mupDefineVar(e->parser, "z", &e->z);
  mupDefineVar(e->parser, "t", &e->t);
  /* muparser names them _pi and _e; decks use the usual names. */
  mupDefineConst(e->parser, "pi", 3.14159265358979323846);
  mupDefineConst(e->parser, "e", 2.71828182845904523536);
  mupSetExpr(e->parser, text);

  /* Listing the used variables tolerates undefined ones (their pointer is NULL), which
   * lets us name the offending variable. When listing itself fails the expression is
   * malformed, and the evaluation below gives the better message. */
  int used_count = mupGetExprVarNum(e->parser);
  if (!mupError(e->parser)) {
    for (int i = 0; i < used_count; i++) {
      const char *name = NULL;
      double *address = NULL;
      mupGetExprVar(e->parser, (unsigned)i, &name, &address);
      if (name && !is_allowed_variable(name)) {
        set_error(err, errlen, "unknown variable '%s' (allowed: x, y, z, t)", name);
        peri_expr_free(e);
        return NULL;
      }
      if (name && !strcmp(name, "t")) e->uses_time = true;
    }
  } else {
    used_count = -1; /* unknown until the expression parses */
  }

  /* muparser parses on first evaluation; this is where syntax errors surface. */
  double first_value = mupEval(e->parser);
  if (mupError(e->parser)) {
    set_parser_error(err, errlen, mupGetErrorMsg(e->parser));
    peri_expr_free(e);
    return NULL;
  }
  /* "1, 2" is a valid muparser expression with two results; mupEval returns the last. */
  int result_count = 0;
  mupEvalMulti(e->parser, &result_count);
  if (result_count != 1) {
    set_error(err, errlen, "%s", "expected a single value, got a comma-separated list");
    peri_expr_free(e);
    return NULL;
  }
  if (used_count < 0) used_count = mupGetExprVarNum(e->parser);

  if (used_count == 0 && !isfinite(first_value)) {
    set_error(err, errlen, "%s", isnan(first_value) ? "the value is not a number (nan)" : "the value is infinite");
    peri_expr_free(e);
    return NULL;
  }
  if (used_count == 0) {
    e->constant = true;
    e->value = first_value;
    mupRelease(e->parser);
    e->parser = NULL;
  }
  return e;
}

double peri_expr_eval(peri_expr *e, double x, double y, double z, double t) {
  if (e->constant) return e->value;
  e->x = x;
  e->y = y;
  e->z = z;
  e->t = t;
  return mupEval(e->parser);
}

bool peri_expr_is_constant(const peri_expr *e) { return e->constant; }

bool peri_expr_uses_time(const peri_expr *e) { return e->uses_time; }

const char *peri_expr_text(const peri_expr *e) { return e->text; }

void peri_expr_free(peri_expr *e) {
  if (!e) return;
  if (e->parser) mupRelease(e->parser);
  free(e->text);
  free(e);
}
