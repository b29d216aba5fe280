// The body of lobe_kernels_w{1,4,8}.cpp: defines lobe_kernels_wN() for PATINA_KERNEL_WIDTH.
#pragma once

#include "core/simd/kernel_width.h"
#include "fit/lobe_kernels.h"
#include "fit/microfacet.h"

PATINA_BEGIN_TARGET
namespace {
using namespace kernel_width;

// A lobe as base x (m + (1 - m) w): for the Schlick-Fresnel lobes (GGX, Beckmann,
// Blinn-Phong, Ashikhmin-Shirley) w is f0, base the lobe at f0 = 1 and m = (1 - cos_d)^5,
// since f0 + (1 - f0) m = m + (1 - m) f0; for Ward and Lafortune, linear in their weight,
// m = 0. With the shape shared by the channels (the usual colour model), the geometry is
// evaluated once for all three.
struct LobeParts {
    F base, m;
};

LobeParts lobe_parts(const MixtureParams& p, int l, const V3& a, const V3& b, F shape, F shape_y) {
    using namespace microfacet;
    const F zero(0.0f), one(1.0f);
    switch (p.kind) {
        case LobeKind::GGX: {
            // ggx_eval's D G2 / (4 cos_i cos_o) with one division: for s = a + b, cos^2(theta_h)
            // = (cos_i + cos_o)^2 / |s|^2 and cos_d = |s| / 2; G2 / (4 cos_i cos_o) =
            // 1 / (2 (cos_o sqrt(cos_i^2 (1 - a2) + a2) + cos_i sqrt(cos_o^2 (1 - a2) + a2)))
            // (height-correlated Smith). The loss is bound by divisions at width 8.
            const F a2 = shape * shape, ci = a.z, co = b.z;
            const F sx = a.x + b.x, sy = a.y + b.y, sz = ci + co;
            const F len2 = sx * sx + sy * sy + sz * sz;
            const F t = madd(sz * sz, a2, sx * sx + sy * sy);  // |s|^2 (cos^2(theta_h) (a2 - 1) + 1), no cancellation
            const F vis = co * sqrt_exact(madd(ci * ci, one - a2, a2)) + ci * sqrt_exact(madd(co * co, one - a2, a2));
            const F base = a2 * len2 * len2 / (F(2.0f * kPi) * t * t * vis);
            return {select((ci > zero) & (co > zero), base, zero), fresnel_schlick(zero, F(0.5f) * sqrt_exact(len2))};
        }
        case LobeKind::Beckmann: {
            const V3 h = half_vector(a, b);
            return {microfacet_value(a, b, beckmann_d(h.z, shape), beckmann_g2(a.z, b.z, shape), one),
                    fresnel_schlick(zero, mean_cos_d(a, b, h))};
        }
        case LobeKind::BlinnPhong: {
            const V3 h = half_vector(a, b);
            const F alpha = sqrt_exact(F(2.0f) / (shape + F(2.0f)));
            return {microfacet_value(a, b, blinn_phong_d(h.z, shape), beckmann_g2(a.z, b.z, alpha), one),
                    fresnel_schlick(zero, mean_cos_d(a, b, h))};
        }
        case LobeKind::AshikhminShirley: {
            const V3 h = half_vector(a, b);
            const F kh = mean_cos_d(a, b, h);
            return {ashikhmin_shirley_eval(a, b, shape, shape_y, one), fresnel_schlick(zero, kh)};
        }
        case LobeKind::Ward:
            return {ward_eval(a, b, shape, shape_y, one), zero};
        case LobeKind::Lafortune: {
            const float* c = p.lafortune_c[l];
            return {lafortune_eval(a, b, F(c[0]), F(c[1]), F(c[2]), shape, (shape + F(2.0f)) * F(0.5f * kInvPi)), zero};
        }
    }
    return {zero, zero};
}

// The mixture's RGB value: Lambert, the lobes, and the coat over them.
void mixture_rgb(const MixtureParams& p, const V3& a, const V3& b, F f[3]) {
    for (int ch = 0; ch < 3; ++ch) f[ch] = microfacet::lambert_eval(a, b, F(p.rho[ch]));
    for (int l = 0; l < p.lobes; ++l) {
        const float* s = p.shape[l];
        const float* sy = p.shape_y[l];
        const bool shared = s[0] == s[1] && s[1] == s[2] && sy[0] == sy[1] && sy[1] == sy[2];
        LobeParts parts = lobe_parts(p, l, a, b, F(s[0]), F(sy[0]));
        for (int ch = 0; ch < 3; ++ch) {
            if (!shared && ch > 0) parts = lobe_parts(p, l, a, b, F(s[ch]), F(sy[ch]));
            f[ch] = madd(parts.base, madd(F(1.0f) - parts.m, F(p.weight[l][ch]), parts.m), f[ch]);
        }
    }
    if (p.coat) {
        const F eta(p.coat_eta);
        const F through = (F(1.0f) - microfacet::fresnel_dielectric(a.z, eta)) *
                          (F(1.0f) - microfacet::fresnel_dielectric(b.z, eta));
        const F coat = microfacet::coat_eval(a, b, F(p.coat_alpha), eta);
        for (int ch = 0; ch < 3; ++ch) f[ch] = madd(f[ch], through, coat);
    }
}

void eval_mixture(const MixtureParams& p, const float* wi, const float* wo, float* out, size_t n) {
    enter_kernel();
    for_blocks(n, [&](size_t i, int lanes) {
        const V3 a = load_rows(wi, i, lanes), b = load_rows(wo, i, lanes);
        F f[3];
        mixture_rgb(p, a, b, f);
        store_rows(out, i, lanes, f[0], f[1], f[2]);
    });
}

void sample_lobe(LobeKind kind, float shape, const float* wi, const float* u1, const float* u2, float* wo, float* pdf,
                 size_t n) {
    enter_kernel();
    for_blocks(n, [&](size_t i, int lanes) {
        const V3 a = load_rows(wi, i, lanes);
        const F s1 = load_lanes(u1, i, lanes), s2 = load_lanes(u2, i, lanes), k(shape);
        V3 s{F(0.0f), F(0.0f), F(1.0f)};
        F p(0.0f);
        switch (kind) {
            case LobeKind::GGX:
                s = microfacet::ggx_sample(a, s1, s2, k);
                p = microfacet::ggx_pdf(a, s, k);
                break;
            case LobeKind::Beckmann:
                s = microfacet::beckmann_sample(a, s1, s2, k);
                p = microfacet::beckmann_pdf(a, s, k);
                break;
            case LobeKind::BlinnPhong:
                s = microfacet::blinn_phong_sample(a, s1, s2, k);
                p = microfacet::blinn_phong_pdf(a, s, k);
                break;
            case LobeKind::Ward:
                s = microfacet::ward_sample(a, s1, s2, k, k);
                p = microfacet::ward_pdf(a, s, k, k);
                break;
            case LobeKind::AshikhminShirley:
                s = microfacet::ashikhmin_shirley_sample(a, s1, s2, k, k);
                p = microfacet::ashikhmin_shirley_pdf(a, s, k, k);
                break;
            case LobeKind::Lafortune:
                s = microfacet::lafortune_sample(a, s1, s2, F(-1.0f), F(-1.0f), F(1.0f), k);
                p = microfacet::lafortune_pdf(a, s, F(-1.0f), F(-1.0f), F(1.0f), k);
                break;
        }
        store_rows(wo, i, lanes, s.x, s.y, s.z);
        store_lanes(pdf, i, lanes, p);
    });
}

void sample_ward(float ax, float ay, const float* wi, const float* u1, const float* u2, float* wo, float* pdf,
                 size_t n) {
    enter_kernel();
    for_blocks(n, [&](size_t i, int lanes) {
        const V3 a = load_rows(wi, i, lanes);
        const V3 s = microfacet::ward_sample(a, load_lanes(u1, i, lanes), load_lanes(u2, i, lanes), F(ax), F(ay));
        store_rows(wo, i, lanes, s.x, s.y, s.z);
        store_lanes(pdf, i, lanes, microfacet::ward_pdf(a, s, F(ax), F(ay)));
    });
}

void sample_lambert(const float* u1, const float* u2, float* wo, float* pdf, size_t n) {
    enter_kernel();
    for_blocks(n, [&](size_t i, int lanes) {
        const V3 s = microfacet::lambert_sample(load_lanes(u1, i, lanes), load_lanes(u2, i, lanes));
        store_rows(wo, i, lanes, s.x, s.y, s.z);
        store_lanes(pdf, i, lanes, s.z * F(kInvPi));
    });
}

template <bool kLogSpace>
double loss_blocks(const MixtureParams& p, const float* wi, const float* wo, const float* measured,
                   const float* weight, size_t n) {
    // lanes accumulate in float for up to kFlush blocks, then into one double: the
    // horizontal sum per block cost as much as a lobe at width 8
    constexpr int kFlush = 64;
    double total = 0;
    F acc(0.0f);
    int blocks = 0;
    auto flush = [&] {
        float lane_sums[N];
        store_n<N>(lane_sums, acc);
        for (int j = 0; j < N; ++j) total += lane_sums[j];
        acc = F(0.0f);
        blocks = 0;
    };
    for_blocks(n, [&](size_t i, int lanes) {
        const V3 a = load_rows(wi, i, lanes), b = load_rows(wo, i, lanes), m = load_rows(measured, i, lanes);
        const F w = load_lanes(weight, i, lanes);  // padded lanes weigh 0
        const F mc[3] = {m.x, m.y, m.z};
        F model[3];
        mixture_rgb(p, a, b, model);
        for (int ch = 0; ch < 3; ++ch) {
            F d;
            if constexpr (kLogSpace) d = fast_log(madd(model[ch], w, F(1.0f))) - fast_log(madd(mc[ch], w, F(1.0f)));
            else d = (model[ch] - mc[ch]) * w;
            acc = madd(d, d, acc);
        }
        if (++blocks == kFlush) flush();
    });
    flush();
    return total;
}

double loss_mixture(const MixtureParams& p, const float* wi, const float* wo, const float* measured,
                        const float* weight, size_t n, bool log_space) {
    enter_kernel();
    return log_space ? loss_blocks<true>(p, wi, wo, measured, weight, n)
                     : loss_blocks<false>(p, wi, wo, measured, weight, n);
}

}  // namespace
PATINA_END_TARGET
