// Materials over arrays of shading points, N lanes at a time (included by integrator_w{1,4,8,16}.cpp).
// Directions are local (z = shading normal, x = tangent): v towards the viewer (the known
// direction), l towards the light (or the sampled one). Values are RGB BRDFs in 1/sr,
// zero when either direction is at or below the horizon -- except for the dielectric,
// which also transmits (l.z < 0) and reads each point's relative index from `eta`
// (index beyond the surface / index on the viewer's side; the others ignore it).
#pragma once

#include <algorithm>

#include "brdf/kernels.h"
#include "core/constants.h"
#include "core/simd/kernel_width.h"
#include "core/width_dispatch.h"
#include "fit/lobe_kernels.h"
#include "fit/microfacet.h"
#include "render/materials/dielectric.h"
#include "render/materials/ggx_aniso.h"
#include "render/scene.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// The table and analytic-lobe kernels compiled for this width.
inline const Kernels& table_kernels() {
    return kernels_at_width<N>(kernels_w1, kernels_w4, kernels_w8, kernels_w16);
}
inline const LobeKernels& lobe_kernels() {
    return kernels_at_width<N>(lobe_kernels_w1, lobe_kernels_w4, lobe_kernels_w8, lobe_kernels_w16);
}

// The clear coat's GGX reflection with exact dielectric Fresnel (fit/microfacet.h's coat
// lobe), with D and G from render/materials/ggx_aniso.h: computed from the directions' components, they
// keep their precision for the nearly smooth coats of car paint, where D from cos(theta_h)
// near 1 would lose it (and no longer cancel against the sampling density).
PATINA_INLINE F coat_value(const V3& l, const V3& v, F alpha, F eta) {
    const V3 h = microfacet::half_vector(l, v);
    const F dg = ggx_aniso::d(h, alpha, alpha) * ggx_aniso::g2(l, v, alpha, alpha);
    return microfacet::microfacet_value(l, v, dg, F(1.0f),
                                        microfacet::fresnel_dielectric(microfacet::mean_cos_d(l, v, h), eta));
}

// l reflected about a GGX normal visible from v (density ggx_aniso::pdf).
PATINA_INLINE V3 ggx_reflect_sample(const V3& v, F u1, F u2, F alpha) {
    return microfacet::reflect(v, ggx_aniso::sample_visible(v, u1, u2, alpha, alpha));
}

// The coat's probability of being sampled, from v alone (so sampling and pdf agree):
// its Fresnel reflectance against what the base reflects, kept in [0.1, 0.9].
PATINA_INLINE F coat_pick(const Material& m, F cos_v) {
    const F fr = microfacet::fresnel_dielectric(max(cos_v, F(0.0f)), F(m.coat_eta));
    const float base = luminance(m.albedo);
    return clamp(fr / (fr + (F(1.0f) - fr) * F(std::max(base, 1e-3f))), F(0.1f), F(0.9f));
}

// The base layer's value (no coat), RGB into f.
inline void base_eval(const Material& m, const float* l, const float* v, const float* eta, float* f, size_t n) {
    switch (m.kind) {
        case MaterialKind::Dielectric:
            for_blocks(n, [&](size_t i, int lanes) {
                F value, pdf;
                dielectric::eval_pdf(load_rows(l, i, lanes), load_rows(v, i, lanes), F(m.alpha_x),
                                     load_lanes(eta, i, lanes), value, pdf);
                store_rows(f, i, lanes, value, value, value);
            });
            return;
        case MaterialKind::Table:
            table_kernels().eval(*m.table, l, v, f, 0, n);
            break;
        case MaterialKind::Mixture:
            lobe_kernels().eval_mixture(m.mixture, l, v, f, n);
            break;
        case MaterialKind::Lambert:
            for_blocks(n, [&](size_t i, int lanes) {
                const V3 a = load_rows(l, i, lanes), b = load_rows(v, i, lanes);
                const F r = microfacet::lambert_eval(a, b, F(m.albedo[0]));
                const F g = microfacet::lambert_eval(a, b, F(m.albedo[1]));
                const F bl = microfacet::lambert_eval(a, b, F(m.albedo[2]));
                store_rows(f, i, lanes, r, g, bl);
            });
            return;
        case MaterialKind::Conductor:
            for_blocks(n, [&](size_t i, int lanes) {
                const V3 a = load_rows(l, i, lanes), b = load_rows(v, i, lanes);
                const F ax(m.alpha_x), ay(m.alpha_y);
                const V3 h = microfacet::half_vector(a, b);
                const F dg = ggx_aniso::d(h, ax, ay) * ggx_aniso::g2(a, b, ax, ay);
                const F cos_d = microfacet::mean_cos_d(a, b, h);
                F c[3];
                for (int ch = 0; ch < 3; ++ch)
                    c[ch] = F(m.tint[ch]) * microfacet::microfacet_value(
                                                a, b, dg, F(1.0f),
                                                microfacet::fresnel_conductor(cos_d, F(m.eta[ch]), F(m.k[ch])));
                store_rows(f, i, lanes, c[0], c[1], c[2]);
            });
            return;
        case MaterialKind::Emitter:
            std::fill(f, f + 3 * n, 0.0f);
            return;
    }
    // Table and Mixture: scale and tint
    if (m.tint[0] != 1.0f || m.tint[1] != 1.0f || m.tint[2] != 1.0f)
        for (size_t i = 0; i < n; ++i)
            for (int ch = 0; ch < 3; ++ch) f[3 * i + ch] *= m.tint[ch];
}

// f(l, v) in RGB, the coat included.
inline void material_eval(const Material& m, const float* l, const float* v, const float* eta, float* f, size_t n) {
    base_eval(m, l, v, eta, f, n);
    if (!m.coat) return;
    for_blocks(n, [&](size_t i, int lanes) {
        const V3 a = load_rows(l, i, lanes), b = load_rows(v, i, lanes);
        const F coat_eta(m.coat_eta);
        const F through = (F(1.0f) - microfacet::fresnel_dielectric(max(a.z, F(0.0f)), coat_eta)) *
                          (F(1.0f) - microfacet::fresnel_dielectric(max(b.z, F(0.0f)), coat_eta));
        const F spec = coat_value(a, b, F(m.coat_alpha), coat_eta);
        const V3 base = load_rows(f, i, lanes);
        store_rows(f, i, lanes, madd(base.x * F(m.coat_tint[0]), through, spec),
                   madd(base.y * F(m.coat_tint[1]), through, spec), madd(base.z * F(m.coat_tint[2]), through, spec));
    });
}

// The base layer's sampling density of l given v.
PATINA_INLINE F base_pdf(const Material& m, const V3& l, const V3& v, F eta) {
    switch (m.kind) {
        case MaterialKind::Dielectric: {
            F value, pdf;
            dielectric::eval_pdf(l, v, F(m.alpha_x), eta, value, pdf);
            return pdf;
        }
        case MaterialKind::Lambert:
            return microfacet::lambert_pdf(v, l);
        case MaterialKind::Conductor:
            return ggx_aniso::pdf(v, l, F(m.alpha_x), F(m.alpha_y));
        case MaterialKind::Table:
        case MaterialKind::Mixture: {
            const F pd(m.proxy_diffuse);
            return madd(pd, microfacet::lambert_pdf(v, l),
                        (F(1.0f) - pd) * ggx_aniso::pdf(v, l, F(m.proxy_alpha), F(m.proxy_alpha)));
        }
        case MaterialKind::Emitter:
            break;
    }
    return F(0.0f);
}

PATINA_INLINE F full_pdf(const Material& m, const V3& l, const V3& v, F eta) {
    const F base = base_pdf(m, l, v, eta);
    if (!m.coat) return base;
    const F c = coat_pick(m, v.z);
    return madd(c, ggx_aniso::pdf(v, l, F(m.coat_alpha), F(m.coat_alpha)), (F(1.0f) - c) * base);
}

inline void material_pdf(const Material& m, const float* l, const float* v, const float* eta, float* pdf, size_t n) {
    for_blocks(n, [&](size_t i, int lanes) {
        store_lanes(pdf, i, lanes,
                        full_pdf(m, load_rows(l, i, lanes), load_rows(v, i, lanes), load_lanes(eta, i, lanes)));
    });
}

// Whether material_sample reads the pick uniform (to choose a coat, a lobe or reflection
// against transmission); the others sample from (u1, u2) alone.
inline bool sampling_picks(const Material& m) {
    return m.coat || m.kind == MaterialKind::Dielectric || m.kind == MaterialKind::Table ||
           m.kind == MaterialKind::Mixture;
}

// Samples l for each v from three uniforms per point (pick, u1, u2; pick only where
// sampling_picks); pdf[i] is full_pdf(l, v).
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
        V3 a{F(0.0f), F(0.0f), F(1.0f)};
        switch (m.kind) {
            case MaterialKind::Dielectric:
                a = dielectric::sample(b, base_pick, s1, s2, F(m.alpha_x), e);
                break;
            case MaterialKind::Lambert:
                a = microfacet::lambert_sample(s1, s2);
                break;
            case MaterialKind::Conductor:
                a = microfacet::reflect(b, ggx_aniso::sample_visible(b, s1, s2, F(m.alpha_x), F(m.alpha_y)));
                break;
            case MaterialKind::Table:
            case MaterialKind::Mixture: {
                const auto diffuse = base_pick < F(m.proxy_diffuse);
                const V3 dl = microfacet::lambert_sample(s1, s2);
                const V3 gl = ggx_reflect_sample(b, s1, s2, F(m.proxy_alpha));
                a = V3{select(diffuse, dl.x, gl.x), select(diffuse, dl.y, gl.y), select(diffuse, dl.z, gl.z)};
                break;
            }
            case MaterialKind::Emitter:
                break;
        }
        if (m.coat) {
            const auto coat = pick_u < c;
            const V3 cl = ggx_reflect_sample(b, s1, s2, F(m.coat_alpha));
            a = V3{select(coat, cl.x, a.x), select(coat, cl.y, a.y), select(coat, cl.z, a.z)};
        }
        store_rows(l, i, lanes, a.x, a.y, a.z);
        store_lanes(pdf, i, lanes, full_pdf(m, a, b, e));
    });
}

}  // namespace render_detail
PATINA_END_TARGET
