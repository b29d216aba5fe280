// Shading geometry at analytic-sphere hits (render/accel/spheres.h), K hits at a time, for
// make_shading_lanes (render/integrators/shading_points_impl.h) and every other reader of a hit's primitive: the
// exact outward normal, the point moved onto the sphere, and a tangent along the sphere's
// parallels about its object y axis, as the tessellated sphere's vertex tangents run
// (python/patina/geometry/shapes.py, sphere), so anisotropic materials turn the same way on
// both. The tessellated sphere has no uvs; neither has this one.
#pragma once

#include "core/simd/simd.h"
#include "core/vec3.h"
#include "render/accel/spheres.h"

PATINA_BEGIN_TARGET

// Lanes whose primitive is an analytic sphere (none without spheres).
template <int K>
PATINA_INLINE vbool<K> sphere_lanes(const SphereSet& s, vint<K> prim) {
    if (s.empty()) return vbool<K>(false);
    return (prim > vint<K>(s.prim_base - 1)) & (prim < vint<K>(s.prim_base + static_cast<int32_t>(s.size())));
}

// The unit outward normal at o + t d on sphere k (k a valid index in every lane).
template <int K>
PATINA_INLINE Vec3<vfloat<K>> sphere_normal(const SphereSet& s, vint<K> k, const Vec3<vfloat<K>>& o,
                                            const Vec3<vfloat<K>>& d, vfloat<K> t) {
    using F = vfloat<K>;
    const Vec3<F> c{gather(s.centre_x.data(), k), gather(s.centre_y.data(), k), gather(s.centre_z.data(), k)};
    const Vec3<F> e = (o + t * d) - c;
    const F len = sqrt_exact(dot(e, e));
    return Vec3<F>{e.x / len, e.y / len, e.z / len};
}

// Sphere hits' point, geometric and shading normal (the same: the exact one) and unit tangent,
// written into the lanes of `on` (sphere_lanes of prim); the other lanes keep theirs. The
// point is put back on the sphere (c + r n): its error then scales with the sphere, not with
// the hit distance, so the integrator's ray offset clears the surface however far the camera.
template <int K>
PATINA_INLINE void sphere_points(const SphereSet& s, vbool<K> on, vint<K> prim, const Vec3<vfloat<K>>& o,
                                 const Vec3<vfloat<K>>& d, vfloat<K> t, Vec3<vfloat<K>>& p, Vec3<vfloat<K>>& ng,
                                 Vec3<vfloat<K>>& n, Vec3<vfloat<K>>& tangent) {
    using F = vfloat<K>;
    using I = vint<K>;
    const I k = select(on, prim - I(s.prim_base), I(0));
    const Vec3<F> m = sphere_normal<K>(s, k, o, d, t);
    const F r = gather(s.radius.data(), k);
    const Vec3<F> on_sphere =
        Vec3<F>{gather(s.centre_x.data(), k), gather(s.centre_y.data(), k), gather(s.centre_z.data(), k)} + r * m;
    const I a9 = k * I(9);
    const auto axis = [&](int i) {
        return Vec3<F>{gather(s.axes.data(), a9 + I(3 * i)), gather(s.axes.data(), a9 + I(3 * i + 1)),
                       gather(s.axes.data(), a9 + I(3 * i + 2))};
    };
    const Vec3<F> ax = axis(0), az = axis(2);
    // in the object frame the point is (x, y, z) = (cos phi, y, sin phi) sin-scaled, its
    // parallel's direction (-z, 0, x); at the poles the tessellated sphere's (1, 0, 0)
    const F qx = dot(m, ax), qz = dot(m, az);
    const F len = sqrt_exact(qx * qx + qz * qz);
    const vbool<K> pole = !(len > F(1e-6f));
    const F safe = select(pole, F(1.0f), len);
    const Vec3<F> along = (F(0.0f) - qz / safe) * ax + (qx / safe) * az;
    const Vec3<F> tu = Vec3<F>{select(pole, ax.x, along.x), select(pole, ax.y, along.y), select(pole, ax.z, along.z)};
    const auto pick = [&](Vec3<F>& dst, const Vec3<F>& src) {
        dst = Vec3<F>{select(on, src.x, dst.x), select(on, src.y, dst.y), select(on, src.z, dst.z)};
    };
    pick(p, on_sphere);
    pick(ng, m);
    pick(n, m);
    pick(tangent, tu);
}

PATINA_END_TARGET
