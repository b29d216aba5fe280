// Light sampling and emission for the integrator (included by render_w{1,4,8}.cpp): the
// environment (lat-long map or constant), point lights and quad area lights, one shading
// point at a time. (Coherent SIMD light sampling is the luminaires issue's work.)
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "render/scene.h"

PATINA_BEGIN_TARGET
namespace render_detail {

constexpr float kPiF = 3.14159265358979323846f;
constexpr float kInfF = std::numeric_limits<float>::infinity();

inline float dot3(const float* a, const float* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// The index i with cdf[i] <= u < cdf[i + 1] among count cells (cdf has count + 1 values).
inline int cdf_cell(const float* cdf, int count, float u) {
    const int i = static_cast<int>(std::upper_bound(cdf, cdf + count + 1, u) - cdf) - 1;
    return std::clamp(i, 0, count - 1);
}

// World direction <-> the map's own frame, turned by env.rotation about +y.
inline void env_to_map(const Environment& env, const float* d, float* m) {
    const float c = std::cos(env.rotation), s = std::sin(env.rotation);
    m[0] = c * d[0] - s * d[2];
    m[1] = d[1];
    m[2] = s * d[0] + c * d[2];
}
inline void map_to_env(const Environment& env, const float* m, float* d) {
    const float c = std::cos(env.rotation), s = std::sin(env.rotation);
    d[0] = c * m[0] + s * m[2];
    d[1] = m[1];
    d[2] = -s * m[0] + c * m[2];
}

// (u, v) in [0, 1)^2 of a unit map-frame direction: phi = atan2(x, -z), theta = acos(y).
inline void map_uv(const float* m, float& u, float& v) {
    u = std::atan2(m[0], -m[2]) * (0.5f / kPiF);
    if (u < 0) u += 1.0f;
    if (u >= 1.0f) u = 0.0f;
    v = std::acos(std::clamp(m[1], -1.0f, 1.0f)) / kPiF;
}

// Radiance arriving from world direction d (unit), bilinear between pixel centres.
inline void env_radiance(const Environment& env, const float* d, float* rgb) {
    if (!env.present) {
        rgb[0] = rgb[1] = rgb[2] = 0;
        return;
    }
    if (!env.is_map) {
        for (int k = 0; k < 3; ++k) rgb[k] = env.constant[k] * env.intensity;
        return;
    }
    float m[3], u, v;
    env_to_map(env, d, m);
    map_uv(m, u, v);
    const float x = u * env.width - 0.5f, y = std::clamp(v * env.height - 0.5f, 0.0f, env.height - 1.0f);
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(y);
    const float fx = x - x0, fy = y - y0;
    const int xa = (x0 + env.width) % env.width, xb = (x0 + 1) % env.width, y1 = std::min(y0 + 1, env.height - 1);
    const float* p00 = env.rgb + 3 * (static_cast<size_t>(y0) * env.width + xa);
    const float* p01 = env.rgb + 3 * (static_cast<size_t>(y0) * env.width + xb);
    const float* p10 = env.rgb + 3 * (static_cast<size_t>(y1) * env.width + xa);
    const float* p11 = env.rgb + 3 * (static_cast<size_t>(y1) * env.width + xb);
    for (int k = 0; k < 3; ++k) {
        const float top = p00[k] + fx * (p01[k] - p00[k]), bottom = p10[k] + fx * (p11[k] - p10[k]);
        rgb[k] = env.intensity * (top + fy * (bottom - top));
    }
}

// Solid-angle density with which env_sample picks world direction d.
inline float env_pdf(const Environment& env, const float* d) {
    if (!env.present) return 0;
    if (!env.is_map) return 1.0f / (4 * kPiF);
    float m[3], u, v;
    env_to_map(env, d, m);
    map_uv(m, u, v);
    const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - m[1] * m[1]));
    if (sin_theta <= 0) return 0;
    const int c = std::min(static_cast<int>(u * env.width), env.width - 1);
    const int r = std::min(static_cast<int>(v * env.height), env.height - 1);
    return env.pixel_pdf[static_cast<size_t>(r) * env.width + c] / (2 * kPiF * kPiF * sin_theta);
}

// A direction from the environment's distribution; returns its solid-angle pdf.
inline float env_sample(const Environment& env, float u1, float u2, float* d) {
    if (!env.is_map) {
        const float z = 1 - 2 * u1, r = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 2 * kPiF * u2;
        d[0] = r * std::cos(phi);
        d[1] = z;
        d[2] = r * std::sin(phi);
        return 1.0f / (4 * kPiF);
    }
    const int h = env.height, w = env.width;
    const int r = cdf_cell(env.row_cdf.data(), h, u1);
    const float r0 = env.row_cdf[r], r1 = env.row_cdf[r + 1];
    const float fv = r1 > r0 ? std::clamp((u1 - r0) / (r1 - r0), 0.0f, 0.999999f) : 0.5f;
    const float* row = env.col_cdf.data() + static_cast<size_t>(r) * (w + 1);
    const int c = cdf_cell(row, w, u2);
    const float fu = row[c + 1] > row[c] ? std::clamp((u2 - row[c]) / (row[c + 1] - row[c]), 0.0f, 0.999999f) : 0.5f;
    const float u = (c + fu) / w, v = (r + fv) / h;
    const float theta = kPiF * v, phi = 2 * kPiF * u;
    const float sin_theta = std::sin(theta);
    const float m[3] = {std::sin(phi) * sin_theta, std::cos(theta), -std::cos(phi) * sin_theta};
    map_to_env(env, m, d);
    if (sin_theta <= 0) return 0;
    return env.pixel_pdf[static_cast<size_t>(r) * w + c] / (2 * kPiF * kPiF * sin_theta);
}

inline float selection_probability(const RenderScene& s, int light) {
    return s.light_cdf[light + 1] - s.light_cdf[light];
}
inline int light_count(const RenderScene& s) { return static_cast<int>(s.light_cdf.size()) - 1; }

// Density (solid angle at the shading point, selection included) of reaching quad light `li`
// at distance `dist` along unit `d` by light sampling.
inline float quad_pdf(const RenderScene& s, int li, const float* d, float dist) {
    const Light& l = s.lights[li];
    const float cos_l = std::abs(dot3(d, l.normal));
    if (cos_l <= 0) return 0;
    return selection_probability(s, li) * dist * dist / (l.area * cos_l);
}

struct LightSample {
    float dir[3];    // unit, from the shading point
    float dist;      // to the light point (inf: environment)
    float rgb[3];    // radiance (W/(m^2 sr)), or intensity / dist^2 for a point light
    float pdf;       // solid-angle pdf including selection; for a point light the selection probability
    bool delta;      // a point light: no MIS
};

// One light sample for shading point p; false when nothing can be sampled there.
inline bool sample_light(const RenderScene& s, const float* p, float u_pick, float u1, float u2, LightSample& ls) {
    const int count = light_count(s);
    if (count <= 0 || s.light_cdf.back() <= 0) return false;
    const int li = cdf_cell(s.light_cdf.data(), count, u_pick);
    const float sel = selection_probability(s, li);
    if (sel <= 0) return false;
    if (li == static_cast<int>(s.lights.size())) {  // the environment
        const float pdf = env_sample(s.env, u1, u2, ls.dir);
        if (!(pdf > 0)) return false;
        env_radiance(s.env, ls.dir, ls.rgb);
        ls.dist = kInfF;
        ls.pdf = pdf * sel;
        ls.delta = false;
        return true;
    }
    const Light& l = s.lights[li];
    float target[3];
    if (l.kind == LightKind::Point) {
        for (int k = 0; k < 3; ++k) target[k] = l.position[k];
    } else {
        const float a = 2 * u1 - 1, b = 2 * u2 - 1;
        for (int k = 0; k < 3; ++k) target[k] = l.position[k] + a * l.u[k] + b * l.v[k];
    }
    float d[3] = {target[0] - p[0], target[1] - p[1], target[2] - p[2]};
    const float dist2 = dot3(d, d);
    if (!(dist2 > 0)) return false;
    const float dist = std::sqrt(dist2);
    for (int k = 0; k < 3; ++k) ls.dir[k] = d[k] / dist;
    ls.dist = dist;
    if (l.kind == LightKind::Point) {
        for (int k = 0; k < 3; ++k) ls.rgb[k] = l.power[k] / dist2;
        ls.pdf = sel;
        ls.delta = true;
        return true;
    }
    const float facing = -dot3(ls.dir, l.normal);
    if (!(facing > 0) && !(l.two_sided && facing < 0)) return false;
    for (int k = 0; k < 3; ++k) ls.rgb[k] = l.power[k];
    ls.pdf = quad_pdf(s, li, ls.dir, dist);
    ls.delta = false;
    return ls.pdf > 0;
}

// Veach's power heuristic a^2 / (a^2 + b^2), written so near-delta pdfs cannot overflow.
inline float power_heuristic(float a, float b) {
    if (!(a > 0)) return 0.0f;
    if (!(b > 0)) return 1.0f;
    const float r = b / a;
    return 1.0f / (1.0f + r * r);
}

}  // namespace render_detail
PATINA_END_TARGET
