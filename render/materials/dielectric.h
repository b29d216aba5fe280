// A rough dielectric interface (Walter, Marschner, Li, Torrance 2007, "Microfacet models
// for refraction through rough surfaces"), GGX with height-correlated Smith masking, in the
// generalized-half-vector form pbrt-v4 uses. Local frame: z = the normal on the viewer's
// side, v (towards the viewer) has v.z > 0; l.z > 0 is reflection, l.z < 0 transmission.
// eta = index beyond the surface / index on the viewer's side. Radiance is carried (the
// transmitted value is divided by eta^2), so a closed glass object in a uniform
// environment shows exactly that environment.
#pragma once

#include <optional>

#include "fit/microfacet.h"
#include "render/materials/ggx_aniso.h"

namespace patina {

// The material: its GGX roughness and its index (inside / outside). The shading points
// carry the relative index the ray sees (eta or 1 / eta by the side it arrives from).
struct Dielectric {
    float alpha = 0.1f;
    float eta = 1;
    static constexpr bool picks_lobe = true;  // reflection against transmission
    static constexpr bool transmits = true;
    std::optional<float> reflection_alpha() const { return std::nullopt; }  // glass: no lobe for the cache
    float highlight_alpha() const { return alpha; }
};

}  // namespace patina

PATINA_BEGIN_TARGET
namespace dielectric {

// The value (f) and the sampling density (pdf) of l given v.
template <class F>
PATINA_INLINE void eval_pdf(const Vec3<F>& l, const Vec3<F>& v, F alpha, F eta, F& f, F& pdf) {
    const auto reflect = l.z > F(0.0f);
    const F etap = select(reflect, F(1.0f), eta);
    F mx = madd(l.x, etap, v.x), my = madd(l.y, etap, v.y), mz = madd(l.z, etap, v.z);
    const F len2 = mx * mx + my * my + mz * mz;
    const F inv = select(mz < F(0.0f), F(-1.0f), F(1.0f)) / sqrt_exact(max(len2, F(1e-30f)));
    const Vec3<F> m{mx * inv, my * inv, mz * inv};
    const F lm = dot(l, m), vm = dot(v, m);
    const auto valid = (len2 > F(1e-20f)) & (l.z != F(0.0f)) & (lm * l.z > F(0.0f)) & (vm > F(0.0f)) & (v.z > F(0.0f));
    const F al = abs(l.z);
    // D and G from the components of m, l, v (not from cosines near 1, which lose the
    // few ulps a very smooth lobe lives in), the same D as the density of m
    const F d = ggx_aniso::d(m, alpha, alpha);
    const Vec3<F> lu{l.x, l.y, al};
    const F g = ggx_aniso::g2(lu, v, alpha, alpha);
    const F fr = microfacet::fresnel_dielectric(vm, eta);
    const F f_r = d * g * fr / (F(4.0f) * al * v.z);
    const F pm = ggx_aniso::visible_pdf(v, m, alpha, alpha);  // the density of m
    const F pdf_r = pm / (F(4.0f) * vm) * fr;
    const F denom_root = lm + vm / etap;
    const F denom = denom_root * denom_root;
    const F t = F(1.0f) - fr;
    const F f_t = d * g * t * abs(lm * vm) / (al * v.z * denom) / (etap * etap);
    const F pdf_t = pm * abs(lm) / denom * t;
    f = select(valid, select(reflect, f_r, f_t), F(0.0f));
    pdf = select(valid, select(reflect, pdf_r, pdf_t), F(0.0f));
}

// l from v: a microfacet normal visible from v, then reflection with probability F(v.h),
// else refraction (total internal reflection has F = 1).
template <class F>
PATINA_INLINE Vec3<F> sample(const Vec3<F>& v, F pick, F u1, F u2, F alpha, F eta) {
    const Vec3<F> h = ggx_aniso::sample_visible(v, u1, u2, alpha, alpha);
    const F vh = dot(v, h);
    const F fr = microfacet::fresnel_dielectric(max(vh, F(0.0f)), eta);
    const Vec3<F> r = microfacet::reflect(v, h);
    const F inv_eta = F(1.0f) / eta;
    const F sin2_t = (F(1.0f) - vh * vh) * inv_eta * inv_eta;
    const F cos_t = sqrt_exact(max(F(1.0f) - sin2_t, F(0.0f)));
    const F k = vh * inv_eta - cos_t;
    const Vec3<F> t{madd(k, h.x, -v.x * inv_eta), madd(k, h.y, -v.y * inv_eta), madd(k, h.z, -v.z * inv_eta)};
    const auto refl = pick < fr;
    // drop (l = 0, pdf 0) what eval_pdf would count on the other side: a microfacet facing
    // away from v, a reflection below the surface, a refraction above it
    const auto keep = (vh > F(0.0f)) & select(refl, r.z > F(0.0f), t.z < F(0.0f));
    const F zero(0.0f);
    return Vec3<F>{select(keep, select(refl, r.x, t.x), zero), select(keep, select(refl, r.y, t.y), zero),
                   select(keep, select(refl, r.z, t.z), zero)};
}

}  // namespace dielectric

namespace materials {

template <class F>
PATINA_INLINE Vec3<F> eval(const Dielectric& m, const Vec3<F>& l, const Vec3<F>& v, F eta) {
    F value, pdf;
    dielectric::eval_pdf(l, v, F(m.alpha), eta, value, pdf);
    return Vec3<F>{value, value, value};
}

template <class F>
PATINA_INLINE F pdf(const Dielectric& m, const Vec3<F>& l, const Vec3<F>& v, F eta) {
    F value, pdf;
    dielectric::eval_pdf(l, v, F(m.alpha), eta, value, pdf);
    return pdf;
}

template <class F>
PATINA_INLINE Vec3<F> sample(const Dielectric& m, const Vec3<F>& v, F pick, F u1, F u2, F eta) {
    return dielectric::sample(v, pick, u1, u2, F(m.alpha), eta);
}

}  // namespace materials
PATINA_END_TARGET
