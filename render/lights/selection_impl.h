// Light selection (docs/render.md, "Light sampling"): which light a shading point samples,
// and with what probability. Each point picks a light in proportion to its estimated
// irradiance there (the selection weight, RenderScene::Selection): an area light's flux
// over 4 pi d^2, a delta light's intensity towards the point over d^2 (its profile
// included: a luminaire that sends the point nothing is never picked, so no sample is
// wasted on it), the sun's and the environment's irradiance. The pick computes the weights
// N points at a time; an MIS weight asks for one point's probability (selection_probability,
// at width 1). The weight is one function of the width, every lane the same bits at every
// width, and the sums add the lights in the same order: the pick's probability and the MIS
// weight's are the same number.
#pragma once

#include <algorithm>
#include <vector>

#include "core/constants.h"
#include "core/simd/kernel_width.h"
#include "core/vec3.h"
#include "render/lights/delta_intensity_impl.h"
#include "render/scene.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// Light k's selection weight at W points p.
template <int W>
PATINA_INLINE vfloat<W> selection_weight(const RenderScene& s, size_t k, const Vec3<vfloat<W>>& p) {
    using FW = vfloat<W>;
    const RenderScene::Selection& sel = s.selection[k];
    if (!sel.local) return FW(sel.weight);
    const FW dx = FW(sel.center[0]) - p.x, dy = FW(sel.center[1]) - p.y, dz = FW(sel.center[2]) - p.z;
    const FW d2 = dx * dx + dy * dy + dz * dz;
    const FW near = max(d2, FW(sel.size2));
    if (!sel.delta) return FW(sel.weight) / (FW(4.0f * kPi) * near);
    // the direction from the light rounded as sample_light_group rounds it (-(d / |d|)), so
    // the weight is 0 exactly where the sample's intensity is; a point at the light gets
    // none (its sample has pdf 0), and its NaN direction is not read
    const FW inv = FW(1.0f) / sqrt_exact(d2);
    const FW intensity = delta_intensity<W>(s.lights[k], Vec3<FW>{-(dx * inv), -(dy * inv), -(dz * inv)});
    return select(d2 > FW(0.0f), FW(sel.weight) * intensity / near, FW(0.0f));
}

// Each light's selection weight at point p (into w); returns their sum. A light alone is
// every point's pick, so its weight is taken as 1 and not computed: a scene with one light
// pays nothing for the selection (where a delta light's weight would be 0 it sends the point
// nothing, and its sample is 0 all the same).
inline float selection_weights(const RenderScene& s, const Vec3f& p, float* w) {
    if (s.selection.size() == 1) return w[0] = 1.0f;
    float sum = 0;
    for (size_t k = 0; k < s.selection.size(); ++k) {
        w[k] = selection_weight<1>(s, k, p);
        sum += w[k];
    }
    return sum;
}

// A light's share of the weights: its probability of being picked.
inline float selection_share(float weight, float sum) { return sum > 0 ? weight / sum : 0.0f; }

// The probability that a shading point at p picks light k.
inline float selection_probability(const RenderScene& s, const Vec3f& p, int k) {
    float w[64];
    std::vector<float> many;
    float* weights = w;
    if (s.selection.size() > 64) {
        many.resize(s.selection.size());
        weights = many.data();
    }
    const float sum = selection_weights(s, p, weights);
    return selection_share(weights[k], sum);
}

inline int light_count(const RenderScene& s) { return static_cast<int>(s.selection.size()); }

// Whether a point's selection depends on where it is: with several lights, one of them local
// (else the points' positions are not read).
inline bool selection_is_local(const RenderScene& s) {
    if (s.selection.size() < 2) return false;
    for (const RenderScene::Selection& sel : s.selection)
        if (sel.local) return true;
    return false;
}

// The selection weights of np points at `pos` ((np, 3) rows; null when not
// selection_is_local, as no weight then reads a position), N points at a time, as
// selection_weights computes them: light k's weight of point q at w[k * np + q], and their
// sum at sum[q], added in the same order (the same bits).
inline void points_selection_weights(const RenderScene& s, const float* pos, size_t np, float* w, float* sum) {
    const size_t count = s.selection.size();
    if (count == 1) {
        std::fill(w, w + np, 1.0f);
        std::fill(sum, sum + np, 1.0f);
        return;
    }
    for_blocks(np, [&](size_t i, int lanes) {
        const V3 p = pos ? load_rows(pos, i, lanes) : V3{F(0.0f), F(0.0f), F(0.0f)};
        F total(0.0f);
        for (size_t k = 0; k < count; ++k) {
            const F wk = selection_weight<N>(s, k, p);
            store_lanes(w + k * np, i, lanes, wk);
            total = total + wk;
        }
        store_lanes(sum, i, lanes, total);
    });
}

// The light a point picks with uniform `pick` from its weights w[0], w[stride], ... (count
// of them, summing to `sum`), and the probability of that pick (selection_probability's).
inline int pick_light(const float* w, size_t stride, int count, float sum, float pick, float& probability) {
    float acc = 0, target = pick * sum;
    int k = 0;
    for (; k < count - 1; ++k) {
        if (target < acc + w[k * stride]) break;
        acc += w[k * stride];
    }
    while (k > 0 && !(w[k * stride] > 0)) --k;  // never a light of zero weight (rounding at the top)
    probability = selection_share(w[k * stride], sum);
    return k;
}

// The render kernels' light_selection (for tests): the probability that a shading point at
// points[q] picks light k (the environment last) as the pick computes it, N points at a time,
// into pick[q * count + k], and as an MIS weight does, one point at a time, into mis.
inline void light_selection(const RenderScene& s, const float* points, size_t n, float* pick, float* mis) {
    enter_kernel();
    const size_t count = s.selection.size();
    std::vector<float> w((count + 1) * n);
    float* sum = w.data() + count * n;
    points_selection_weights(s, points, n, w.data(), sum);
    for (size_t q = 0; q < n; ++q)
        for (size_t k = 0; k < count; ++k) {
            pick[q * count + k] = selection_share(w[k * n + q], sum[q]);
            mis[q * count + k] = selection_probability(s, load_vec3(points + 3 * q), static_cast<int>(k));
        }
}

// Whether any light (or the environment) can light anything.
inline bool lights_emit(const RenderScene& s) {
    for (const RenderScene::Selection& sel : s.selection)
        if (sel.weight > 0) return true;
    return false;
}

}  // namespace render_detail
PATINA_END_TARGET
