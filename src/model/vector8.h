/* Eight double lanes for the bond functions of the models (bond_kernel.h, pmb.c, lps.c,
 * osb_mo.c): one 512-bit register on AVX-512, a pair of 256-bit registers on AVX2 with FMA.
 * The kernels are written once against the v8_* operations below, named after the AVX-512
 * intrinsics they stand for, with eight-bit lane masks (bit l is lane l) on both. Without
 * either instruction set PERI_BOND_V8 stays undefined and the models use their scalar loops.
 *
 * Why a pair on AVX2 rather than GCC's own vectorization of the eight-lane loops: GCC
 * unrolls an eight-iteration loop completely before it vectorizes it for four lanes, and the
 * unrolled code is scalar (measured: 7.4e7 directed-bond updates/s on the 206k-node PMB
 * problem, about twice LAMMPS); AVX2 has no double-precision reciprocal square root, so
 * v8_rsqrt14_pd starts from the single-precision estimate (relative error below 1.5 x 2^-12)
 * refined by one Newton step (about 2^-23), a better start than vrsqrt14pd's 2^-14 for the
 * correction step of peri_root_v8. Its range is that of a float: squared lengths between
 * 1e-37 and 3e38 in the deck's units. */
#ifndef PERI_VECTOR8_H
#define PERI_VECTOR8_H

#if defined(__AVX512F__) || (defined(__AVX2__) && defined(__FMA__))
#include <immintrin.h>
#include <stdbool.h>
#include <stdint.h>
#define PERI_BOND_V8 1
/* An AVX-512 build for AMD Zen 5 (GCC 12 names it znver3 under -march=native, later compilers
 * znver5), where the kernels take the hardware square root (PERI_ROOT_HARDWARE, bond_kernel.h)
 * and do gathers by loads (PERI_GATHER_LOADS below): the two choices measured there
 * (docs/performance.md, docs/plasticity.md section 8) */
#if defined(__AVX512F__) && (defined(__znver3__) || defined(__znver5__))
#define PERI_AVX512_ZEN5 1
#else
#define PERI_AVX512_ZEN5 0
#endif

#if defined(__AVX512F__)
typedef __m512d peri_v8d;
typedef __mmask8 peri_m8;
typedef __m256i peri_v8i;
typedef __m512i peri_v8l; /* eight 64-bit integers */
#define v8_loadu_pd _mm512_loadu_pd
#define v8_storeu_pd _mm512_storeu_pd
#define v8_mask_storeu_pd _mm512_mask_storeu_pd
#define v8_set1_pd _mm512_set1_pd
#define v8_setzero_pd _mm512_setzero_pd
#define v8_add_pd _mm512_add_pd
#define v8_sub_pd _mm512_sub_pd
#define v8_mul_pd _mm512_mul_pd
#define v8_div_pd _mm512_div_pd
#define v8_sqrt_pd _mm512_sqrt_pd
#define v8_fmadd_pd _mm512_fmadd_pd
#define v8_fnmadd_pd _mm512_fnmadd_pd
#define v8_fmsub_pd _mm512_fmsub_pd
#define v8_min_pd _mm512_min_pd
#define v8_abs_pd _mm512_abs_pd
#define v8_mask_min_pd _mm512_mask_min_pd
#define v8_mask_max_pd _mm512_mask_max_pd
#define v8_mask_add_pd _mm512_mask_add_pd
#define v8_mask3_fmadd_pd _mm512_mask3_fmadd_pd
#define v8_maskz_mov_pd _mm512_maskz_mov_pd
#define v8_mask_mov_pd _mm512_mask_mov_pd
/* the bits of a and b or'ed (AVX512F has no or of doubles) */
#define v8_or_pd(a, b) _mm512_castsi512_pd(_mm512_or_si512(_mm512_castpd_si512(a), _mm512_castpd_si512(b)))
#define v8_cmp_pd_mask _mm512_cmp_pd_mask
#define v8_mask_cmp_pd_mask _mm512_mask_cmp_pd_mask
#define v8_reduce_min_pd _mm512_reduce_min_pd
#define v8_reduce_max_pd _mm512_reduce_max_pd
#define v8_rsqrt14_pd _mm512_rsqrt14_pd
#define v8_maskz_loadu_epi32 _mm256_maskz_loadu_epi32
/* Gathers by eight scalar loads where the gather instruction is slow: on Zen 5 (GCC 12 names
 * it znver3) vgatherdpd/vgatherqpd take longer than eight loads and the shuffles that join
 * them (docs/plasticity.md §8). The loads are the same, so are the results. Elsewhere (Intel)
 * the instruction, as in AVX2 builds. -DPERI_GATHER_LOADS=0 or 1 overrides the choice (AVX-512
 * builds). */
#ifndef PERI_GATHER_LOADS
#define PERI_GATHER_LOADS PERI_AVX512_ZEN5
#endif
#if PERI_GATHER_LOADS
/* The 64-bit indices of the lanes in m, the lanes not in m given the first such lane's (so
 * that every load is of an element the caller names); m is not 0. */
static inline __attribute__((always_inline)) void v8_lane_indices(__mmask8 m, __m512i index, int64_t at[8]) {
  const __m512i first = _mm512_permutexvar_epi64(_mm512_set1_epi64(__builtin_ctz(m)), index);
  _mm512_storeu_si512(at, _mm512_mask_mov_epi64(first, m, index));
}
static inline __attribute__((always_inline)) __m512d v8_loads_pd(__mmask8 m, const int64_t at[8], const double *base) {
  const __m128d a = _mm_loadh_pd(_mm_load_sd(&base[at[0]]), &base[at[1]]);
  const __m128d b = _mm_loadh_pd(_mm_load_sd(&base[at[2]]), &base[at[3]]);
  const __m128d c = _mm_loadh_pd(_mm_load_sd(&base[at[4]]), &base[at[5]]);
  const __m128d d = _mm_loadh_pd(_mm_load_sd(&base[at[6]]), &base[at[7]]);
  const __m256d lo = _mm256_insertf128_pd(_mm256_castpd128_pd256(a), b, 1);
  const __m256d hi = _mm256_insertf128_pd(_mm256_castpd128_pd256(c), d, 1);
  return _mm512_maskz_mov_pd(m, _mm512_insertf64x4(_mm512_castpd256_pd512(lo), hi, 1));
}
/* the eight doubles at base[index[l]] of the lanes in m, 0 in the others */
static inline __attribute__((always_inline)) __m512d v8_mask_i32gather_pd(__mmask8 m, __m256i index, const double *base) {
  if (!m) return _mm512_setzero_pd();
  int64_t at[8];
  v8_lane_indices(m, _mm512_cvtepi32_epi64(index), at);
  return v8_loads_pd(m, at, base);
}
static inline __attribute__((always_inline)) __m512d v8_mask_i64gather_pd(__mmask8 m, __m512i index, const double *base) {
  if (!m) return _mm512_setzero_pd();
  int64_t at[8];
  v8_lane_indices(m, index, at);
  return v8_loads_pd(m, at, base);
}
/* the doubles at base[at[l]] of the lanes in m, 0 in the others, where every at[l] (in m or not)
 * is an index into base */
static inline __attribute__((always_inline)) __m512d v8_mask_gather_at_pd(__mmask8 m, const int64_t at[8],
                                                                          const double *base) {
  return v8_loads_pd(m, at, base);
}
/* the eight 64-bit integers at base[index[l]], 0 in the lanes not in m */
static inline __attribute__((always_inline)) __m512i v8_mask_i32gather_epi64(__mmask8 m, __m256i index,
                                                                             const int64_t *base) {
  if (!m) return _mm512_setzero_si512();
  int64_t at[8];
  v8_lane_indices(m, _mm512_cvtepi32_epi64(index), at);
  const __m128i a = _mm_insert_epi64(_mm_cvtsi64_si128(base[at[0]]), base[at[1]], 1);
  const __m128i b = _mm_insert_epi64(_mm_cvtsi64_si128(base[at[2]]), base[at[3]], 1);
  const __m128i c = _mm_insert_epi64(_mm_cvtsi64_si128(base[at[4]]), base[at[5]], 1);
  const __m128i d = _mm_insert_epi64(_mm_cvtsi64_si128(base[at[6]]), base[at[7]], 1);
  const __m256i lo = _mm256_inserti128_si256(_mm256_castsi128_si256(a), b, 1);
  const __m256i hi = _mm256_inserti128_si256(_mm256_castsi128_si256(c), d, 1);
  return _mm512_maskz_mov_epi64(m, _mm512_inserti64x4(_mm512_castsi256_si512(lo), hi, 1));
}
#else
/* the eight doubles at base[index[l]] of the lanes in m, 0 in the others */
#define v8_mask_i32gather_pd(m, index, base) _mm512_mask_i32gather_pd(_mm512_setzero_pd(), (m), (index), (base), 8)
/* the eight 64-bit integers at base[index[l]] (0 in the lanes not in m), and the doubles at
 * base[index[l]] for 64-bit indices */
#define v8_mask_i32gather_epi64(m, index, base)                                                                \
  _mm512_mask_i32gather_epi64(_mm512_setzero_si512(), (m), (index), (base), 8)
#define v8_mask_gather_at_pd(m, at, base) v8_mask_i64gather_pd((m), _mm512_loadu_si512(at), (base))
#define v8_mask_i64gather_pd(m, index, base) _mm512_mask_i64gather_pd(_mm512_setzero_pd(), (m), (index), (base), 8)
#endif

#else /* AVX2 and FMA: lanes 0-3 in lo, 4-7 in hi */
typedef struct peri_v8d {
  __m256d lo, hi;
} peri_v8d;
typedef uint8_t peri_m8;
typedef __m256i peri_v8i;
typedef struct peri_v8l {
  __m256i lo, hi;
} peri_v8l; /* eight 64-bit integers */
#define V8_INLINE static inline __attribute__((always_inline))

/* the 64-bit lane masks of four bits */
V8_INLINE __m256d v8_lanes4(unsigned bits) {
  const __m256i bit = _mm256_set_epi64x(8, 4, 2, 1);
  return _mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_and_si256(_mm256_set1_epi64x((long long)bits), bit), bit));
}
V8_INLINE __m256d v8_mask_lo(peri_m8 m) { return v8_lanes4(m & 15u); }
V8_INLINE __m256d v8_mask_hi(peri_m8 m) { return v8_lanes4((unsigned)m >> 4); }
V8_INLINE peri_v8d v8_make(__m256d lo, __m256d hi) {
  const peri_v8d v = {lo, hi};
  return v;
}
V8_INLINE peri_v8d v8_loadu_pd(const double *p) { return v8_make(_mm256_loadu_pd(p), _mm256_loadu_pd(p + 4)); }
V8_INLINE void v8_storeu_pd(double *p, peri_v8d v) { _mm256_storeu_pd(p, v.lo), _mm256_storeu_pd(p + 4, v.hi); }
V8_INLINE void v8_mask_storeu_pd(double *p, peri_m8 m, peri_v8d v) {
  _mm256_maskstore_pd(p, _mm256_castpd_si256(v8_mask_lo(m)), v.lo);
  _mm256_maskstore_pd(p + 4, _mm256_castpd_si256(v8_mask_hi(m)), v.hi);
}
V8_INLINE peri_v8d v8_set1_pd(double a) { return v8_make(_mm256_set1_pd(a), _mm256_set1_pd(a)); }
V8_INLINE peri_v8d v8_setzero_pd(void) { return v8_make(_mm256_setzero_pd(), _mm256_setzero_pd()); }
#define V8_BINARY(NAME, OP)                                                                                    \
  V8_INLINE peri_v8d NAME(peri_v8d a, peri_v8d b) { return v8_make(OP(a.lo, b.lo), OP(a.hi, b.hi)); }
V8_BINARY(v8_add_pd, _mm256_add_pd)
V8_BINARY(v8_sub_pd, _mm256_sub_pd)
V8_BINARY(v8_mul_pd, _mm256_mul_pd)
V8_BINARY(v8_div_pd, _mm256_div_pd)
V8_BINARY(v8_min_pd, _mm256_min_pd)
V8_BINARY(v8_max_pd, _mm256_max_pd)
#undef V8_BINARY
#define V8_TERNARY(NAME, OP)                                                                                   \
  V8_INLINE peri_v8d NAME(peri_v8d a, peri_v8d b, peri_v8d c) {                                            \
    return v8_make(OP(a.lo, b.lo, c.lo), OP(a.hi, b.hi, c.hi));                                              \
  }
V8_TERNARY(v8_fmadd_pd, _mm256_fmadd_pd)
V8_TERNARY(v8_fnmadd_pd, _mm256_fnmadd_pd)
V8_TERNARY(v8_fmsub_pd, _mm256_fmsub_pd)
#undef V8_TERNARY
V8_INLINE peri_v8d v8_sqrt_pd(peri_v8d a) { return v8_make(_mm256_sqrt_pd(a.lo), _mm256_sqrt_pd(a.hi)); }
V8_INLINE peri_v8d v8_abs_pd(peri_v8d a) {
  const __m256d sign = _mm256_set1_pd(-0.0);
  return v8_make(_mm256_andnot_pd(sign, a.lo), _mm256_andnot_pd(sign, a.hi));
}
/* lane l of `value` where bit l of m is set, of `src` elsewhere */
V8_INLINE peri_v8d v8_select(peri_v8d src, peri_m8 m, peri_v8d value) {
  return v8_make(_mm256_blendv_pd(src.lo, value.lo, v8_mask_lo(m)), _mm256_blendv_pd(src.hi, value.hi, v8_mask_hi(m)));
}
V8_INLINE peri_v8d v8_or_pd(peri_v8d a, peri_v8d b) { return v8_make(_mm256_or_pd(a.lo, b.lo), _mm256_or_pd(a.hi, b.hi)); }
V8_INLINE peri_v8d v8_mask_mov_pd(peri_v8d src, peri_m8 m, peri_v8d a) { return v8_select(src, m, a); }
V8_INLINE peri_v8d v8_mask_min_pd(peri_v8d src, peri_m8 m, peri_v8d a, peri_v8d b) {
  return v8_select(src, m, v8_min_pd(a, b));
}
V8_INLINE peri_v8d v8_mask_max_pd(peri_v8d src, peri_m8 m, peri_v8d a, peri_v8d b) {
  return v8_select(src, m, v8_max_pd(a, b));
}
V8_INLINE peri_v8d v8_mask_add_pd(peri_v8d src, peri_m8 m, peri_v8d a, peri_v8d b) {
  return v8_select(src, m, v8_add_pd(a, b));
}
V8_INLINE peri_v8d v8_mask3_fmadd_pd(peri_v8d a, peri_v8d b, peri_v8d c, peri_m8 m) {
  return v8_select(c, m, v8_fmadd_pd(a, b, c));
}
V8_INLINE peri_v8d v8_maskz_mov_pd(peri_m8 m, peri_v8d a) {
  return v8_make(_mm256_and_pd(a.lo, v8_mask_lo(m)), _mm256_and_pd(a.hi, v8_mask_hi(m)));
}
/* (a macro: the predicate must be a constant) */
#define v8_cmp_pd_mask(a, b, predicate)                                                                        \
  ((peri_m8)(_mm256_movemask_pd(_mm256_cmp_pd((a).lo, (b).lo, (predicate))) |                                 \
             (_mm256_movemask_pd(_mm256_cmp_pd((a).hi, (b).hi, (predicate))) << 4)))
#define v8_mask_cmp_pd_mask(m, a, b, predicate) ((peri_m8)((m) & v8_cmp_pd_mask(a, b, predicate)))
V8_INLINE double v8_reduce4(__m256d v, bool want_min) {
  __m128d h = want_min ? _mm_min_pd(_mm256_castpd256_pd128(v), _mm256_extractf128_pd(v, 1))
                       : _mm_max_pd(_mm256_castpd256_pd128(v), _mm256_extractf128_pd(v, 1));
  h = want_min ? _mm_min_sd(h, _mm_unpackhi_pd(h, h)) : _mm_max_sd(h, _mm_unpackhi_pd(h, h));
  return _mm_cvtsd_f64(h);
}
V8_INLINE double v8_reduce_min_pd(peri_v8d a) { return v8_reduce4(_mm256_min_pd(a.lo, a.hi), true); }
V8_INLINE double v8_reduce_max_pd(peri_v8d a) { return v8_reduce4(_mm256_max_pd(a.lo, a.hi), false); }
/* 1/sqrt(x): the float estimate and one Newton step (see the top of this file) */
V8_INLINE __m256d v8_rsqrt4(__m256d x) {
  const __m256d y = _mm256_cvtps_pd(_mm_rsqrt_ps(_mm256_cvtpd_ps(x)));
  const __m256d half_x = _mm256_mul_pd(x, _mm256_set1_pd(0.5));
  return _mm256_fmadd_pd(y, _mm256_fnmadd_pd(_mm256_mul_pd(half_x, y), y, _mm256_set1_pd(0.5)), y);
}
V8_INLINE peri_v8d v8_rsqrt14_pd(peri_v8d x) { return v8_make(v8_rsqrt4(x.lo), v8_rsqrt4(x.hi)); }
V8_INLINE peri_v8i v8_maskz_loadu_epi32(peri_m8 m, const int32_t *p) {
  const __m256i bit = _mm256_set_epi32(128, 64, 32, 16, 8, 4, 2, 1);
  const __m256i on = _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(m), bit), bit);
  return _mm256_maskload_epi32((const int *)p, on);
}
V8_INLINE peri_v8d v8_mask_i32gather_pd(peri_m8 m, peri_v8i index, const double *base) {
  const __m256d zero = _mm256_setzero_pd();
  return v8_make(_mm256_mask_i32gather_pd(zero, base, _mm256_castsi256_si128(index), v8_mask_lo(m), 8),
                 _mm256_mask_i32gather_pd(zero, base, _mm256_extracti128_si256(index, 1), v8_mask_hi(m), 8));
}
V8_INLINE peri_v8l v8_mask_i32gather_epi64(peri_m8 m, peri_v8i index, const int64_t *base) {
  const __m256i zero = _mm256_setzero_si256();
  const long long *b = (const long long *)base;
  const peri_v8l v = {
      _mm256_mask_i32gather_epi64(zero, b, _mm256_castsi256_si128(index), _mm256_castpd_si256(v8_mask_lo(m)), 8),
      _mm256_mask_i32gather_epi64(zero, b, _mm256_extracti128_si256(index, 1), _mm256_castpd_si256(v8_mask_hi(m)), 8)};
  return v;
}
V8_INLINE peri_v8d v8_mask_i64gather_pd(peri_m8 m, peri_v8l index, const double *base) {
  const __m256d zero = _mm256_setzero_pd();
  return v8_make(_mm256_mask_i64gather_pd(zero, base, index.lo, v8_mask_lo(m), 8),
                 _mm256_mask_i64gather_pd(zero, base, index.hi, v8_mask_hi(m), 8));
}
V8_INLINE peri_v8d v8_mask_gather_at_pd(peri_m8 m, const int64_t at[8], const double *base) {
  const peri_v8l index = {_mm256_loadu_si256((const __m256i *)at), _mm256_loadu_si256((const __m256i *)(at + 4))};
  return v8_mask_i64gather_pd(m, index, base);
}
#undef V8_INLINE
#endif
#endif
#endif
