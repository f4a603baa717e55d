/* The pair list of short-range contact (include/peri/contact_list.h) against a search of
 * every pair: the build lists exactly the pairs within d_ij + skin; the pruned list holds
 * every pair in contact as long as no node has moved half the prune skin since the prune,
 * and the list says when it needs a prune or a build. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/contact_list.h"

enum { SIDE = 9, N = SIDE * SIDE * SIDE };

static const peri_contact_reach REACH = {0.9, 1.35, 0.3}; /* the LAMMPS form on a unit lattice */
static const double PRUNE_SKIN = 0.08;

static double x[3 * N], u[3 * N], y[3 * N];

/* uniform in [-1, 1), reproducible */
static double uniform(unsigned *state) {
  *state = *state * 1103515245u + 12345u;
  return ((*state >> 8) & 0xffffff) / (double)0x800000 - 1.0;
}

static double reach_of(int32_t i, int32_t j) {
  double r02 = 0.0;
  for (int a = 0; a < 3; ++a) r02 += (x[3 * i + a] - x[3 * j + a]) * (x[3 * i + a] - x[3 * j + a]);
  return fmin(REACH.ratio * sqrt(r02), REACH.max_reach);
}

static double distance(int32_t i, int32_t j) {
  double r2 = 0.0;
  for (int a = 0; a < 3; ++a) r2 += (y[3 * i + a] - y[3 * j + a]) * (y[3 * i + a] - y[3 * j + a]);
  return sqrt(r2);
}

/* Moves every node by a random vector of length below `most` (none longer). */
static void move(unsigned *state, double most) {
  for (int32_t i = 0; i < N; ++i) {
    double v[3], len = 0.0;
    for (int a = 0; a < 3; ++a) {
      v[a] = uniform(state);
      len += v[a] * v[a];
    }
    const double scale = most * 0.999 * fabs(uniform(state)) / (sqrt(len) + 1e-300);
    for (int a = 0; a < 3; ++a) u[3 * i + a] += scale * v[a];
  }
}

static bool listed(const int32_t *partner, int64_t from, int64_t to, int32_t j) {
  for (int64_t k = from; k < to; ++k)
    if (partner[k] == j) return true;
  return false;
}

/* Every pair in contact (closer than d_ij) is in row i of the pruned list, which is in index
 * order and a part of the built row. */
static void expect_pruned_complete(const peri_contact_list *l) {
  long in_contact = 0;
  for (int32_t i = 0; i < N; ++i) {
    const int64_t from = l->offset[i], end = l->pruned_end[i];
    cr_assert(from <= end && end <= l->offset[i + 1], "row %d: pruned end outside its range", i);
    for (int64_t k = from + 1; k < end; ++k) cr_assert_lt(l->pruned_partner[k - 1], l->pruned_partner[k], "row %d order", i);
    for (int64_t k = from; k < end; ++k) {
      cr_assert(listed(l->partner, from, l->offset[i + 1], l->pruned_partner[k]), "row %d: pruned partner not built", i);
      cr_assert_eq(l->pruned_reach[k], reach_of(i, l->pruned_partner[k]), "row %d: reach", i);
    }
    for (int32_t j = 0; j < N; ++j)
      if (j != i && distance(i, j) < reach_of(i, j)) {
        ++in_contact;
        cr_assert(listed(l->pruned_partner, from, end, j), "pair (%d, %d) in contact (r/d = %g) missing from the pruned list",
                  i, j, distance(i, j) / reach_of(i, j));
      }
  }
  cr_assert_gt(in_contact, 0, "the test should bring some pairs into contact");
}

static peri_contact_list_need needs(const peri_contact_list *l) {
  return peri_contact_list_needs(l, x, u, N, REACH.skin, PRUNE_SKIN, y);
}

Test(contact_list, build_and_prune_against_every_pair) {
  unsigned state = 12345u;
  for (int32_t k = 0, i = 0; i < SIDE; ++i)
    for (int32_t j = 0; j < SIDE; ++j)
      for (int32_t m = 0; m < SIDE; ++m, ++k) {
        x[3 * k] = m + 0.05 * uniform(&state);
        x[3 * k + 1] = j + 0.05 * uniform(&state);
        x[3 * k + 2] = i + 0.05 * uniform(&state);
      }
  memset(u, 0, sizeof u);
  move(&state, 0.25); /* some nearest neighbours compressed past 0.9 of their distance */
  peri_contact_list l;
  memset(&l, 0, sizeof l);
  cr_assert_eq(needs(&l), PERI_CONTACT_LIST_BUILD, "a list never built needs a build");
  for (int32_t k = 0; k < 3 * N; ++k) cr_assert_eq(y[k], x[k] + u[k], "deformed position %d", k);
  peri_contact_list_build(&l, x, y, N, 0, N, u, &REACH);
  /* the build: exactly the pairs within d_ij + skin, in index order */
  for (int32_t i = 0; i < N; ++i) {
    int64_t k = l.offset[i];
    for (int32_t j = 0; j < N; ++j) {
      if (j == i || !(distance(i, j) < reach_of(i, j) + REACH.skin)) continue;
      cr_assert(k < l.offset[i + 1] && l.partner[k] == j, "row %d: pair with %d not built (or out of order)", i, j);
      ++k;
    }
    cr_assert_eq(k, l.offset[i + 1], "row %d: %ld pairs built beyond d + skin", i, (long)(l.offset[i + 1] - k));
  }
  peri_contact_list_prune(&l, y, 0, u, PRUNE_SKIN);
  long pruned = 0;
  for (int32_t i = 0; i < N; ++i) pruned += (long)(l.pruned_end[i] - l.offset[i]);
  cr_assert_lt(pruned, l.offset[N], "the prune should drop pairs (%ld of %ld kept)", pruned, (long)l.offset[N]);
  expect_pruned_complete(&l);

  /* a step below half the prune skin: nothing to do, and the pruned list still holds every
   * pair in contact */
  move(&state, 0.5 * PRUNE_SKIN);
  cr_assert_eq(needs(&l), PERI_CONTACT_LIST_FRESH, "nodes moved less than half the prune skin");
  expect_pruned_complete(&l);

  /* beyond half the prune skin (from the prune), within half the skin (from the build) */
  u[3 * 100] += PRUNE_SKIN; /* whatever its earlier step, now more than half the prune skin away */
  cr_assert_eq(needs(&l), PERI_CONTACT_LIST_PRUNE, "node 100 moved more than half the prune skin since the prune");
  peri_contact_list_prune(&l, y, 0, u, PRUNE_SKIN);
  cr_assert_eq(needs(&l), PERI_CONTACT_LIST_FRESH, "just pruned");
  expect_pruned_complete(&l);

  /* beyond half the skin since the build */
  u[3 * 200 + 1] += REACH.skin;
  cr_assert_eq(needs(&l), PERI_CONTACT_LIST_BUILD, "node 200 moved more than half the skin since the build");
  peri_contact_list_free(&l);
}
