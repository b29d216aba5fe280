// Materials over arrays of shading points, N lanes at a time (included by integrator_w{1,4,8,16}.cpp).
// Directions are local (z = shading normal, x = tangent): v towards the viewer (the known
// direction), l towards the light (or the sampled one). Values are RGB BRDFs in 1/sr,
// zero when either direction is at or below the horizon -- except for the dielectric,
// which also transmits (l.z < 0) and reads each point's relative index from `eta`
// (index beyond the surface / index on the viewer's side; the others ignore it).
// Each operation is one visit_kind over the material's kind (render/materials/material.h)
// per packet of points, the kind's own eval / pdf / sample in its file.
#pragma once

#include "core/simd/kernel_width.h"
#include "render/materials/material.h"

PATINA_BEGIN_TARGET
namespace materials {

// f for n rows of (l, v), a kind evaluated N lanes at a time (the table and the mixture
// evaluate whole arrays with their own kernels: their files' eval_rows).
template <int Width, class Kind>
inline void eval_rows(const Kind& kind, const float* l, const float* v, const float* eta, float* f, size_t n) {
    using namespace kernel_width;
    for_blocks(n, [&](size_t i, int lanes) {
        // only glass reads the relative index: the others' blocks skip loading it
        F e(1.0f);
        if constexpr (Kind::transmits) e = load_lanes(eta, i, lanes);
        store_rows(f, i, lanes, eval(kind, load_rows(l, i, lanes), load_rows(v, i, lanes), e));
    });
}

}  // namespace materials

namespace render_detail {
using namespace kernel_width;

// f(l, v) in RGB, the coat included.
inline void material_eval(const Material& m, const float* l, const float* v, const float* eta, float* f, size_t n) {
    visit_kind(m, [&](const auto& kind) { materials::eval_rows<N>(kind, l, v, eta, f, n); });
    if (!m.coat) return;
    for_blocks(n, [&](size_t i, int lanes) {
        const V3 base = load_rows(f, i, lanes);
        store_rows(f, i, lanes, materials::over_coat(*m.coat, load_rows(l, i, lanes), load_rows(v, i, lanes), base));
    });
}

PATINA_INLINE F coat_pick(const Material& m, F cos_v) {
    return materials::coat_pick(*m.coat, luminance(m.albedo), cos_v);
}

// The sampling density of l given v, the coat's lobe included.
PATINA_INLINE F material_pdf(const Material& m, const V3& l, const V3& v, F eta) {
    const F base = visit_kind(m, [&](const auto& kind) { return materials::pdf(kind, l, v, eta); });
    if (!m.coat) return base;
    const F c = coat_pick(m, v.z);
    return madd(c, materials::coat_pdf(*m.coat, l, v), (F(1.0f) - c) * base);
}

inline void material_pdf(const Material& m, const float* l, const float* v, const float* eta, float* pdf, size_t n) {
    for_blocks(n, [&](size_t i, int lanes) {
        store_lanes(pdf, i, lanes,
                    material_pdf(m, load_rows(l, i, lanes), load_rows(v, i, lanes), load_lanes(eta, i, lanes)));
    });
}

// Samples l for each v from three uniforms per point (pick, u1, u2; pick only where
// sampling_picks); pdf[i] is material_pdf(l, v).
inline void material_sample(const Material& m, const float* v, const float* eta, const float* pick, const float* u1,
                            const float* u2, float* l, float* pdf, size_t n) {
    for_blocks(n, [&](size_t i, int lanes) {
        const V3 b = load_rows(v, i, lanes);
        const F pick_u = load_lanes(pick, i, lanes);
        const F s1 = load_lanes(u1, i, lanes), s2 = load_lanes(u2, i, lanes);
        // one uniform makes both choices: the coat when pick < c, else the base, with the
        // pick rescaled to [0, 1) for the base's own choice of lobe
        const F c = m.coat ? coat_pick(m, b.z) : F(0.0f);
        const F base_pick = m.coat ? (pick_u - c) / (F(1.0f) - c) : pick_u;
        const F e = load_lanes(eta, i, lanes);
        V3 a = visit_kind(m, [&](const auto& kind) { return materials::sample(kind, b, base_pick, s1, s2, e); });
        if (m.coat) {
            const auto coat = pick_u < c;
            const V3 cl = materials::coat_sample(*m.coat, b, s1, s2);
            a = V3{select(coat, cl.x, a.x), select(coat, cl.y, a.y), select(coat, cl.z, a.z)};
        }
        store_rows(l, i, lanes, a.x, a.y, a.z);
        store_lanes(pdf, i, lanes, material_pdf(m, a, b, e));
    });
}

}  // namespace render_detail
PATINA_END_TARGET
