// K rays at once (K = 1, 4, 8), with what the traversal and the watertight triangle
// test precompute per ray.
#pragma once

#include <limits>

#include "core/simd/simd.h"

PATINA_BEGIN_TARGET

// Relative margin on plane distances: 16 float ulps of the operands' magnitudes.
constexpr float kPlaneMargin = 16.0f / (1 << 23);

template <int K>
struct RayPacket {
    using F = vfloat<K>;
    using I = vint<K>;
    F org[3], dir[3], inv_dir[3];
    // Rounding margin of the distance to a plane x[a] = p (traverse.h, plane_distance):
    // |p| margin_per_unit + margin_of_origin, from |1/d| (0 where d = 0) and kPlaneMargin.
    F margin_per_unit[3], margin_of_origin[3];
    // Per axis, whether the child below a splitting plane is the near one (d >= +0), and
    // 1 / 0 when that holds for all lanes / none, -1 when the lanes differ.
    vbool<K> below_near[3];
    int uniform_below_near[3];
    F tmin, tmax;
    // Watertight test (Woop, Benthin, Wald 2013): the axis where the direction is
    // largest becomes z; kx, ky the other two (swapped when dir[kz] < 0 to keep the
    // winding); shear sx, sy and scale sz map the ray onto +z.
    I kx, ky, kz;
    F sx, sy, sz;
    // When every lane has the same (kx, ky, kz), the vertex components are picked once
    // for the packet instead of per lane.
    bool uniform_axes;
    int ukx, uky, ukz;
};

namespace ray_detail {
template <int K>
PATINA_INLINE vfloat<K> pick(const vfloat<K>* v, vint<K> k) {
    if constexpr (K == 1) {
        return v[k];
    } else {
        return select(k == vint<K>(0), v[0], select(k == vint<K>(1), v[1], v[2]));
    }
}
}  // namespace ray_detail

template <int K>
PATINA_INLINE void prepare_packet(RayPacket<K>& r) {
    using F = vfloat<K>;
    using I = vint<K>;
    const F ax = abs(r.dir[0]), ay = abs(r.dir[1]), az = abs(r.dir[2]);
    const I kz = select((ax >= ay) & (ax >= az), I(0), select(ay >= az, I(1), I(2)));
    I kx = select(kz == I(2), I(0), kz + I(1));
    I ky = select(kx == I(2), I(0), kx + I(1));
    const F dz = ray_detail::pick<K>(r.dir, kz);
    const vbool<K> flip = dz < F(0.0f);
    const I swapped = kx;
    kx = select(flip, ky, kx);
    ky = select(flip, swapped, ky);
    r.kx = kx;
    r.ky = ky;
    r.kz = kz;
    r.sz = F(1.0f) / dz;
    r.sx = ray_detail::pick<K>(r.dir, kx) * r.sz;
    r.sy = ray_detail::pick<K>(r.dir, ky) * r.sz;
    for (int a = 0; a < 3; ++a) {
        r.inv_dir[a] = F(1.0f) / r.dir[a];
        const F m = abs(r.inv_dir[a]);
        r.margin_per_unit[a] = select(m < F(std::numeric_limits<float>::infinity()), m, F(0.0f)) * F(kPlaneMargin);
        r.margin_of_origin[a] = abs(r.org[a]) * r.margin_per_unit[a];
        r.below_near[a] = !signbit(r.dir[a]);
        const int bits = movemask(r.below_near[a]), lanes = (1 << K) - 1;
        r.uniform_below_near[a] = bits == lanes ? 1 : (bits == 0 ? 0 : -1);
    }
    r.ukx = lane(kx, 0);
    r.uky = lane(ky, 0);
    r.ukz = lane(kz, 0);
    if constexpr (K == 1) {
        r.uniform_axes = true;
    } else {
        r.uniform_axes = all((kx == I(r.ukx)) & (ky == I(r.uky)) & (kz == I(r.ukz)));
    }
}

PATINA_END_TARGET
