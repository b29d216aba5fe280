// Scenes, rays and a double-precision brute-force reference shared by the tracer's tests
// (the kd-tree's in tests/cpp/render/accel/test_kdtree.cpp, the BVH's beside this file).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <random>
#include <utility>
#include <vector>

namespace trace_test {
constexpr float kInf = std::numeric_limits<float>::infinity();

struct Mesh {
    std::vector<float> v;
    std::vector<int32_t> f;
    size_t triangles() const { return f.size() / 3; }
};

// A closed icosphere: shared vertices, so neighbouring triangles share exact edges.
inline Mesh icosphere(int subdivisions) {
    const double p = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<std::array<double, 3>> pts = {{-1, p, 0}, {1, p, 0}, {-1, -p, 0}, {1, -p, 0}, {0, -1, p}, {0, 1, p},
                                              {0, -1, -p}, {0, 1, -p}, {p, 0, -1}, {p, 0, 1}, {-p, 0, -1}, {-p, 0, 1}};
    std::vector<std::array<int, 3>> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                             {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                             {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                             {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    auto unit = [](std::array<double, 3> a) {
        const double l = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        return std::array<double, 3>{a[0] / l, a[1] / l, a[2] / l};
    };
    for (auto& q : pts) q = unit(q);
    for (int s = 0; s < subdivisions; ++s) {
        std::map<std::pair<int, int>, int> mid;
        auto midpoint = [&](int a, int b) {
            const auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            pts.push_back(unit({(pts[a][0] + pts[b][0]) / 2, (pts[a][1] + pts[b][1]) / 2, (pts[a][2] + pts[b][2]) / 2}));
            return mid[key] = static_cast<int>(pts.size()) - 1;
        };
        std::vector<std::array<int, 3>> next;
        for (const auto& t : faces) {
            const int a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
            next.push_back({t[0], a, c});
            next.push_back({t[1], b, a});
            next.push_back({t[2], c, b});
            next.push_back({a, b, c});
        }
        faces = next;
    }
    Mesh m;
    for (const auto& q : pts)
        for (double c : q) m.v.push_back(static_cast<float>(c));
    for (const auto& t : faces)
        for (int i : t) m.f.push_back(i);
    return m;
}

inline Mesh soup(size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), s(-0.2f, 0.2f);
    Mesh m;
    for (size_t t = 0; t < n; ++t) {
        const float cx = u(rng), cy = u(rng), cz = u(rng);
        for (int k = 0; k < 3; ++k) {
            m.v.insert(m.v.end(), {cx + s(rng), cy + s(rng), cz + s(rng)});
            m.f.push_back(static_cast<int32_t>(3 * t + k));
        }
    }
    return m;
}

struct Rays {
    std::vector<float> o, d;
    size_t size() const { return o.size() / 3; }
    void add(std::array<float, 3> org, std::array<float, 3> dir) {
        o.insert(o.end(), org.begin(), org.end());
        d.insert(d.end(), dir.begin(), dir.end());
    }
};

inline Rays random_rays(size_t n, unsigned seed, float spread = 1.5f) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-spread, spread);
    std::normal_distribution<float> g;
    Rays r;
    for (size_t i = 0; i < n; ++i) r.add({u(rng), u(rng), u(rng)}, {g(rng), g(rng), g(rng) + 1e-3f});
    return r;
}

// A pinhole camera's rays in 4 x 2 pixel tiles (so 4- and 8-ray packets are tiles).
inline Rays camera_rays(int w, int h) {
    Rays r;
    for (int ty = 0; ty < h; ty += 2)
        for (int tx = 0; tx < w; tx += 4)
            for (int y = ty; y < ty + 2; ++y)
                for (int x = tx; x < tx + 4; ++x) {
                    const float px = (x + 0.5f) / w * 2 - 1, py = (y + 0.5f) / h * 2 - 1;
                    r.add({0.1f, 0.2f, 3.0f}, {0.6f * px, 0.6f * py, -1.0f});
                }
    return r;
}

// Rays from each of `origins` (inside a closed mesh) through each of the mesh's vertices
// and edge midpoints: ties between the triangles that share them.
template <size_t N>
inline Rays rays_through_edges(const Mesh& m, const std::array<std::array<float, 3>, N>& origins) {
    Rays rays;
    for (const auto& o : origins) {
        for (size_t k = 0; k < m.v.size() / 3; ++k)
            rays.add(o, {m.v[3 * k] - o[0], m.v[3 * k + 1] - o[1], m.v[3 * k + 2] - o[2]});
        for (size_t t = 0; t < m.triangles(); ++t)
            for (int e = 0; e < 3; ++e) {
                const float* a = &m.v[3 * size_t(m.f[3 * t + e])];
                const float* b = &m.v[3 * size_t(m.f[3 * t + (e + 1) % 3])];
                rays.add(o, {(a[0] + b[0]) / 2 - o[0], (a[1] + b[1]) / 2 - o[1], (a[2] + b[2]) / 2 - o[2]});
            }
    }
    return rays;
}

// Closest hit by testing every triangle (Moller-Trumbore in double).
inline std::pair<double, int> brute_force(const Mesh& m, const float* o, const float* d) {
    double best = kInf;
    int prim = -1;
    for (size_t t = 0; t < m.triangles(); ++t) {
        double p[3][3];
        for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a) p[k][a] = m.v[3 * size_t(m.f[3 * t + k]) + a];
        const double e1[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
        const double e2[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
        const double pv[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
        const double det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
        if (std::fabs(det) < 1e-300) continue;
        const double tv[3] = {o[0] - p[0][0], o[1] - p[0][1], o[2] - p[0][2]};
        const double u = (tv[0] * pv[0] + tv[1] * pv[1] + tv[2] * pv[2]) / det;
        if (u < 0 || u > 1) continue;
        const double q[3] = {tv[1] * e1[2] - tv[2] * e1[1], tv[2] * e1[0] - tv[0] * e1[2], tv[0] * e1[1] - tv[1] * e1[0]};
        const double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
        if (v < 0 || u + v > 1) continue;
        const double tt = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
        if (tt > 0 && tt < best) {
            best = tt;
            prim = static_cast<int>(t);
        }
    }
    return {best, prim};
}

// Closest hits (t and triangle per ray) against brute_force: a miss where it misses, every
// hit it finds found, t within 1e-5 relative, another triangle only in a tie (t within
// 1e-6); and at least `min_hits` rays that hit, so that the check means something.
inline void expect_brute_force_hits(const Mesh& m, const Rays& rays, const float* t, const int32_t* prim,
                                    int min_hits) {
    int hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const auto [bt, bprim] = brute_force(m, &rays.o[3 * i], &rays.d[3 * i]);
        if (bprim < 0) {
            EXPECT_EQ(prim[i], -1) << "ray " << i;
            continue;
        }
        ++hits;
        ASSERT_GE(prim[i], 0) << "ray " << i << " missed, brute force hits " << bprim << " at " << bt;
        EXPECT_NEAR(t[i], bt, 1e-5 * bt) << "ray " << i;
        if (prim[i] != bprim) {
            EXPECT_NEAR(t[i], bt, 1e-6 * bt) << "ray " << i << ": not a tie";
        }
    }
    EXPECT_GT(hits, min_hits);
}

}  // namespace trace_test
