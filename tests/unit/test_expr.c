/* Deck expressions: values, constant detection, and the reasons given for bad input. */
#include <criterion/criterion.h>
#include <math.h>
#include "peri/expr.h"

static peri_expr *parse_ok(const char *text) {
  char err[256] = "";
  peri_expr *e = peri_expr_parse(text, err, sizeof err);
  cr_assert_not_null(e, "'%s' should parse, got: %s", text, err);
  return e;
}

/* Parses text that must fail and checks the one-line reason. */
static void expect_reason(const char *text, const char *reason) {
  char err[256] = "";
  peri_expr *e = peri_expr_parse(text, err, sizeof err);
  cr_assert_null(e, "'%s' should not parse", text);
  cr_assert_str_eq(err, reason);
}

Test(expr, parabola_in_z) {
  peri_expr *e = parse_ok("200 - 50*((z/0.05)-1)^2");
  cr_assert_float_eq(peri_expr_eval(e, 0, 0, 0.025, 0), 187.5, 1e-12);
  cr_assert_float_eq(peri_expr_eval(e, 0, 0, 0.05, 0), 200.0, 1e-12);
  cr_assert_float_eq(peri_expr_eval(e, 1, 2, 0.0, 3), 150.0, 1e-12);
  cr_assert_not(peri_expr_is_constant(e));
  cr_assert_str_eq(peri_expr_text(e), "200 - 50*((z/0.05)-1)^2");
  peri_expr_free(e);
}

Test(expr, ramp_in_t) {
  peri_expr *e = parse_ok("-100*t + 0.00155");
  cr_assert_float_eq(peri_expr_eval(e, 0, 0, 0, 1e-5), 0.00055, 1e-15);
  cr_assert_not(peri_expr_is_constant(e));
  peri_expr_free(e);
}

Test(expr, each_variable_is_bound) {
  peri_expr *e = parse_ok("x + 10*y + 100*z + 1000*t");
  cr_assert_float_eq(peri_expr_eval(e, 1, 2, 3, 4), 4321.0, 1e-12);
  cr_assert_float_eq(peri_expr_eval(e, 4, 3, 2, 1), 1234.0, 1e-12);
  peri_expr_free(e);
}

Test(expr, constant_detected_and_cached) {
  peri_expr *e = parse_ok("2*pi + sqrt(16) - e");
  cr_assert(peri_expr_is_constant(e));
  double expected = 2 * 3.14159265358979323846 + 4 - 2.71828182845904523536;
  cr_assert_float_eq(peri_expr_eval(e, 0, 0, 0, 0), expected, 1e-12);
  cr_assert_float_eq(peri_expr_eval(e, 9, 9, 9, 9), expected, 1e-12);
  cr_assert_str_eq(peri_expr_text(e), "2*pi + sqrt(16) - e");
  peri_expr_free(e);
}

Test(expr, functions_and_ternary) {
  peri_expr *e = parse_ok("x > 0 ? min(x, 2) : abs(x)");
  cr_assert_float_eq(peri_expr_eval(e, 5, 0, 0, 0), 2.0, 1e-12);
  cr_assert_float_eq(peri_expr_eval(e, 1.5, 0, 0, 0), 1.5, 1e-12);
  cr_assert_float_eq(peri_expr_eval(e, -3, 0, 0, 0), 3.0, 1e-12);
  peri_expr_free(e);
  e = parse_ok("sin(pi/2) * max(1, 3) + 1e-3");
  cr_assert(peri_expr_is_constant(e));
  cr_assert_float_eq(peri_expr_eval(e, 0, 0, 0, 0), 3.001, 1e-12);
  peri_expr_free(e);
}

Test(expr, comparison_operators_are_not_assignment) {
  peri_expr *e = parse_ok("(x <= 1) + (x >= 1) + (x == 1) + (x != 1)");
  cr_assert_float_eq(peri_expr_eval(e, 1, 0, 0, 0), 3.0, 1e-12);
  peri_expr_free(e);
}

Test(expr, constant_without_parser) {
  peri_expr *e = peri_expr_constant(2.5e9);
  cr_assert(peri_expr_is_constant(e));
  cr_assert_float_eq(peri_expr_eval(e, 1, 2, 3, 4), 2.5e9, 1e-3);
  cr_assert_str_eq(peri_expr_text(e), "2500000000");
  peri_expr_free(e);
}

Test(expr, unknown_variable_rejected) {
  expect_reason("2*q", "unknown variable 'q' (allowed: x, y, z, t)");
  expect_reason("X + 1", "unknown variable 'X' (allowed: x, y, z, t)");
  expect_reason("x + time", "unknown variable 'time' (allowed: x, y, z, t)");
}

Test(expr, bad_syntax_rejected) {
  expect_reason("2*", "unexpected end of expression at position 3");
  expect_reason("sin(x", "missing parenthesis");
  expect_reason("3 4", "unexpected value \"4\" found at position 2");
  expect_reason("", "expression is empty");
  expect_reason("   ", "expression is empty");
}

Test(expr, unknown_function_rejected) {
  expect_reason("foo(2)", "unexpected token \"foo\" found at position 0");
}

Test(expr, assignment_rejected) {
  expect_reason("x = 3", "assignment '=' is not allowed (use '==' to compare)");
}

Test(expr, several_values_rejected) {
  expect_reason("1, 2", "expected a single value, got a comma-separated list");
}

Test(expr, error_buffer_optional) {
  cr_assert_null(peri_expr_parse("2*q", NULL, 0));
  char tiny[8];
  cr_assert_null(peri_expr_parse("2*q", tiny, sizeof tiny));
  cr_assert_str_eq(tiny, "unknown");
}

Test(expr, free_null_is_harmless) { peri_expr_free(NULL); }

/* A constant that is not finite is bad input, reported at parse time. */
Test(expr, non_finite_constant_rejected) {
  char err[256] = "";
  cr_expect_null(peri_expr_parse("1/0", err, sizeof err));
  cr_expect(strstr(err, "infinite") != NULL, "message: %s", err);
  cr_expect_null(peri_expr_parse("sqrt(-1)", err, sizeof err));
  cr_expect(strstr(err, "not a number") != NULL, "message: %s", err);
}
