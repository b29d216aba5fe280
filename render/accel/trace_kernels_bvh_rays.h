// The BVH's single rays set up N at a time. bvh_traverse.h's load_ray prepares one ray
// with scalar code: three divisions and, for incoherent rays, branches on the signs and on
// the largest direction component that the CPU mispredicts. Here the same arithmetic runs
// in the width's lanes for N rays of the batch (the same operations in the same order, so
// the same bits), and each ray's fields are then copied out of the lanes for its traversal.
#pragma once

#include <cstddef>

#include "core/simd/rows.h"
#include "render/accel/bvh_traverse.h"
#include "render/accel/trace_kernels.h"

PATINA_BEGIN_TARGET

template <int N>
struct BvhRayLanes {
    alignas(64) float org[3][N], dir[3][N], inv[3][N], near_offset[3][N], far_offset[3][N];
    alignas(64) int32_t positive[3][N];  // 1 where inv[a] >= +0 (the box's low plane is the near one)
    alignas(64) int32_t kx[N], ky[N], kz[N];
    alignas(64) float sx[N], sy[N], sz[N], tmax[N];

    // The lanes' origins and directions as registers (the analytic spheres' tests take them so).
    PATINA_INLINE void rays(vfloat<N> (&o)[3], vfloat<N> (&d)[3]) const {
        for (int a = 0; a < 3; ++a) o[a] = load_n<N>(org[a]), d[a] = load_n<N>(dir[a]);
    }
};

// Rays [i, i + lanes) of the batch into the lanes: load_ray's arithmetic, N rays at once.
template <int N>
PATINA_INLINE void load_bvh_rays(const Bvh& bvh, const RayBatch& rays, size_t i, int lanes, BvhRayLanes<N>& out) {
    using F = vfloat<N>;
    using I = vint<N>;
    constexpr float kTiny = 0x1p-64f;
    F o[3], d[3], inv[3];
    rows::load3<N>(rays.origins, i, lanes, o[0], o[1], o[2]);
    rows::load3<N>(rays.directions, i, lanes, d[0], d[1], d[2]);
    for (int a = 0; a < 3; ++a) {
        // components below kTiny in magnitude count as +-kTiny (the sign of d kept)
        inv[a] = F(1.0f) / select(abs(d[a]) < F(kTiny), copysign(F(kTiny), d[a]), d[a]);
        const F margin = (F(bvh.extent[a]) + abs(o[a])) * abs(inv[a]) * F(bvh_detail::kBoxMargin);
        const F oi = o[a] * inv[a];
        store_n<N>(out.org[a], o[a]);
        store_n<N>(out.dir[a], d[a]);
        store_n<N>(out.inv[a], inv[a]);
        store_n<N>(out.near_offset[a], oi + margin);
        store_n<N>(out.far_offset[a], oi - margin);
        store_n<N>(out.positive[a], select(signbit(inv[a]), I(0), I(1)));
    }
    const F ax = abs(d[0]), ay = abs(d[1]), az = abs(d[2]);
    const I kz = select((ax >= ay) & (ax >= az), I(0), select(ay >= az, I(1), I(2)));
    I kx = select(kz == I(2), I(0), kz + I(1));
    I ky = select(kx == I(2), I(0), kx + I(1));
    const vbool<N> flip = ray_detail::pick<N>(d, kz) < F(0.0f);
    const I unflipped = kx;
    kx = select(flip, ky, kx);
    ky = select(flip, unflipped, ky);
    const F sz = ray_detail::pick<N>(inv, kz);  // 1 / dir[kz]: the largest component is never below kTiny
    store_n<N>(out.kx, kx);
    store_n<N>(out.ky, ky);
    store_n<N>(out.kz, kz);
    store_n<N>(out.sz, sz);
    store_n<N>(out.sx, ray_detail::pick<N>(d, kx) * sz);
    store_n<N>(out.sy, ray_detail::pick<N>(d, ky) * sz);
    store_n<N>(out.tmax, rays.tmax ? rows::load1<N>(rays.tmax, i, lanes) : F(rays.tmax_all));
}

// The root node's children against N rays at once, the lanes over the rays (a single ray's
// test, hit_children, has them over the children): incoherent rays enter the tree at the same
// node, so its eight boxes are tested once for the whole group, with hit_children's operations
// per (ray, child) in the same order (the same masks and entry distances), and a ray that
// enters none of them is done without a traversal.
template <int N>
struct BvhRootLanes {
    alignas(64) float near[kBvhWidth][N];  // near[c][j]: ray j's entry distance into child c
    alignas(64) int32_t mask[N];           // bit c: ray j enters child c within [tmin, tmax]
};

// Only for a root that is an interior node (bvh.root = node 0).
template <int N>
PATINA_INLINE void test_root_children(const Bvh& bvh, const BvhRayLanes<N>& l, float tmin, BvhRootLanes<N>& out) {
    using F = vfloat<N>;
    using I = vint<N>;
    const BvhNode& node = bvh.nodes[bvh.root];
    vbool<N> positive[3];
    F inv[3], near_offset[3], far_offset[3];
    for (int a = 0; a < 3; ++a) {
        positive[a] = load_n<N>(l.positive[a]) == I(1);
        inv[a] = load_n<N>(l.inv[a]);
        near_offset[a] = load_n<N>(l.near_offset[a]);
        far_offset[a] = load_n<N>(l.far_offset[a]);
    }
    const F tmax = load_n<N>(l.tmax);
    I mask(0);
    for (int c = 0; c < kBvhWidth; ++c) {
        F t0(tmin), t1 = tmax;
        for (int a = 0; a < 3; ++a) {
            const F lo(node.box[2 * a][c]), hi(node.box[2 * a + 1][c]);
            const F n = fmadd(select(positive[a], lo, hi), inv[a], -near_offset[a]);
            const F f = fmadd(select(positive[a], hi, lo), inv[a], -far_offset[a]);
            t0 = max(n, t0);
            t1 = min(f, t1);
        }
        store_n<N>(out.near[c], t0);
        mask = select(t0 <= t1, mask | I(1 << c), mask);
    }
    store_n<N>(out.mask, mask);
}

// Lane j as load_ray would have prepared it.
template <int N>
PATINA_INLINE void bvh_ray_of(const BvhRayLanes<N>& l, int j, float tmin, RayPacket<1>& r, bvh_detail::BoxRay& b) {
    for (int a = 0; a < 3; ++a) {
        r.org[a] = l.org[a][j];
        r.dir[a] = l.dir[a][j];
        b.inv[a] = l.inv[a][j];
        b.near_offset[a] = l.near_offset[a][j];
        b.far_offset[a] = l.far_offset[a][j];
        b.near_row[a] = 2 * a + 1 - l.positive[a][j];
        b.far_row[a] = 2 * a + l.positive[a][j];
    }
    r.tmin = tmin;
    r.tmax = l.tmax[j];
    r.kx = r.ukx = l.kx[j];
    r.ky = r.uky = l.ky[j];
    r.kz = r.ukz = l.kz[j];
    r.uniform_axes = true;
    r.sx = l.sx[j];
    r.sy = l.sy[j];
    r.sz = l.sz[j];
}

PATINA_END_TARGET
