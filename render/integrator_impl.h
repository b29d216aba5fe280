// The wavefront path integrator (see integrator.h), compiled once per width by
// integrator_w{1,4,8}.cpp. Everything random comes from rng.h's counter-based hash, and every
// kernel it calls gives the same bits at every width, so one seed renders the same image
// at widths 1, 4 and 8 (the tests check this).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/simd/upper_state.h"
#include "render/accel/trace_kernels.h"
#include "render/camera.h"
#include "render/env_impl.h"
#include "render/integrator.h"
#include "render/lights_impl.h"
#include "render/material_impl.h"
#include "render/rng.h"

PATINA_BEGIN_TARGET
namespace render_detail {

inline const TraceKernels& trace_kernels() {
    if constexpr (W == 1) return trace_kernels_w1();
    else if constexpr (W == 4) return trace_kernels_w4();
    else return trace_kernels_w8();
}


inline void normalize3(float* a) {
    const float len = std::sqrt(dot3(a, a));
    if (len > 0)
        for (int k = 0; k < 3; ++k) a[k] /= len;
}

inline void cross3(const float* a, const float* b, float* c) {
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

inline void to_local(const ShadingPoint& sp, const float* d, float* out) {
    out[0] = dot3(d, sp.t);
    out[1] = dot3(d, sp.b);
    out[2] = dot3(d, sp.n);
}
inline void to_world(const ShadingPoint& sp, const float* l, float* out) {
    for (int k = 0; k < 3; ++k) out[k] = l[0] * sp.t[k] + l[1] * sp.b[k] + l[2] * sp.n[k];
}

// Fills the shading point of a hit: interpolated normal and tangent, frame, facing. False
// when the path ends here (the back of a one-sided surface).
inline bool make_shading_point(const RenderScene& s, int32_t prim, float u, float v, const float* org,
                               const float* dir, float t, ShadingPoint& sp) {
    const Material& m = s.materials[s.tri_material[prim]];
    const int32_t* tri = s.indices + 3 * static_cast<size_t>(prim);
    const float w0 = 1.0f - u - v;
    for (int k = 0; k < 3; ++k) {
        sp.p[k] = org[k] + t * dir[k];
        sp.ng[k] = s.tree->normals[3 * static_cast<size_t>(prim) + k];
        sp.n[k] = w0 * s.normals[3 * tri[0] + k] + u * s.normals[3 * tri[1] + k] + v * s.normals[3 * tri[2] + k];
    }
    normalize3(sp.n);
    const float wo[3] = {-dir[0], -dir[1], -dir[2]};
    const bool transmissive = m.kind == MaterialKind::Dielectric;
    // the geometric normal (from the winding) points out of a closed dielectric
    sp.eta = transmissive ? (dot3(sp.ng, wo) < 0 ? 1.0f / m.eta[0] : m.eta[0]) : 1.0f;
    if (dot3(sp.ng, wo) < 0) {
        if (!m.two_sided && !transmissive) return false;
        for (int k = 0; k < 3; ++k) {
            sp.ng[k] = -sp.ng[k];
            sp.n[k] = -sp.n[k];
        }
    } else if (dot3(sp.n, sp.ng) < 0) {
        for (int k = 0; k < 3; ++k) sp.n[k] = -sp.n[k];  // a mesh whose normals point inwards
    }
    // a shading normal facing away from the viewer (silhouettes of coarse meshes): use the true one
    if (!(dot3(sp.n, wo) > 0)) std::copy(sp.ng, sp.ng + 3, sp.n);
    if (s.tangents != nullptr) {
        for (int k = 0; k < 3; ++k)
            sp.t[k] = w0 * s.tangents[3 * tri[0] + k] + u * s.tangents[3 * tri[1] + k] + v * s.tangents[3 * tri[2] + k];
        const float along = dot3(sp.t, sp.n);
        for (int k = 0; k < 3; ++k) sp.t[k] -= along * sp.n[k];
        if (dot3(sp.t, sp.t) > 1e-12f) {
            normalize3(sp.t);
            cross3(sp.n, sp.t, sp.b);
            return true;
        }
    }
    orthonormal_frame(sp.n, sp.t, sp.b);
    return true;
}

template <class T>
inline T* grow(std::vector<T>& v, size_t n) {
    if (v.size() < n) v.resize(n);
    return v.data();
}

// out[q] = bounce_uniform(keys[q], depth, d), W keys at a time.
inline void fill_uniforms(const int32_t* keys, size_t n, int depth, RandomDim d, float* out) {
    for_blocks(n, [&](size_t i, int lanes) {
        int32_t pad[W] = {};
        std::copy(keys + i, keys + i + lanes, pad);
        rows::store1<W>(out, i, lanes, bounce_uniform_lanes(load_n<W>(pad), depth, d));
    });
}

inline LightSample load_light_sample(const PathScratch& sc, size_t q) {
    LightSample ls;
    std::copy(sc.ls_dir.data() + 3 * q, sc.ls_dir.data() + 3 * q + 3, ls.dir);
    std::copy(sc.ls_rgb.data() + 3 * q, sc.ls_rgb.data() + 3 * q + 3, ls.rgb);
    ls.dist = sc.ls_dist[q];
    ls.pdf = sc.ls_pdf[q];
    ls.delta = sc.ls_delta[q] != 0;
    return ls;
}

// Queues the shadow ray of a light sample taken at p: from p lifted by `offset` along n to
// the light's point (or to infinity), carrying the radiance `rgb` and illuminance `lux` it
// adds to path `owner` if nothing is in the way.
inline void queue_shadow_ray(PathScratch& sc, int32_t owner, const float* p, const float* n, float offset,
                             const LightSample& ls, const float* rgb, float lux) {
    float o[3], d[3] = {ls.dir[0], ls.dir[1], ls.dir[2]}, tmax = kInfinity;
    for (int k = 0; k < 3; ++k) o[k] = p[k] + offset * n[k];
    if (!std::isinf(ls.dist)) {
        // aim from the lifted origin at the light's point: seen at a grazing angle, an origin
        // lifted off the surface is much nearer the light than `dist` says
        float to[3];
        for (int k = 0; k < 3; ++k) to[k] = p[k] + ls.dir[k] * ls.dist - o[k];
        const float len = std::sqrt(dot3(to, to));
        for (int k = 0; k < 3; ++k) d[k] = to[k] / len;
        tmax = len * (1.0f - 1e-4f);
    }
    sc.shadow_path.push_back(owner);
    for (int k = 0; k < 3; ++k) {
        sc.shadow_org.push_back(o[k]);
        sc.shadow_dir.push_back(d[k]);
        sc.shadow_rgb.push_back(rgb[k]);
    }
    sc.shadow_tmax.push_back(tmax);
    sc.shadow_lux.push_back(lux);
}

inline void clear_shadow_rays(PathScratch& sc) {
    sc.shadow_path.clear();
    sc.shadow_org.clear();
    sc.shadow_dir.clear();
    sc.shadow_tmax.clear();
    sc.shadow_rgb.clear();
    sc.shadow_lux.clear();
}

// Traces the queued shadow rays, W per packet; returns sc.blocked (one byte per ray).
inline const uint8_t* trace_shadow_rays(const RenderScene& s, PathScratch& sc) {
    const size_t ns = sc.shadow_path.size();
    uint8_t* blocked = grow(sc.blocked, ns);
    if (ns > 0) {
        trace_kernels().occluded(
            *s.tree, RayBatch{sc.shadow_org.data(), sc.shadow_dir.data(), 0.0f, sc.shadow_tmax.data(), kInfinity}, blocked,
            0, ns);
        sc.rays_traced += ns;
    }
    return blocked;
}

// Misses see the environment: W directions at a time, radiance and (for MIS after a BRDF
// sample) the density of light sampling.
inline void add_environment(const RenderScene& s, PathScratch& sc, const float* dir, const float* thr,
                            const float* prev_pdf, const float* prev_pos, bool can_sample_lights, PathResult* out) {
    const size_t n = sc.misses.size();
    if (n == 0) return;
    float* d = grow(sc.miss_dir, 3 * n);
    float* le = grow(sc.miss_rgb, 3 * n);
    float* lp = grow(sc.miss_pdf, n);
    for (size_t j = 0; j < n; ++j) std::copy(dir + 3 * sc.misses[j], dir + 3 * sc.misses[j] + 3, d + 3 * j);
    if (s.env.present) for_blocks(n, [&](size_t i, int lanes) {
        const D3 w = load_dir(d, i, lanes);
        F r, g, b;
        env_w::radiance(s.env, w, r, g, b);
        rows::store3<W>(le, i, lanes, r, g, b);
        rows::store1<W>(lp, i, lanes, env_w::pdf(s.env, w));
    });
    const int env_light = static_cast<int>(s.lights.size());
    for (size_t j = 0; j < n; ++j) {
        const int32_t i = sc.misses[j];
        const bool mis = prev_pdf[i] > 0 && can_sample_lights;  // after a BRDF sample (not a camera ray)
        if (s.env.present) {
            const float w =
                mis ? power_heuristic(prev_pdf[i], selection_probability(s, prev_pos + 3 * i, env_light) * lp[j]) : 1.0f;
            for (int k = 0; k < 3; ++k) out[i].rgb[k] += thr[3 * i + k] * le[3 * j + k] * w;
        }
        // the sun's disc, where the ray goes through it
        for (size_t li = 0; li < s.lights.size(); ++li) {
            const Light& l = s.lights[li];
            if (l.kind != LightKind::Sun || !(dot3(d + 3 * j, l.direction) >= l.cos_sun)) continue;
            const float w = mis ? power_heuristic(prev_pdf[i], selection_probability(s, prev_pos + 3 * i, int(li)) /
                                                                   (2.0f * kPi * l.sun_one_minus_cos))
                                : 1.0f;
            for (int k = 0; k < 3; ++k) out[i].rgb[k] += thr[3 * i + k] * l.power[k] * w;
        }
    }
}

// A point light's relative intensity towards unit direction `out` (from the light): 1 for
// a point light, the smooth cone of a spot, the candela table of a goniometric luminaire.
PATINA_INLINE F delta_intensity(const Light& l, const D3& out) {
    if (l.kind == LightKind::Spot) {
        const F c = out.x * F(l.direction[0]) + out.y * F(l.direction[1]) + out.z * F(l.direction[2]);
        const F t = clamp((c - F(l.cos_outer)) / F(std::max(l.cos_inner - l.cos_outer, 1e-6f)), F(0.0f), F(1.0f));
        return t * t * nmadd(F(2.0f), t, F(3.0f));  // smoothstep
    }
    if (l.kind == LightKind::Goniometric) {
        const F x = out.x * F(l.axis_x[0]) + out.y * F(l.axis_x[1]) + out.z * F(l.axis_x[2]);
        const F y = out.x * F(l.axis_y[0]) + out.y * F(l.axis_y[1]) + out.z * F(l.axis_y[2]);
        const F z = out.x * F(l.axis_z[0]) + out.y * F(l.axis_z[1]) + out.z * F(l.axis_z[2]);
        if (l.type_b) {
            // type B (docs/luminaires.md): H = asin(-x) within the plane, V = atan2(y, z) about x
            return grid2_w::eval(l.candela, fast_asin(clamp(-x, F(-1.0f), F(1.0f))), fast_atan2(y, z));
        }
        // photometric type C: gamma from the nadir (-axis_z), C from axis_x towards axis_y
        const F gamma = fast_acos(clamp(-z, F(-1.0f), F(1.0f)));
        F c = fast_atan2(y, x);
        c = select(c < F(0.0f), c + F(2.0f * kPi), c);
        return grid2_w::eval(l.candela, c, gamma);
    }
    return F(1.0f);
}

// The sun: a direction uniform in its disc's cone (pdf 1 / (2 pi (1 - cos))), its radiance.
PATINA_INLINE F sample_sun(const Light& l, F u1, F u2, D3& w, F& r, F& g, F& b) {
    // 1 - cos(theta) = u1 (1 - cos_sun), uniform over the cone; sin from it without cancellation
    const F one_minus = u1 * F(l.sun_one_minus_cos);
    const F cos_t = F(1.0f) - one_minus;
    const F sin_t = sqrt_exact(max(one_minus * (F(2.0f) - one_minus), F(0.0f)));
    F sp, cp;
    fast_sincos(F(2.0f * kPi) * u2, sp, cp);
    const F a = sin_t * cp, c = sin_t * sp;
    w = D3{madd(a, F(l.frame_t[0]), madd(c, F(l.frame_b[0]), cos_t * F(l.direction[0]))),
           madd(a, F(l.frame_t[1]), madd(c, F(l.frame_b[1]), cos_t * F(l.direction[1]))),
           madd(a, F(l.frame_t[2]), madd(c, F(l.frame_b[2]), cos_t * F(l.direction[2])))};
    r = F(l.power[0]), g = F(l.power[1]), b = F(l.power[2]);
    return F(1.0f / (2.0f * kPi * l.sun_one_minus_cos));
}

// A point uniform by area over a triangle light's triangles (the triangle by its area cdf,
// u1 reused within the cell), with that triangle's geometric normal.
PATINA_INLINE D3 sample_triangles(const RenderScene& s, const Light& l, F u1, F u2, D3& n) {
    const int count = static_cast<int>(l.triangles.size());
    const vint<W> k = coherent_search<W>(l.area_cdf.data(), count + 1, u1, F(0.0f) == F(0.0f));
    const F c0 = gather(l.area_cdf.data(), k), c1 = gather(l.area_cdf.data(), k + vint<W>(1));
    const F r1 = select(c1 > c0, clamp((u1 - c0) / (c1 - c0), F(0.0f), F(1.0f)), F(0.5f));
    const vint<W> tri = gather(l.triangles.data(), k);
    const float* v = s.tree->triangles.data();
    const vint<W> base = tri * vint<W>(9), nb = tri * vint<W>(3);
    D3 p[3];
    for (int j = 0; j < 3; ++j)
        p[j] = D3{gather(v, base + vint<W>(3 * j)), gather(v, base + vint<W>(3 * j + 1)),
                  gather(v, base + vint<W>(3 * j + 2))};
    n = D3{gather(s.tree->normals.data(), nb), gather(s.tree->normals.data(), nb + vint<W>(1)),
           gather(s.tree->normals.data(), nb + vint<W>(2))};
    const F su = sqrt_exact(r1), b0 = F(1.0f) - su, b1 = su * (F(1.0f) - u2), b2 = su * u2;
    return D3{madd(b0, p[0].x, madd(b1, p[1].x, b2 * p[2].x)), madd(b0, p[0].y, madd(b1, p[1].y, b2 * p[2].y)),
              madd(b0, p[0].z, madd(b1, p[1].z, b2 * p[2].z))};
}

// Light samples for the points that chose light `li` (every lane the same light: coherent),
// W points at a time: inputs gathered from the points, results scattered back to sc.ls_*.
inline void sample_light_group(const RenderScene& s, PathScratch& sc, int li, const int32_t* points, size_t n,
                               const float* u1, const float* u2) {
    float* pos = grow(sc.group_pos, 3 * n);
    float* g1 = grow(sc.group_u1, n);
    float* g2 = grow(sc.group_u2, n);
    float* dir = grow(sc.group_dir, 3 * n);
    float* rgb = grow(sc.group_rgb, 3 * n);
    float* dist = grow(sc.group_dist, n);
    float* pdf = grow(sc.group_pdf, n);
    float* gsel = grow(sc.group_sel, n);
    const bool env = li == static_cast<int>(s.lights.size());
    const Light* light = env ? nullptr : &s.lights[li];
    const bool at_infinity = env || light->kind == LightKind::Sun;  // the points' positions do not matter
    for (size_t j = 0; j < n; ++j) {
        const int32_t q = points[j];
        if (!at_infinity) std::copy(sc.sorted[q].p, sc.sorted[q].p + 3, pos + 3 * j);
        g1[j] = u1[q];
        g2[j] = u2[q];
        gsel[j] = sc.point_sel[q];
    }
    for_blocks(n, [&](size_t i, int lanes) {
        const F s1 = rows::load1<W>(g1, i, lanes), s2 = rows::load1<W>(g2, i, lanes);
        const F sel = rows::load1<W>(gsel, i, lanes);
        D3 w;
        F r, g, b, d, p;
        if (env) {
            p = sel * env_w::sample(s.env, s1, s2, w, r, g, b);
            d = F(kInfinity);
        } else if (light->kind == LightKind::Sun) {
            p = sample_sun(*light, s1, s2, w, r, g, b) * sel;
            d = F(kInfinity);
        } else {
            const D3 at = load_dir(pos, i, lanes);
            D3 target{F(light->position[0]), F(light->position[1]), F(light->position[2])};
            D3 n{F(light->normal[0]), F(light->normal[1]), F(light->normal[2])};
            if (light->kind == LightKind::Quad) {  // a uniform point on the parallelogram
                const F ua = madd(F(2.0f), s1, F(-1.0f)), ub = madd(F(2.0f), s2, F(-1.0f));
                target.x = madd(ua, F(light->u[0]), madd(ub, F(light->v[0]), target.x));
                target.y = madd(ua, F(light->u[1]), madd(ub, F(light->v[1]), target.y));
                target.z = madd(ua, F(light->u[2]), madd(ub, F(light->v[2]), target.z));
            } else if (light->kind == LightKind::Triangles) {
                target = sample_triangles(s, *light, s1, s2, n);
            }
            const F dx = target.x - at.x, dy = target.y - at.y, dz = target.z - at.z;
            const F dist2 = dx * dx + dy * dy + dz * dz;
            d = sqrt_exact(dist2);
            const F inv = F(1.0f) / d;
            w = D3{dx * inv, dy * inv, dz * inv};
            if (light->kind == LightKind::Quad || light->kind == LightKind::Triangles) {
                // emitting side: -dir . n > 0, or either side when two-sided
                const F facing = -(w.x * n.x + w.y * n.y + w.z * n.z);
                const F cos_l = light->two_sided ? abs(facing) : facing;
                r = F(light->power[0]), g = F(light->power[1]), b = F(light->power[2]);
                p = select((cos_l > F(0.0f)) & (dist2 > F(0.0f)), sel * dist2 / (F(light->area) * cos_l), F(0.0f));
            } else {  // delta lights: intensity towards the point / distance^2
                const F scale = delta_intensity(*light, D3{-w.x, -w.y, -w.z}) / dist2;
                r = F(light->power[0]) * scale, g = F(light->power[1]) * scale, b = F(light->power[2]) * scale;
                p = select(dist2 > F(0.0f), sel, F(0.0f));
            }
        }
        rows::store3<W>(dir, i, lanes, w.x, w.y, w.z);
        rows::store3<W>(rgb, i, lanes, r, g, b);
        rows::store1<W>(dist, i, lanes, d);
        rows::store1<W>(pdf, i, lanes, p);
    });
    const bool delta = light != nullptr && (light->kind == LightKind::Point || light->kind == LightKind::Spot ||
                                            light->kind == LightKind::Goniometric);
    for (size_t j = 0; j < n; ++j) {
        const int32_t q = points[j];
        std::copy(dir + 3 * j, dir + 3 * j + 3, sc.ls_dir.data() + 3 * q);
        std::copy(rgb + 3 * j, rgb + 3 * j + 3, sc.ls_rgb.data() + 3 * q);
        sc.ls_dist[q] = dist[j];
        sc.ls_pdf[q] = pdf[j];
        sc.ls_delta[q] = delta;
        sc.ls_ok[q] = pdf[j] > 0 && std::isfinite(pdf[j]);
    }
}

// One light sample per shading point into sc.ls_*: each point picks a light in proportion to
// its estimated irradiance there, the points are grouped by the light they picked, and each
// group is sampled W points at a time.
inline void sample_lights(const RenderScene& s, PathScratch& sc, int depth, size_t np) {
    sc.ls_dir.resize(3 * np);
    sc.ls_rgb.resize(3 * np);
    sc.ls_dist.resize(np);
    sc.ls_pdf.resize(np);
    sc.ls_delta.resize(np);
    sc.ls_ok.resize(np);
    float* pick = grow(sc.u_pick, np);
    float* u1 = grow(sc.u1, np);
    float* u2 = grow(sc.u2, np);
    fill_uniforms(sc.point_keys.data(), np, depth, kDimLightPick, pick);
    fill_uniforms(sc.point_keys.data(), np, depth, kDimLightU, u1);
    fill_uniforms(sc.point_keys.data(), np, depth, kDimLightV, u2);
    const int count = light_count(s);
    std::vector<int32_t>& chosen = sc.light_of_point;
    chosen.resize(np);
    sc.point_sel.resize(np);
    sc.light_start.assign(count + 1, 0);
    std::vector<float>& w = sc.selection_scratch;
    w.resize(count + 1);
    for (size_t q = 0; q < np; ++q) {
        // the light by its estimated irradiance at this point
        const float sum = selection_weights(s, sc.sorted[q].p, w.data());
        float acc = 0, target = pick[q] * sum;
        int k = 0;
        for (; k < count - 1; ++k) {
            if (target < acc + w[k]) break;
            acc += w[k];
        }
        while (k > 0 && !(w[k] > 0)) --k;  // never a light of zero weight (rounding at the top)
        chosen[q] = k;
        sc.point_sel[q] = sum > 0 ? w[k] / sum : 0.0f;
        ++sc.light_start[k + 1];
    }
    for (int k = 0; k < count; ++k) sc.light_start[k + 1] += sc.light_start[k];
    sc.light_points.resize(np);
    sc.light_fill.assign(sc.light_start.begin(), sc.light_start.end() - 1);
    for (size_t q = 0; q < np; ++q) sc.light_points[sc.light_fill[chosen[q]]++] = static_cast<int32_t>(q);
    for (int k = 0; k < count; ++k) {
        const size_t a = sc.light_start[k], n = sc.light_start[k + 1] - a;
        if (n > 0) sample_light_group(s, sc, k, sc.light_points.data() + a, n, u1, u2);
    }
}

void trace_paths(const RenderScene& s, const IntegratorSettings& st, const CameraSample* cs, size_t n,
                 PathResult* out, PathScratch& sc) {
    if constexpr (W < 8) clear_upper_state();
    const TraceKernels& tk = trace_kernels();
    float* org = grow(sc.org, 3 * n);
    float* dir = grow(sc.dir, 3 * n);
    float* thr = grow(sc.throughput, 3 * n);
    float* prev_pdf = grow(sc.prev_pdf, n);
    float* prev_pos = grow(sc.prev_pos, 3 * n);  // where the path's last BRDF sample left from
    sc.active.clear();
    for (size_t i = 0; i < n; ++i) {
        const uint32_t key = cs[i].key;
        camera_ray(s.camera, cs[i].fx, cs[i].fy, bounce_uniform(key, 0, kDimLensU), bounce_uniform(key, 0, kDimLensV),
                   org + 3 * i, dir + 3 * i);
        std::fill(thr + 3 * i, thr + 3 * i + 3, 1.0f);
        prev_pdf[i] = 0;  // a camera ray: whatever it sees counts in full
        PathResult& r = out[i];
        std::fill(r.rgb, r.rgb + 3, 0.0f);
        std::fill(r.albedo, r.albedo + 3, 0.0f);
        std::fill(r.normal, r.normal + 3, 0.0f);
        r.depth = kInfinity;
        r.illuminance = 0;
        sc.active.push_back(static_cast<int32_t>(i));
    }
    const bool can_sample_lights = lights_emit(s);
    bool has_sun = false;
    for (const Light& l : s.lights) has_sun = has_sun || l.kind == LightKind::Sun;
    const float eps = s.ray_offset;

    for (int depth = 0; !sc.active.empty(); ++depth) {
        // 1. trace this bounce's rays, W per packet
        const size_t m = sc.active.size();
        float* ro = grow(sc.ray_org, 3 * m);
        float* rd = grow(sc.ray_dir, 3 * m);
        for (size_t j = 0; j < m; ++j) {
            const int32_t i = sc.active[j];
            std::copy(org + 3 * i, org + 3 * i + 3, ro + 3 * j);
            std::copy(dir + 3 * i, dir + 3 * i + 3, rd + 3 * j);
        }
        HitBatch hits{grow(sc.hit_t, m), grow(sc.hit_prim, m), grow(sc.hit_u, m), grow(sc.hit_v, m)};
        tk.intersect(*s.tree, RayBatch{ro, rd, 0.0f, nullptr, kInfinity}, hits, 0, m);
        sc.rays_traced += m;

        // 2. misses and lights seen add their emission (MIS-weighted after a BRDF sample);
        //    surface hits become shading points
        sc.points.clear();
        sc.misses.clear();
        for (size_t j = 0; j < m; ++j) {
            const int32_t i = sc.active[j];
            const float* d = dir + 3 * i;
            float* T = thr + 3 * i;
            const int32_t prim = hits.prim[j];
            if (prim < 0) {
                if (s.env.present || has_sun) sc.misses.push_back(i);
                continue;
            }
            const Material& mat = s.materials[s.tri_material[prim]];
            if (mat.kind == MaterialKind::Emitter) {
                const Light& l = s.lights[mat.light];
                const float* ng = s.tree->normals.data() + 3 * static_cast<size_t>(prim);  // quads: their normal
                const float facing = -dot3(d, ng);
                if (facing > 0 || (l.two_sided && facing < 0)) {
                    float w = 1.0f;
                    if (prev_pdf[i] > 0 && can_sample_lights)
                        w = power_heuristic(prev_pdf[i], area_light_pdf(s, prev_pos + 3 * i, mat.light, facing, hits.t[j]));
                    for (int k = 0; k < 3; ++k) out[i].rgb[k] += T[k] * l.power[k] * w;
                }
                if (depth == 0) out[i].depth = hits.t[j];
                continue;
            }
            if (depth >= st.max_depth) continue;
            ShadingPoint sp;
            if (!make_shading_point(s, prim, hits.u[j], hits.v[j], org + 3 * i, d, hits.t[j], sp)) {
                if (depth == 0) out[i].depth = hits.t[j];
                continue;
            }
            sp.path = i;
            sp.material = s.tri_material[prim];
            if (depth == 0) {
                for (int k = 0; k < 3; ++k) {
                    out[i].albedo[k] = mat.albedo[k];
                    out[i].normal[k] = sp.n[k];
                }
                out[i].depth = hits.t[j];
            }
            sc.points.push_back(sp);
        }

        add_environment(s, sc, dir, thr, prev_pdf, prev_pos, can_sample_lights, out);

        // 3. group the shading points by material, so each group is shaded W at a time
        const size_t np = sc.points.size();
        const size_t nm = s.materials.size();
        sc.material_start.assign(nm + 1, 0);
        for (const ShadingPoint& sp : sc.points) ++sc.material_start[sp.material + 1];
        for (size_t k = 0; k < nm; ++k) sc.material_start[k + 1] += sc.material_start[k];
        sc.sorted.resize(np);
        {
            std::vector<int32_t>& fill = sc.next_active;  // reused as the write cursors
            fill.assign(sc.material_start.begin(), sc.material_start.end() - 1);
            for (const ShadingPoint& sp : sc.points) sc.sorted[fill[sp.material]++] = sp;
        }

        float* vl = grow(sc.v_local, 3 * np);
        float* ll = grow(sc.l_local, 3 * np);
        float* fv = grow(sc.f, 3 * np);
        float* pdf = grow(sc.pdf, np);
        float* eta = grow(sc.eta, np);
        float* upick = grow(sc.u_pick, np);
        float* u1 = grow(sc.u1, np);
        float* u2 = grow(sc.u2, np);
        for (size_t q = 0; q < np; ++q) {
            const ShadingPoint& sp = sc.sorted[q];
            const float wo[3] = {-dir[3 * sp.path], -dir[3 * sp.path + 1], -dir[3 * sp.path + 2]};
            to_local(sp, wo, vl + 3 * q);
            eta[q] = sp.eta;
        }
        sc.point_keys.resize(np);
        for (size_t q = 0; q < np; ++q) sc.point_keys[q] = static_cast<int32_t>(cs[sc.sorted[q].path].key);

        // 4. light sampling: one sample per point, its shadow ray queued
        clear_shadow_rays(sc);
        if (can_sample_lights) {
            sample_lights(s, sc, depth, np);
            for (size_t q = 0; q < np; ++q) {
                const ShadingPoint& sp = sc.sorted[q];
                const float* ldir = sc.ls_dir.data() + 3 * q;
                if (sc.ls_ok[q]) to_local(sp, ldir, ll + 3 * q);
                else std::fill(ll + 3 * q, ll + 3 * q + 3, 0.0f);
                // the light must be on the side the local direction says (shading normals bend)
                const float side = dot3(ldir, sp.ng);
                const bool transmissive = s.materials[sp.material].kind == MaterialKind::Dielectric;
                sc.ls_ok[q] = sc.ls_ok[q] && (transmissive ? side * ll[3 * q + 2] > 0 : side > 0);
            }
            for (size_t k = 0; k < nm; ++k) {
                const size_t a = sc.material_start[k], count = sc.material_start[k + 1] - a;
                if (count == 0) continue;
                material_eval(s.materials[k], ll + 3 * a, vl + 3 * a, eta + a, fv + 3 * a, count);
                material_pdf(s.materials[k], ll + 3 * a, vl + 3 * a, eta + a, pdf + a, count);
            }
            for (size_t q = 0; q < np; ++q) {
                if (!sc.ls_ok[q]) continue;
                const ShadingPoint& sp = sc.sorted[q];
                const LightSample ls = load_light_sample(sc, q);
                const float lz = ll[3 * q + 2], cos_l = std::abs(lz);
                if (!(cos_l > 0)) continue;
                const float w = ls.delta ? 1.0f : power_heuristic(ls.pdf, pdf[q]);
                const float* T = thr + 3 * sp.path;
                float c[3];
                for (int k = 0; k < 3; ++k) c[k] = T[k] * fv[3 * q + k] * cos_l * ls.rgb[k] * w / ls.pdf;
                const float lux = depth == 0 && lz > 0 ? kLumensPerWatt * luminance(ls.rgb) * cos_l / ls.pdf : 0.0f;
                const float side = lz > 0 ? eps : -eps;
                if (c[0] <= 0 && c[1] <= 0 && c[2] <= 0 && lux <= 0) continue;
                queue_shadow_ray(sc, sp.path, sp.p, sp.ng, side, ls, c, lux);
            }
        }

        // 5. BRDF sampling: the next bounce's rays
        fill_uniforms(sc.point_keys.data(), np, depth, kDimBsdfPick, upick);
        fill_uniforms(sc.point_keys.data(), np, depth, kDimBsdfU, u1);
        fill_uniforms(sc.point_keys.data(), np, depth, kDimBsdfV, u2);
        for (size_t k = 0; k < nm; ++k) {
            const size_t a = sc.material_start[k], count = sc.material_start[k + 1] - a;
            if (count == 0) continue;
            const Material& mat = s.materials[k];
            material_sample(mat, vl + 3 * a, eta + a, upick + a, u1 + a, u2 + a, ll + 3 * a, pdf + a, count);
            material_eval(mat, ll + 3 * a, vl + 3 * a, eta + a, fv + 3 * a, count);
        }
        sc.next_active.clear();
        for (size_t q = 0; q < np; ++q) {
            const ShadingPoint& sp = sc.sorted[q];
            const int32_t i = sp.path;
            const float* l = ll + 3 * q;
            if (!(pdf[q] > 0) || l[2] == 0 || depth + 1 > st.max_depth) continue;
            float wl[3];
            to_world(sp, l, wl);
            normalize3(wl);
            if (!(dot3(wl, sp.ng) * l[2] > 0)) continue;  // the side the local direction says
            float* T = thr + 3 * i;
            for (int k = 0; k < 3; ++k) T[k] *= fv[3 * q + k] * std::abs(l[2]) / pdf[q];
            if (!(T[0] > 0 || T[1] > 0 || T[2] > 0)) continue;
            if (depth + 1 >= st.rr_depth) {
                const float survive = std::min(0.95f, std::max(T[0], std::max(T[1], T[2])));
                if (bounce_uniform(cs[i].key, depth, kDimRoulette) >= survive) continue;
                for (int k = 0; k < 3; ++k) T[k] /= survive;
            }
            const float side = l[2] > 0 ? eps : -eps;
            for (int k = 0; k < 3; ++k) {
                org[3 * i + k] = sp.p[k] + side * sp.ng[k];
                dir[3 * i + k] = wl[k];
            }
            prev_pdf[i] = pdf[q];
            std::copy(sp.p, sp.p + 3, prev_pos + 3 * i);
            sc.next_active.push_back(i);
        }

        // 6. shadow rays, W per packet; the unblocked ones add their light
        const uint8_t* blocked = trace_shadow_rays(s, sc);
        for (size_t q = 0; q < sc.shadow_path.size(); ++q) {
            if (blocked[q]) continue;
            PathResult& r = out[sc.shadow_path[q]];
            for (int k = 0; k < 3; ++k) r.rgb[k] += sc.shadow_rgb[3 * q + k];
            r.illuminance += sc.shadow_lux[q];
        }
        std::swap(sc.active, sc.next_active);
    }
}

// Direct illuminance on sensors (patina illuminance): the same light sampling and shadow
// packets as the renderer's, with the sensor's cosine instead of a BRDF.
void sensor_illuminance(const RenderScene& s, const float* points, const float* normals, size_t begin, size_t end,
                        int samples, uint32_t seed, float* lux, PathScratch& sc) {
    if constexpr (W < 8) clear_upper_state();
    const size_t np = end - begin;
    std::fill(lux + begin, lux + end, 0.0f);
    if (np == 0 || !lights_emit(s)) return;
    sc.sorted.resize(np);
    for (size_t q = 0; q < np; ++q) {
        ShadingPoint& sp = sc.sorted[q];
        const size_t i = begin + q;
        std::copy(points + 3 * i, points + 3 * i + 3, sp.p);
        std::copy(normals + 3 * i, normals + 3 * i + 3, sp.ng);
        normalize3(sp.ng);
        std::copy(sp.ng, sp.ng + 3, sp.n);
        orthonormal_frame(sp.n, sp.t, sp.b);
        sp.path = static_cast<int32_t>(q);
        sp.material = 0;
        sp.eta = 1;
    }
    const float eps = s.ray_offset;
    std::vector<double> sum(np, 0.0);
    sc.point_keys.resize(np);
    for (int k = 0; k < samples; ++k) {
        for (size_t q = 0; q < np; ++q)
            sc.point_keys[q] = static_cast<int32_t>(path_key(seed, static_cast<uint32_t>(begin + q), static_cast<uint32_t>(k)));
        sample_lights(s, sc, 0, np);
        clear_shadow_rays(sc);
        for (size_t q = 0; q < np; ++q) {
            if (!sc.ls_ok[q]) continue;
            const ShadingPoint& sp = sc.sorted[q];
            const LightSample ls = load_light_sample(sc, q);
            const float cos_s = dot3(ls.dir, sp.n);
            if (!(cos_s > 0)) continue;
            const float none[3] = {0, 0, 0};
            queue_shadow_ray(sc, static_cast<int32_t>(q), sp.p, sp.n, eps, ls, none,
                             kLumensPerWatt * luminance(ls.rgb) * cos_s / ls.pdf);
        }
        const uint8_t* blocked = trace_shadow_rays(s, sc);
        for (size_t j = 0; j < sc.shadow_path.size(); ++j)
            if (!blocked[j]) sum[sc.shadow_path[j]] += sc.shadow_lux[j];
    }
    for (size_t q = 0; q < np; ++q) lux[begin + q] = static_cast<float>(sum[q] / samples);
}

}  // namespace render_detail
PATINA_END_TARGET
