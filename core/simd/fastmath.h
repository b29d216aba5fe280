// Fast inverse trigonometry, square roots and reciprocals on any SIMD width.
//
// One implementation for float, vfloat4 and vfloat8 (the scalar path is the same
// polynomial). The polynomial coefficients were fitted when this header was first written
// (commit f32b030); the script that produced them was never committed, so they cannot be
// regenerated. They are near-minimax: a double-precision Remez fit of the same forms agrees
// with them to 2-5 significant digits (atan_unit, asin_small), not to the printed digits. Treat
// them as given; the bounds below, not their provenance, are what the tests enforce.
// Maximum errors, enforced by tests/cpp/core/simd/simd_lane_tests.h against double precision
// over dense sweeps (2^22 + 2^17 points in [-1, 1], 2^20 over 80 binades, 1.3M atan2
// pairs); measured maxima in parentheses. All widths give bit-identical results (madd
// rounds twice everywhere), so the bounds hold for every width alike.
//   fast_acos   x in [-1, 1]       absolute <= 5e-7 rad  (3.3e-7)
//   fast_asin   x in [-1, 1]       absolute <= 4e-7 rad  (1.9e-7)
//   fast_atan   any x              absolute <= 4e-7 rad  (1.8e-7)
//   fast_atan2  any (y, x)         absolute <= 5e-7 rad  (3.3e-7)
//   fast_sincos |x| <= 1e4         absolute <= 5e-7 (sine and cosine together; for sampling angles)
//   fast_log    x > 0              absolute <= 2e-7 max(1, |log x|) (log(0) = -inf, log(x < 0) = NaN)
//   fast_exp    |x| <= 87          relative <= 3e-7 (above 88.7: inf; below -87.3: 0)
//   fast_sqrt   x >= 0             correctly rounded (hardware sqrt)
//   fast_rcp    |x| in [2^-126, 2^126]  relative <= 3e-7 (2.0e-7; estimate + one Newton step)
//   fast_rsqrt  x in [2^-126, 2^126]    relative <= 3e-7 (2.4e-7; estimate + one Newton step)
// Special values follow the C library: asin/acos of |x| > 1 and NaN give NaN;
// atan2 handles signed zeros and infinities as C does; rcp(±0) = ±inf,
// rcp(±inf) = ±0, rsqrt(±0) = ±inf, rsqrt(inf) = 0, rsqrt(x < 0) = NaN. The wide
// rcp / rsqrt treat denormal inputs as ±0 (so does the hardware estimate); width 1
// divides exactly.
#pragma once

#include <limits>

#include "core/constants.h"
#include "core/simd/simd.h"

PATINA_BEGIN_TARGET

namespace fastmath_detail {
// atan(a) for a in [0, 1]: a + a z P(z), z = a^2 (fit error 5.3e-8).
template <class F>
PATINA_INLINE F atan_unit(F a) {
    const F z = a * a;
    F p = F(-0.004387184977531433f);
    p = madd(p, z, F(0.02316996082663536f));
    p = madd(p, z, F(-0.057983674108982086f));
    p = madd(p, z, F(0.0981130301952362f));
    p = madd(p, z, F(-0.13983823359012604f));
    p = madd(p, z, F(0.19964194297790527f));
    p = madd(p, z, F(-0.33331772685050964f));
    return madd(a * z, p, a);
}

// asin(s) for s in [0, 0.5], given z = s^2: s + s z Q(z) (fit error 3.1e-8).
template <class F>
PATINA_INLINE F asin_small(F s, F z) {
    F q = F(0.05182850360870361f);
    q = madd(q, z, F(0.039076246321201324f));
    q = madd(q, z, F(0.07555775344371796f));
    q = madd(q, z, F(0.1666484922170639f));
    return madd(s * z, q, s);
}

// asin(|x|) split as in the classic reduction: |x| <= 0.5 directly, otherwise
// asin(|x|) = pi/2 - 2 asin(sqrt((1 - |x|) / 2)). Returns the small-argument asin
// value p and the mask of lanes that took the large branch.
template <class F>
PATINA_INLINE F asin_core(F ax, mask_t<F>& big) {
    big = ax > F(0.5f);
    const F half_gap = (F(1.0f) - ax) * F(0.5f);
    const F z = select(big, half_gap, ax * ax);
    const F s = select(big, sqrt_exact(z), ax);
    return asin_small(s, z);
}
}  // namespace fastmath_detail

template <class F>
PATINA_INLINE F fast_atan(F x) {
    using namespace fastmath_detail;
    const F ax = abs(x);
    const mask_t<F> big = ax > F(1.0f);
    const F r = atan_unit(select(big, F(1.0f) / ax, ax));
    return copysign(select(big, F(kHalfPi) - r, r), x);
}

template <class F>
PATINA_INLINE F fast_atan2(F y, F x) {
    using namespace fastmath_detail;
    const F inf = F(std::numeric_limits<float>::infinity());
    const F ax = abs(x), ay = abs(y);
    const F hi = max(ax, ay), lo = min(ax, ay);
    F a = lo / hi;
    a = select(hi == F(0.0f), F(0.0f), a);                 // atan2(±0, ±0)
    a = select((ax == inf) & (ay == inf), F(1.0f), a);     // atan2(±inf, ±inf)
    F r = atan_unit(a);
    r = select(ay > ax, F(kHalfPi) - r, r);
    r = select(signbit(x), F(kPi) - r, r);
    r = copysign(r, y);
    return select(isnan(x) | isnan(y), F(std::numeric_limits<float>::quiet_NaN()), r);
}

template <class F>
PATINA_INLINE F fast_asin(F x) {
    using namespace fastmath_detail;
    mask_t<F> big;
    const F p = asin_core(abs(x), big);
    return copysign(select(big, F(kHalfPi) - (p + p), p), x);
}

template <class F>
PATINA_INLINE F fast_acos(F x) {
    using namespace fastmath_detail;
    mask_t<F> big;
    const F p = asin_core(abs(x), big);
    const F near_axis = select(signbit(x), F(kPi) - (p + p), p + p);  // acos(x) for |x| > 0.5
    const F middle = F(kHalfPi) - copysign(p, x);                       // pi/2 - asin(x)
    return select(big, near_axis, middle);
}

// sin(x) and cos(x): x = k pi/2 + r with |r| <= pi/4 (Cody-Waite reduction), odd/even
// polynomials in r, then the quadrant k swaps and negates them.
template <class F>
PATINA_INLINE void fast_sincos(F x, F& s, F& c) {
    using I = int_t<F>;
    const F k = floor(x * F(0.63661977236758134f) + F(0.5f));  // round(x / (pi/2))
    // pi/2 in three parts with few significant bits each, so k times each is exact
    const F r = ((x - k * F(1.5703125f)) - k * F(4.837512969970703125e-4f)) - k * F(7.549789954891882e-8f);
    const F z = r * r;
    F ps = F(-0.0001949169673025608f);
    ps = madd(ps, z, F(0.008331945165991783f));
    ps = madd(ps, z, F(-0.16666650772094727f));
    const F sr = madd(r * z, ps, r);
    F pc = F(2.443490484438371e-05f);
    pc = madd(pc, z, F(-0.0013887336244806647f));
    pc = madd(pc, z, F(0.04166664555668831f));
    const F cr = madd(z * z, pc, F(1.0f) - F(0.5f) * z);
    const I q = to_int_trunc(k - F(4.0f) * floor(k * F(0.25f)));  // quadrant 0..3
    const mask_t<F> swap = (q & I(1)) == I(1);
    const F s0 = select(swap, cr, sr), c0 = select(swap, sr, cr);
    s = select((q & I(2)) == I(2), -s0, s0);
    c = select(((q + I(1)) & I(2)) == I(2), -c0, c0);
}

// log(x) = e ln2 + log(m), m in [sqrt(1/2), sqrt(2)): log(m) = 2 atanh(t), t = (m - 1) / (m + 1).
template <class F>
PATINA_INLINE F fast_log(F x) {
    using I = int_t<F>;
    const mask_t<F> tiny = x < F(1.17549435e-38f);  // denormals: scale up first
    const F xs = select(tiny, x * F(8388608.0f), x);
    const I bits = as_int(xs);
    I e = ((bits >> 23) & I(0xff)) - I(127);
    e = select(tiny, e - I(23), e);
    F m = as_float((bits & I(0x7fffff)) | I(0x3f800000));  // [1, 2)
    const mask_t<F> big = m > F(1.41421356f);
    m = select(big, m * F(0.5f), m);
    const F ef = to_float(select(big, e + I(1), e));
    const F t = (m - F(1.0f)) / (m + F(1.0f));
    const F z = t * t;
    F p = F(0.2997798025608063f);
    p = madd(p, z, F(0.39972931146621704f));
    p = madd(p, z, F(0.6666682362556458f));
    const F log_m = madd(t * z, p, t + t);
    F r = madd(ef, F(0.693145751953125f), madd(ef, F(1.428606820309417e-06f), log_m));
    const F inf = F(std::numeric_limits<float>::infinity());
    r = select(x == F(0.0f), -inf, r);
    r = select(x == inf, inf, r);
    return select((x < F(0.0f)) | isnan(x), F(std::numeric_limits<float>::quiet_NaN()), r);
}

// exp(x) = 2^k exp(r), k = round(x / ln2), |r| <= ln2 / 2.
template <class F>
PATINA_INLINE F fast_exp(F x) {
    using I = int_t<F>;
    const F xc = clamp(x, F(-87.0f), F(88.5f));
    const F k = floor(xc * F(1.44269504f) + F(0.5f));
    const F r = (xc - k * F(0.693145751953125f)) - k * F(1.428606820309417e-06f);
    F p = F(0.008307237178087234f);
    p = madd(p, r, F(0.04189436882734299f));
    p = madd(p, r, F(0.16667185723781586f));
    p = madd(p, r, F(0.4999919831752777f));
    const F er = madd(r * r, p, r + F(1.0f));
    const F scaled = er * as_float((to_int_trunc(k) + I(127)) << 23);
    F out = select(x > F(88.72f), F(std::numeric_limits<float>::infinity()), scaled);
    out = select(x < F(-87.33f), F(0.0f), out);
    return select(isnan(x), x, out);
}

template <class F>
PATINA_INLINE F fast_sqrt(F x) {
    return sqrt_exact(x);
}

// Width 1 divides exactly; wide paths refine the hardware estimate once.
PATINA_INLINE float fast_rcp(float x) { return 1.0f / x; }
PATINA_INLINE float fast_rsqrt(float x) { return 1.0f / std::sqrt(x); }

template <class F>
PATINA_INLINE F fast_rcp(F x) {
    const F r = rcp_estimate(x);
    const F refined = r * nmadd(x, r, F(2.0f));
    const mask_t<F> keep = (abs(r) == F(std::numeric_limits<float>::infinity())) | (r == F(0.0f));
    return select(keep, r, refined);
}

template <class F>
PATINA_INLINE F fast_rsqrt(F x) {
    const F r = rsqrt_estimate(x);
    const F refined = r * nmadd(F(0.5f) * x, r * r, F(1.5f));
    const mask_t<F> keep = (abs(r) == F(std::numeric_limits<float>::infinity())) | (r == F(0.0f));
    return select(keep, r, refined);
}

PATINA_END_TARGET
