/* Expressions in decks: formulas of x, y, z (reference position) and t (time),
 * evaluated with muparser's C API. */
#ifndef PERI_EXPR_H
#define PERI_EXPR_H
#include <stdbool.h>
#include <stddef.h>

typedef struct peri_expr peri_expr;

/* Parses text such as "-100*t + 0.00155" or "200 - 50*((z/0.05)-1)^2".
 * Variables: x y z t; constants: pi, e; muparser's functions (sin, sqrt, abs, min, max,
 * ...) and the ternary "a ? b : c". Returns NULL and writes a one-line reason into
 * err (of size errlen) when the text does not parse or uses another variable. */
peri_expr *peri_expr_parse(const char *text, char *err, size_t errlen);
/* A constant expression (never fails). */
peri_expr *peri_expr_constant(double value);
/* Evaluates; not thread-safe on one expression (muparser binds variables by address). */
double peri_expr_eval(peri_expr *e, double x, double y, double z, double t);
/* True when the expression does not depend on x, y, z or t. */
bool peri_expr_is_constant(const peri_expr *e);
/* True when the expression reads t. */
bool peri_expr_uses_time(const peri_expr *e);
/* The text the expression was parsed from. */
const char *peri_expr_text(const peri_expr *e);
void peri_expr_free(peri_expr *e);

#endif
