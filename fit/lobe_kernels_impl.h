// The body of lobe_w{1,4,8}.cpp: defines lobe_kernels_wN() for PATINA_KERNEL_WIDTH.
#pragma once

#include <algorithm>

#include "core/simd/rows.h"
#include "core/simd/upper_state.h"
#include "fit/lobe_kernels.h"
#include "fit/microfacet.h"

#ifndef PATINA_KERNEL_WIDTH
#error "define PATINA_KERNEL_WIDTH before including lobe_kernels_impl.h"
#endif

PATINA_BEGIN_TARGET
namespace {

constexpr int W = PATINA_KERNEL_WIDTH;
using F = vfloat<W>;

// Runs body(i, lanes) over blocks of W rows; rows past n read from zero-padded copies.
template <class Body>
void for_blocks(size_t n, Body body) {
    if constexpr (W < 8) clear_upper_state();
    for (size_t i = 0; i < n; i += W) body(i, static_cast<int>(std::min<size_t>(W, n - i)));
}

// Rows and lanes of the (n, 3) and (n,) arrays, the last block through padded copies (core/simd/rows.h).
Dir3<F> load_rows(const float* p, size_t i, int lanes) {
    Dir3<F> d;
    rows::load3<W>(p, i, lanes, d.x, d.y, d.z);
    return d;
}
F load_lanes(const float* p, size_t i, int lanes) { return rows::load1<W>(p, i, lanes); }
void store_rows(float* p, size_t i, int lanes, F x, F y, F z) { rows::store3<W>(p, i, lanes, x, y, z); }
void store_lanes(float* p, size_t i, int lanes, F v) { rows::store1<W>(p, i, lanes, v); }

// The mixture's value in one channel; the lobe kind is uniform, so its switch is one branch.
F mixture_channel(const MixtureParams& p, const Dir3<F>& a, const Dir3<F>& b, int ch) {
    F f = microfacet::lambert_eval(a, b, F(p.rho[ch]));
    for (int l = 0; l < p.lobes; ++l) {
        const F shape(p.shape[l][ch]), shape_y(p.shape_y[l][ch]), w(p.weight[l][ch]);
        switch (p.kind) {
            case LobeKind::GGX: f += microfacet::ggx_eval(a, b, shape, w); break;
            case LobeKind::Beckmann: f += microfacet::beckmann_eval(a, b, shape, w); break;
            case LobeKind::BlinnPhong: f += microfacet::blinn_phong_eval(a, b, shape, w); break;
            case LobeKind::Ward: f += microfacet::ward_eval(a, b, shape, shape_y, w); break;
            case LobeKind::AshikhminShirley: f += microfacet::ashikhmin_shirley_eval(a, b, shape, shape_y, w); break;
            case LobeKind::Lafortune: {
                const float* c = p.lafortune_c[l];
                const F rho = w * (shape + F(2.0f)) * F(0.5f * microfacet::kInvPi);
                f += microfacet::lafortune_eval(a, b, F(c[0]), F(c[1]), F(c[2]), shape, rho);
                break;
            }
        }
    }
    if (p.coat) {
        const F eta(p.coat_eta);
        const F through = (F(1.0f) - microfacet::fresnel_dielectric(a.z, eta)) *
                          (F(1.0f) - microfacet::fresnel_dielectric(b.z, eta));
        f = madd(f, through, microfacet::coat_eval(a, b, F(p.coat_alpha), eta));
    }
    return f;
}

void eval_mixture(const MixtureParams& p, const float* wi, const float* wo, float* out, size_t n) {
    for_blocks(n, [&](size_t i, int lanes) {
        const Dir3<F> a = load_rows(wi, i, lanes), b = load_rows(wo, i, lanes);
        store_rows(out, i, lanes, mixture_channel(p, a, b, 0), mixture_channel(p, a, b, 1), mixture_channel(p, a, b, 2));
    });
}

void sample_lobe(LobeKind kind, float shape, const float* wi, const float* u1, const float* u2, float* wo, float* pdf,
                 size_t n) {
    for_blocks(n, [&](size_t i, int lanes) {
        const Dir3<F> a = load_rows(wi, i, lanes);
        const F s1 = load_lanes(u1, i, lanes), s2 = load_lanes(u2, i, lanes), k(shape);
        Dir3<F> s{F(0.0f), F(0.0f), F(1.0f)};
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
    for_blocks(n, [&](size_t i, int lanes) {
        const Dir3<F> a = load_rows(wi, i, lanes);
        const Dir3<F> s = microfacet::ward_sample(a, load_lanes(u1, i, lanes), load_lanes(u2, i, lanes), F(ax), F(ay));
        store_rows(wo, i, lanes, s.x, s.y, s.z);
        store_lanes(pdf, i, lanes, microfacet::ward_pdf(a, s, F(ax), F(ay)));
    });
}

void sample_lambert(const float* u1, const float* u2, float* wo, float* pdf, size_t n) {
    for_blocks(n, [&](size_t i, int lanes) {
        const Dir3<F> s = microfacet::lambert_sample(load_lanes(u1, i, lanes), load_lanes(u2, i, lanes));
        store_rows(wo, i, lanes, s.x, s.y, s.z);
        store_lanes(pdf, i, lanes, s.z * F(microfacet::kInvPi));
    });
}

template <bool kLogSpace>
double loss_blocks(const MixtureParams& p, const float* wi, const float* wo, const float* measured,
                   const float* weight, size_t n) {
    double total = 0;
    for_blocks(n, [&](size_t i, int lanes) {
        const Dir3<F> a = load_rows(wi, i, lanes), b = load_rows(wo, i, lanes), m = load_rows(measured, i, lanes);
        const F w = load_lanes(weight, i, lanes);  // padded lanes weigh 0
        const F mc[3] = {m.x, m.y, m.z};
        F sum(0.0f);
        for (int ch = 0; ch < 3; ++ch) {
            const F f = mixture_channel(p, a, b, ch);
            F d;
            if constexpr (kLogSpace) d = fast_log(madd(f, w, F(1.0f))) - fast_log(madd(mc[ch], w, F(1.0f)));
            else d = (f - mc[ch]) * w;
            sum = madd(d, d, sum);
        }
        float lane_sums[W];
        store_n<W>(lane_sums, sum);
        for (int j = 0; j < W; ++j) total += lane_sums[j];
    });
    return total;
}

double loss_mixture(const MixtureParams& p, const float* wi, const float* wo, const float* measured,
                        const float* weight, size_t n, bool log_space) {
    return log_space ? loss_blocks<true>(p, wi, wo, measured, weight, n)
                     : loss_blocks<false>(p, wi, wo, measured, weight, n);
}

}  // namespace
PATINA_END_TARGET
