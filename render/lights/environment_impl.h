// The environment light N directions at a time (included by integrator_w{1,4,8}.cpp): radiance
// (bilinear over the lat-long map), the density of light sampling, and light sampling itself
// -- a coherent binary search over the rows' cdf, then a masked binary search (one gather per
// level) over each lane's own row. The same code at width 1 is the scalar path.
#pragma once

#include "brdf/search.h"
#include "core/constants.h"
#include "core/simd/fastmath.h"
#include "core/simd/kernel_width.h"
#include "render/scene.h"

PATINA_BEGIN_TARGET
namespace render_detail {
namespace env_w {
using namespace kernel_width;

// World direction -> the map's frame (turned back by the rotation about +y), and back.
PATINA_INLINE V3 to_map(const Environment& e, const V3& d) {
    const F c(e.cos_rotation), s(e.sin_rotation);
    return V3{c * d.x - s * d.z, d.y, s * d.x + c * d.z};
}
PATINA_INLINE V3 from_map(const Environment& e, const V3& m) {
    const F c(e.cos_rotation), s(e.sin_rotation);
    return V3{c * m.x + s * m.z, m.y, c * m.z - s * m.x};
}

// (u, v) in [0, 1) x [0, 1] of a unit map-frame direction: phi = atan2(x, -z), theta = acos(y).
PATINA_INLINE void map_uv(const V3& m, F& u, F& v) {
    u = fast_atan2(m.x, -m.z) * F(0.5f / kPi);
    u = select(u < F(0.0f), u + F(1.0f), u);
    u = select(u >= F(1.0f), F(0.0f), u);
    v = fast_acos(clamp(m.y, F(-1.0f), F(1.0f))) * F(1.0f / kPi);
}

PATINA_INLINE I clamp_int(I x, int lo, int hi) { return min(max(x, I(lo)), I(hi)); }

// Radiance at map coordinates (u, v) of a map environment, bilinear between pixel centres.
PATINA_INLINE void radiance_uv(const Environment& e, F u, F v, F& r, F& g, F& b) {
    const int w = e.width, h = e.height;
    const F x = madd(u, F(float(w)), F(-0.5f));
    const F y = clamp(madd(v, F(float(h)), F(-0.5f)), F(0.0f), F(float(h - 1)));
    const F xf = floor(x), yf = floor(y);
    const F fx = x - xf, fy = y - yf;
    const I x0 = to_int_trunc(xf), y0 = to_int_trunc(yf);  // x0 in [-1, w - 1], y0 in [0, h - 1]
    const I xa = select(x0 < I(0), x0 + I(w), x0);
    const I xb = select(x0 + I(1) > I(w - 1), x0 + I(1 - w), x0 + I(1));
    const I y1 = min(y0 + I(1), I(h - 1));
    const I row0 = y0 * I(w), row1 = y1 * I(w);
    F c00[3], c01[3], c10[3], c11[3];
    gather3(e.texels.data(), (row0 + xa) * I(3), c00[0], c00[1], c00[2]);
    gather3(e.texels.data(), (row0 + xb) * I(3), c01[0], c01[1], c01[2]);
    gather3(e.texels.data(), (row1 + xa) * I(3), c10[0], c10[1], c10[2]);
    gather3(e.texels.data(), (row1 + xb) * I(3), c11[0], c11[1], c11[2]);
    F out[3];
    for (int k = 0; k < 3; ++k) {
        const F top = madd(fx, c01[k] - c00[k], c00[k]), bottom = madd(fx, c11[k] - c10[k], c10[k]);
        out[k] = F(e.intensity) * madd(fy, bottom - top, top);
    }
    r = out[0], g = out[1], b = out[2];
}

// Radiance from unit world directions d (RGB).
PATINA_INLINE void radiance(const Environment& e, const V3& d, F& r, F& g, F& b) {
    if (!e.present) {
        r = g = b = F(0.0f);
        return;
    }
    if (!e.is_map) {
        r = F(e.constant[0] * e.intensity), g = F(e.constant[1] * e.intensity), b = F(e.constant[2] * e.intensity);
        return;
    }
    F u, v;
    map_uv(to_map(e, d), u, v);
    radiance_uv(e, u, v, r, g, b);
}

// The pixel (row, column) a map-frame (u, v) falls in.
PATINA_INLINE I pixel_of(const Environment& e, F u, F v) {
    const I c = clamp_int(to_int_trunc(u * F(float(e.width))), 0, e.width - 1);
    const I r = clamp_int(to_int_trunc(v * F(float(e.height))), 0, e.height - 1);
    return r * I(e.width) + c;
}

// Solid-angle density with which `sample` picks world direction d.
PATINA_INLINE F pdf(const Environment& e, const V3& d) {
    if (!e.present) return F(0.0f);
    if (!e.is_map) return F(1.0f / (4 * kPi));
    const V3 m = to_map(e, d);
    F u, v;
    map_uv(m, u, v);
    const F sin_theta = sqrt_exact(max(F(1.0f) - m.y * m.y, F(0.0f)));
    const F p = gather(e.pixel_pdf.data(), pixel_of(e, u, v));
    return select(sin_theta > F(0.0f), p / (F(2.0f * kPi * kPi) * sin_theta), F(0.0f));
}

// radiance() and, where with_pdf, pdf() of the same directions, the map coordinates found
// once for both (the same operations as each alone: the same bits); without with_pdf the
// pdf is 0. A miss after a camera ray needs no pdf (nothing to weigh it against).
PATINA_INLINE F radiance_and_pdf(const Environment& e, const V3& d, bool with_pdf, F& r, F& g, F& b) {
    if (!e.present || !e.is_map) {
        radiance(e, d, r, g, b);
        return with_pdf ? pdf(e, d) : F(0.0f);
    }
    const V3 m = to_map(e, d);
    F u, v;
    map_uv(m, u, v);
    radiance_uv(e, u, v, r, g, b);
    if (!with_pdf) return F(0.0f);
    const F sin_theta = sqrt_exact(max(F(1.0f) - m.y * m.y, F(0.0f)));
    const F p = gather(e.pixel_pdf.data(), pixel_of(e, u, v));
    return select(sin_theta > F(0.0f), p / (F(2.0f * kPi * kPi) * sin_theta), F(0.0f));
}

// Where sample() looks for a map's pixel: its row, a coherent search over the marginal cdf
// (lanes often agree on bright rows), and the columns [lo, hi] of that row's cdf between
// the guide's entries for u2's bucket (cdf[lo] <= u2 < cdf[hi], so the column is the last
// one whose cdf is <= u2: the full row's binary search gives the same).
PATINA_INLINE void column_range(const Environment& e, F u1, F u2, I& row, I& lo, I& hi) {
    row = coherent_search<N>(e.row_cdf.data(), e.height + 1, u1, F(0.0f) == F(0.0f));
    const int nb = e.col_buckets;
    const I bucket = min(to_int_trunc(u2 * F(float(nb))), I(nb - 1));
    const I gi = row * I(nb + 1) + bucket;
    lo = gather(e.col_guide.data(), gi), hi = gather(e.col_guide.data(), gi + I(1)) + I(1);
}

// Asks the cache for the cdf lines sample(e, u1, u2, ...) will search (the ends and middle
// of each lane's column range), so that a later block's first gathers, one random row per
// lane in a table larger than L2, overlap this block's work instead of waiting on memory.
// Reads and computes nothing sample() uses: its results are the same with or without it.
PATINA_INLINE void prefetch_sample(const Environment& e, F u1, F u2) {
    if (!e.is_map) return;
    I row, lo, hi;
    column_range(e, u1, u2, row, lo, hi);
    alignas(64) int32_t first[N], mid[N], last[N];
    const I base = row * I(e.width + 1);
    store_n<N>(first, (base + lo) * I(2));
    store_n<N>(mid, (base + ((lo + hi) >> 1)) * I(2));
    store_n<N>(last, (base + hi) * I(2));
    const float* cdf = e.col_cdf_pdf.data();
    for (int k = 0; k < N; ++k) {
        __builtin_prefetch(cdf + first[k]);
        __builtin_prefetch(cdf + mid[k]);
        __builtin_prefetch(cdf + last[k]);
    }
}

// Directions from the environment's distribution for uniforms (u1, u2), with their radiance
// (from the sampled map coordinates: no inverse trigonometry); returns the pdf.
PATINA_INLINE F sample(const Environment& e, F u1, F u2, V3& d, F& r, F& g, F& b) {
    if (!e.is_map) {
        const F z = nmadd(F(2.0f), u1, F(1.0f)), rad = sqrt_exact(max(F(1.0f) - z * z, F(0.0f)));
        F s, c;
        fast_sincos(F(2.0f * kPi) * u2, s, c);
        d = V3{rad * c, z, rad * s};
        radiance(e, d, r, g, b);
        return F(1.0f / (4 * kPi));
    }
    const int w = e.width, h = e.height;
    I row, lo, hi;
    column_range(e, u1, u2, row, lo, hi);
    const F r0 = gather(e.row_cdf.data(), row), r1 = gather(e.row_cdf.data(), row + I(1));
    const F fv = select(r1 > r0, clamp((u1 - r0) / (r1 - r0), F(0.0f), F(0.99999f)), F(0.5f));
    const I base = row * I(w + 1);
    while (any(hi - lo > I(1))) {
        const I mid = (lo + hi) >> 1;
        const auto right = u2 >= gather(e.col_cdf_pdf.data(), (base + mid) * I(2));
        lo = select(right, mid, lo);
        hi = select(right, hi, mid);
    }
    const I at = (base + lo) * I(2);
    const F c0 = gather(e.col_cdf_pdf.data(), at), c1 = gather(e.col_cdf_pdf.data(), at + I(2));
    const F fu = select(c1 > c0, clamp((u2 - c0) / (c1 - c0), F(0.0f), F(0.99999f)), F(0.5f));
    const F u = (to_float(lo) + fu) * F(1.0f / float(w)), v = (to_float(row) + fv) * F(1.0f / float(h));
    F sin_t, cos_t, sin_p, cos_p;
    fast_sincos(F(kPi) * v, sin_t, cos_t);
    fast_sincos(F(2.0f * kPi) * u, sin_p, cos_p);
    d = from_map(e, V3{sin_p * sin_t, cos_t, -cos_p * sin_t});
    radiance_uv(e, u, v, r, g, b);
    const F p = gather(e.col_cdf_pdf.data(), at + I(1));  // pixel_pdf[row * w + lo]
    return select(sin_t > F(0.0f), p / (F(2.0f * kPi * kPi) * sin_t), F(0.0f));
}

}  // namespace env_w
}  // namespace render_detail
PATINA_END_TARGET
