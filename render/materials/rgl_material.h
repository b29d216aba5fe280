// The RGL material: a measured RGL .bsdf file (Dupuy & Jakob 2018) evaluated by the format's
// own rule (brdf/rgl/rgl_eval.h) and importance sampled by its own luminance and VNDF warps
// (brdf/rgl/rgl_sample.h), with their pdf, so MIS weighs its samples against the lights'.
// Scaled by `tint`. The file is conditioned on its incident direction: here that is v (the
// known direction) and l is the one sampled, as Mitsuba 3's `measured` takes si.wi.
// Cosine sampling (`cosine_sampling`) is kept to measure what the file's warps are worth
// (patina bench's render.rgl.sampling_vs_cosine).
#pragma once

#include <optional>

#include "brdf/rgl/rgl_eval.h"
#include "brdf/rgl/rgl_sample.h"
#include "fit/microfacet.h"

namespace patina {

struct RglMaterial {
    const RglView* rgl = nullptr;
    float tint[3] = {1, 1, 1};
    // the GGX roughness of the lobe fitted to the file's peak (as a table's sampling proxy,
    // python/patina/render/materials.py): what the radiance cache and the guide decide by
    float lobe_alpha = 0.2f;
    bool cosine_sampling = false;
    static constexpr bool picks_lobe = false;
    static constexpr bool transmits = false;
    std::optional<float> reflection_alpha() const { return lobe_alpha; }
    float highlight_alpha() const { return kInfinity; }  // no analytic lobe to place, as a table
};

}  // namespace patina

PATINA_BEGIN_TARGET
namespace rgl_material {
// The SIMD width of a float vector type: the RGL blocks are templates on it.
template <class F>
constexpr int lanes = static_cast<int>(sizeof(F) / sizeof(float));
}  // namespace rgl_material

namespace materials {

template <class F>
PATINA_INLINE Vec3<F> eval(const RglMaterial& m, const Vec3<F>& l, const Vec3<F>& v, F) {
    RglHints hints;
    F rgb[kRglChannels];
    rgl_eval_block<rgl_material::lanes<F>>(*m.rgl, v, l, hints, rgb);
    return Vec3<F>{rgb[0] * F(m.tint[0]), rgb[1] * F(m.tint[1]), rgb[2] * F(m.tint[2])};
}

template <class F>
PATINA_INLINE F pdf(const RglMaterial& m, const Vec3<F>& l, const Vec3<F>& v, F) {
    if (m.cosine_sampling) return microfacet::lambert_pdf(v, l);
    RglHints hints;
    return rgl_pdf_block<rgl_material::lanes<F>>(*m.rgl, v, l, hints);
}

// Where the warps' sample falls below the horizon (pdf 0) l is the zero vector, which every
// kind's pdf and value take as 0: the sample ends its path.
template <class F>
PATINA_INLINE Vec3<F> sample(const RglMaterial& m, const Vec3<F>& v, F, F u1, F u2, F) {
    if (m.cosine_sampling) return microfacet::lambert_sample(u1, u2);
    RglHints hints;
    const RglSampled<rgl_material::lanes<F>> s = rgl_sample_block<rgl_material::lanes<F>>(*m.rgl, v, u1, u2, hints);
    const auto valid = s.pdf > F(0.0f);
    const F zero(0.0f);
    return Vec3<F>{select(valid, s.wo.x, zero), select(valid, s.wo.y, zero), select(valid, s.wo.z, zero)};
}

}  // namespace materials
PATINA_END_TARGET
