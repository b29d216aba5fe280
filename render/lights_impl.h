// Light selection and the quad lights' density for the integrator (included by
// integrator_w{1,4,8}.cpp). The lights themselves are sampled W points at a time, grouped by
// the light each point chose (integrator_impl.h, env_impl.h).
#pragma once

#include <algorithm>
#include <cmath>

#include "core/constants.h"
#include "render/scene.h"

PATINA_BEGIN_TARGET
namespace render_detail {

inline float dot3(const float* a, const float* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Each light's estimated irradiance at point p (the selection weights); returns their sum.
inline float selection_weights(const RenderScene& s, const float* p, float* w) {
    float sum = 0;
    for (size_t k = 0; k < s.selection.size(); ++k) {
        const RenderScene::Selection& sel = s.selection[k];
        float wk = sel.weight;
        if (sel.local) {
            const float d[3] = {sel.center[0] - p[0], sel.center[1] - p[1], sel.center[2] - p[2]};
            wk = sel.weight / (4.0f * kPi * std::max(dot3(d, d), sel.size2));
        }
        w[k] = wk;
        sum += wk;
    }
    return sum;
}

// The probability that a shading point at p picks light k.
inline float selection_probability(const RenderScene& s, const float* p, int k) {
    float w[64];
    std::vector<float> many;
    float* weights = w;
    if (s.selection.size() > 64) {
        many.resize(s.selection.size());
        weights = many.data();
    }
    const float sum = selection_weights(s, p, weights);
    return sum > 0 ? weights[k] / sum : 0.0f;
}
inline int light_count(const RenderScene& s) { return static_cast<int>(s.selection.size()); }

// Whether any light (or the environment) can light anything.
inline bool lights_emit(const RenderScene& s) {
    for (const RenderScene::Selection& sel : s.selection)
        if (sel.weight > 0) return true;
    return false;
}

// Density (solid angle at the shading point `from`, selection included) with which light sampling
// reaches area light `li` (a quad or triangles: uniform by area) at distance `dist`, where
// the light's surface has cosine `facing` with the direction.
inline float area_light_pdf(const RenderScene& s, const float* from, int li, float facing, float dist) {
    const float cos_l = std::abs(facing);
    if (cos_l <= 0) return 0;
    return selection_probability(s, from, li) * dist * dist / (s.lights[li].area * cos_l);
}

struct LightSample {
    float dir[3] = {0, 0, 0};  // unit, from the shading point
    float dist = 0;            // to the light point (inf: environment)
    float rgb[3] = {0, 0, 0};  // radiance (W/(m^2 sr)), or intensity / dist^2 for a point light
    float pdf = 0;             // solid-angle pdf including selection; for a point light the selection probability
    bool delta = false;        // a point light: no MIS
};

// Veach's power heuristic a^2 / (a^2 + b^2), written so near-delta pdfs cannot overflow.
inline float power_heuristic(float a, float b) {
    if (!(a > 0)) return 0.0f;
    if (!(b > 0)) return 1.0f;
    const float r = b / a;
    return 1.0f / (1.0f + r * r);
}

}  // namespace render_detail
PATINA_END_TARGET
