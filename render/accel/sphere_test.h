// K rays against the analytic spheres (spheres.h), written once for K = 1, 4, 8 and 16: the
// rays in the lanes, the spheres one after another (broadcast), so every width gives every
// lane the same bits.
//
// The quadratic |o + t d - c|^2 = r^2, i.e. a t^2 + 2 b t + c' = 0 with f = o - c, a = d.d,
// b = f.d and c' = f.f - r^2, solved as in "Precision improvements for ray/sphere
// intersection" (Haines, Guenther, Akenine-Moeller; Ray Tracing Gems, ch. 7):
// - the discriminant b^2 - a c' is formed as a (r^2 - |l|^2), l = f - (b / a) d the centre's
//   offset from the ray's closest approach: no cancellation of two large squares when the
//   sphere is small or far (b^2 and a c' nearly equal), only where the ray grazes it;
// - the roots as q / a and c' / q with q = -(b + sign(b) sqrt(a disc)): no cancellation in
//   -b +- sqrt(...) for either root.
// The root c' / q is the one nearer t = 0, and c' ~ 2 r (distance of the origin from the
// surface). A point on the sphere stored in float is off it by the rounding of its
// coordinates (up to 2^-23 (|c|_1 + 3 r) for c + r n), and c' itself is rounded (a few ulps of
// f.f + r^2); where |c'| is within those bounds the origin lies on the sphere as far as float
// can tell (a secondary or shadow ray leaving the surface without an offset), and that root is
// dropped (pbrt-v4 likewise rejects a root whose error interval holds 0): such a ray does not
// hit the sphere at its own origin, yet leaving inwards it still finds the far side. The
// integrator also moves its rays' origins off the surface (RenderScene::ray_offset, far more
// than this bound), so in renders the test only ever decides points well off it.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/simd/simd.h"
#include "render/accel/spheres.h"

PATINA_BEGIN_TARGET

namespace sphere_detail {
// 2^-21 of f.f + r^2: more than c' = f.f - r^2's rounding (f's three differences, the squares
// and sums, r^2 and the difference: at most 6 ulps of 2^-24 to first order); and 2^-21 of
// r (|o|_1 + 6 r): twice 2 r times a stored surface point's distance from the sphere
// (|c|_1 <= |o|_1 + 3 r there).
constexpr float kOnSurface = 0x1p-21f;

// Where K rays meet sphere k (the discriminant >= 0) and their two distances: `outer` = q / a
// and `inner` = c' / q, the root nearer the origin, NaN or infinite where it is undefined.
// inner_ok: false where the origin is on the sphere within rounding (inner is then dropped).
template <int K>
PATINA_INLINE vbool<K> sphere_roots(const SphereSet& s, size_t k, const vfloat<K>* org, const vfloat<K>* dir,
                                    vfloat<K>& inner, vfloat<K>& outer, vbool<K>& inner_ok) {
    using F = vfloat<K>;
    const F r(s.radius[k]);
    const F fx = org[0] - F(s.centre_x[k]), fy = org[1] - F(s.centre_y[k]), fz = org[2] - F(s.centre_z[k]);
    const F a = dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2];
    const F b = fx * dir[0] + fy * dir[1] + fz * dir[2];
    const F along = b / a;
    const F lx = fx - along * dir[0], ly = fy - along * dir[1], lz = fz - along * dir[2];
    const F r2 = r * r;
    const F disc = r2 - (lx * lx + ly * ly + lz * lz);
    const F f2 = fx * fx + fy * fy + fz * fz;
    const F c = f2 - r2;
    const vbool<K> meets = disc >= F(0.0f);
    const F root = sqrt_exact(a * select(meets, disc, F(0.0f)));
    const F q = F(0.0f) - (b + copysign(root, b));
    outer = q / a;
    inner = c / q;
    const F reach = abs(org[0]) + abs(org[1]) + abs(org[2]) + F(6.0f) * r;
    inner_ok = abs(c) > F(kOnSurface) * ((f2 + r2) + r * reach);
    return meets;
}

// 2^-12 of the offset's magnitude: far more than the rounding that decides whether the
// quadratic's line meets the sphere (its closest-approach offset l, a few ulps of |o - c|).
constexpr float kLineSlack = 0x1p-12f;

// Lanes whose line may pass within the sphere's radius of its centre: |f x d|^2 <= a (r + m)^2,
// f = o - c, a = d.d, m = kLineSlack (|f|_1 + r), as a lane's distance |f x d| / |d| from the
// centre to the line, without the quadratic's three divisions and square root. A packet none
// of whose lanes passes near skips the sphere (the lighting bench's shadow rays towards 20
// luminaires mostly pass its five spheres at a distance); a NaN counts as near.
template <int K>
PATINA_INLINE vbool<K> passes_near(const SphereSet& s, size_t k, const vfloat<K>* org, const vfloat<K>* dir) {
    using F = vfloat<K>;
    const F r(s.radius[k]);
    const F fx = org[0] - F(s.centre_x[k]), fy = org[1] - F(s.centre_y[k]), fz = org[2] - F(s.centre_z[k]);
    const F cx = fy * dir[2] - fz * dir[1], cy = fz * dir[0] - fx * dir[2], cz = fx * dir[1] - fy * dir[0];
    const F a = dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2];
    const F reach = r + F(kLineSlack) * (abs(fx) + abs(fy) + abs(fz) + r);
    return !(cx * cx + cy * cy + cz * cz > a * (reach * reach));
}
}  // namespace sphere_detail

// Closest hit: lanes whose nearest sphere root in (tmin, t] (or < t once a sphere holds the
// lane: of equal distances the lower primitive wins, as in the BVH) lowers t and sets prim
// (sphere k: spheres.prim_base + k).
template <int K>
PATINA_INLINE void intersect_spheres(const SphereSet& s, const vfloat<K>* org, const vfloat<K>* dir, vfloat<K> tmin,
                                     vfloat<K>& t, vint<K>& prim) {
    using F = vfloat<K>;
    using B = vbool<K>;
    using I = vint<K>;
    for (size_t k = 0; k < s.size(); ++k) {
        F inner, outer;
        B inner_ok;
        const B meets = sphere_detail::sphere_roots<K>(s, k, org, dir, inner, outer, inner_ok);
        if (none(meets)) continue;
        const B open = prim == I(-1);  // t is still the rays' tmax: a root there counts
        const auto before = [&](F x) { return (x > tmin) & ((x < t) | (open & (x == t))); };
        const B inner_hit = meets & inner_ok & before(inner);
        const B outer_hit = meets & before(outer);
        // the inner root is nearer when both lie ahead (|inner| <= |outer|)
        const B use_inner = inner_hit & ((!outer_hit) | (inner <= outer));
        const B hit = inner_hit | outer_hit;
        t = select(use_inner, inner, select(hit, outer, t));
        prim = select(hit, I(s.prim_base + static_cast<int32_t>(k)), prim);
    }
}

// Any hit: lanes with a sphere root in (tmin, tmax).
template <int K>
PATINA_INLINE vbool<K> occluded_by_spheres(const SphereSet& s, const vfloat<K>* org, const vfloat<K>* dir,
                                           vfloat<K> tmin, vfloat<K> tmax) {
    using F = vfloat<K>;
    using B = vbool<K>;
    B blocked(false);
    for (size_t k = 0; k < s.size(); ++k) {
        if (none(sphere_detail::passes_near<K>(s, k, org, dir))) continue;
        F inner, outer;
        B inner_ok;
        const B meets = sphere_detail::sphere_roots<K>(s, k, org, dir, inner, outer, inner_ok);
        const auto within = [&](F x) { return (x > tmin) & (x < tmax); };
        blocked = blocked | (meets & ((inner_ok & within(inner)) | within(outer)));
        if (all(blocked)) break;
    }
    return blocked;
}

PATINA_END_TARGET
