/* The eight-lane lengths of the bond kernels (src/model/bond_kernel.h, peri_root_v8) against
 * the correctly rounded square root, and the cache-line allocation the per-bond state uses
 * (include/peri/error.h). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include "model/bond_kernel.h"
#include "peri/error.h"

/* The bound, from the construction: y0 has relative error |e|/2 < 2^-15 and one third-order
 * step leaves 35e^4/128 < 2^-57; what remains is rounding, in units u = 2^-53 of the
 * result: the product x y0 (u, entering sqrt(x) whole and 1/sqrt(x) through e at half
 * weight), e itself (u), the correction term (u |e|, negligible) and the final fused
 * multiply-add (u). So |error| <= 2.1 u relative for sqrt(x), 1.6 u for 1/sqrt(x); asserted
 * at 2.5 u for both. Builds that take the hardware way (PERI_ROOT_HARDWARE, bond_kernel.h) are
 * inside it by construction: the square root correctly rounded (0.5 u), 1/sqrt(x) one rounded
 * division of it (about 1 u). */
#define UNIT_ROUNDOFF 0x1p-53
#define BOUND (2.5 * UNIT_ROUNDOFF)

Test(bond_lengths, root_and_reciprocal_within_round_off) {
#ifndef PERI_BOND_V8
  cr_skip_test("this build has no eight-lane kernels");
#else
  srand(2026);
  double worst_root = 0.0, worst_inv = 0.0;
  for (int trial = 0; trial < 200000; ++trial) {
    double x[8], root[8], inv[8];
    /* squared lengths over the range a deck's units give (1e-18 .. 1e18), and the binade
     * edges, where one unit in the last place is largest relative to the value */
    for (int l = 0; l < 8; ++l) {
      const double mantissa = l == 0 ? 1.0 : l == 1 ? nextafter(2.0, 0.0) : 1.0 + rand() / (double)RAND_MAX;
      x[l] = ldexp(mantissa, rand() % 121 - 60);
    }
    peri_v8d r, ir;
    peri_root_v8(v8_loadu_pd(x), &r, &ir);
    v8_storeu_pd(root, r);
    v8_storeu_pd(inv, ir);
    for (int l = 0; l < 8; ++l) {
      const long double exact = sqrtl((long double)x[l]);
      const double e_root = (double)(fabsl((long double)root[l] - exact) / exact);
      const double e_inv = (double)(fabsl((long double)inv[l] * exact - 1.0L));
      if (e_root > worst_root) worst_root = e_root;
      if (e_inv > worst_inv) worst_inv = e_inv;
      cr_assert(e_root <= BOUND, "sqrt(%.17g) = %.17g: relative error %.3g u", x[l], root[l], e_root / UNIT_ROUNDOFF);
      cr_assert(e_inv <= BOUND, "1/sqrt(%.17g) = %.17g: relative error %.3g u", x[l], inv[l], e_inv / UNIT_ROUNDOFF);
    }
  }
  cr_log_info("worst relative errors: sqrt %.2f u, 1/sqrt %.2f u", worst_root / UNIT_ROUNDOFF,
              worst_inv / UNIT_ROUNDOFF);
#endif
}

/* An undeformed bond has exactly zero stretch: |y| and |xi| come from the same function, so
 * y = xi gives r == r0 bit for bit. */
Test(bond_lengths, undeformed_bond_has_zero_extension) {
#ifndef PERI_BOND_V8
  cr_skip_test("this build has no eight-lane kernels");
#else
  const double xj[3][8] = {{0.1, -0.3, 1e-3, 0.7, 2.5, -1e-4, 0.0, 3.0},
                           {0.2, 0.0, 2e-3, -0.7, 0.5, 3e-4, 1e-6, 0.0},
                           {-0.4, 0.9, 0.0, 0.7, 1.5, -2e-4, 0.0, 4.0}};
  const peri_v8d zero = v8_setzero_pd();
  const peri_v8d xv[3] = {v8_loadu_pd(xj[0]), v8_loadu_pd(xj[1]), v8_loadu_pd(xj[2])}, c[3] = {zero, zero, zero};
  const peri_v8d u[3] = {v8_set1_pd(0.25), v8_set1_pd(-0.5), v8_set1_pd(0.125)}; /* a translation */
  peri_v8d y[3], r0, inv_r0, r, inv_r;
  peri_bond_lengths_v8(xv, u, c, u, y, &r0, &inv_r0, &r, &inv_r);
  double a[8], b[8];
  v8_storeu_pd(a, r0);
  v8_storeu_pd(b, r);
  for (int l = 0; l < 8; ++l) {
    cr_assert(a[l] == b[l], "lane %d: |y| = %.17g against |xi| = %.17g", l, b[l], a[l]);
    const double exact = sqrt(xj[0][l] * xj[0][l] + xj[1][l] * xj[1][l] + xj[2][l] * xj[2][l]);
    cr_assert(fabs(a[l] - exact) <= 4.0 * UNIT_ROUNDOFF * exact, "lane %d: |xi| %.17g, sqrt %.17g", l, a[l], exact);
  }
#endif
}

Test(aligned_allocation, cache_line_aligned_and_zeroed) {
  const size_t sizes[] = {0, 1, 7, 63, 64, 65, 1000, 1 << 20};
  for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; ++s) {
    double *p = peri_calloc_aligned(sizes[s], sizeof(double));
    cr_assert_not_null(p);
    cr_assert_eq((uintptr_t)p % PERI_CACHE_LINE, 0, "%zu doubles at %p", sizes[s], (void *)p);
    for (size_t k = 0; k < sizes[s]; ++k) cr_assert(p[k] == 0.0, "element %zu of %zu not zero", k, sizes[s]);
    free(p);
    void *q = peri_malloc_aligned(sizes[s] * 3 + 1);
    cr_assert_eq((uintptr_t)q % PERI_CACHE_LINE, 0);
    free(q);
  }
}
