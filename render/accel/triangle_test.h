// K rays against one triangle, watertight: no ray slips between two triangles that
// share an edge or a vertex (Woop, Benthin, Wald, "Watertight ray/triangle
// intersection", 2013). The edge functions U, V, W are recomputed in double where
// one of them is exactly 0, as the paper prescribes for single precision.
#pragma once

#include "render/accel/ray_packet.h"

PATINA_BEGIN_TARGET

template <int K>
struct HitPacket {
    vfloat<K> t, u, v;
    vint<K> prim;
};

namespace tri_detail {
// Vertex components relative to the ray origin, in the ray's sheared frame.
template <int K>
PATINA_INLINE void sheared(const RayPacket<K>& r, const float* p, vfloat<K>& x, vfloat<K>& y, vfloat<K>& z) {
    using F = vfloat<K>;
    if (r.uniform_axes) {
        // the packet's axes are known: only the three components needed, in their places
        z = F(p[r.ukz]) - r.org[r.ukz];
        x = (F(p[r.ukx]) - r.org[r.ukx]) - r.sx * z;
        y = (F(p[r.uky]) - r.org[r.uky]) - r.sy * z;
    } else {
        const F rel[3] = {F(p[0]) - r.org[0], F(p[1]) - r.org[1], F(p[2]) - r.org[2]};
        z = ray_detail::pick<K>(rel, r.kz);
        x = ray_detail::pick<K>(rel, r.kx) - r.sx * z;
        y = ray_detail::pick<K>(rel, r.ky) - r.sy * z;
    }
}

// 2D cross products in double for the lanes where the float result is exactly 0.
template <int K>
PATINA_INLINE void refine_in_double(vfloat<K>& u, vfloat<K>& v, vfloat<K>& w, vfloat<K> ax, vfloat<K> ay, vfloat<K> bx,
                                    vfloat<K> by, vfloat<K> cx, vfloat<K> cy) {
    if constexpr (K == 1) {
        u = float(double(cx) * double(by) - double(cy) * double(bx));
        v = float(double(ax) * double(cy) - double(ay) * double(cx));
        w = float(double(bx) * double(ay) - double(by) * double(ax));
    } else {
        alignas(32) float U[K], V[K], W[K];
        u.store(U);
        v.store(V);
        w.store(W);
        for (int j = 0; j < K; ++j) {
            if (U[j] != 0.0f && V[j] != 0.0f && W[j] != 0.0f) continue;
            const double Ax = lane(ax, j), Ay = lane(ay, j), Bx = lane(bx, j), By = lane(by, j);
            const double Cx = lane(cx, j), Cy = lane(cy, j);
            U[j] = float(Cx * By - Cy * Bx);
            V[j] = float(Ax * Cy - Ay * Cx);
            W[j] = float(Bx * Ay - By * Ax);
        }
        u = vfloat<K>::load(U);
        v = vfloat<K>::load(V);
        w = vfloat<K>::load(W);
    }
}
}  // namespace tri_detail

// Lanes of `active` whose hit on triangle `tri` (9 floats) lies in (tmin, hit.t]
// (closest hit) or (tmin, tmax) (any hit, kAnyHit) — returned as a mask; for the
// closest hit, hit is updated in those lanes.
template <int K, bool kAnyHit>
PATINA_INLINE vbool<K> intersect_triangle(const RayPacket<K>& r, const float* tri, int32_t prim, vbool<K> active,
                                          HitPacket<K>& hit) {
    using F = vfloat<K>;
    F ax, ay, az, bx, by, bz, cx, cy, cz;
    tri_detail::sheared<K>(r, tri, ax, ay, az);
    tri_detail::sheared<K>(r, tri + 3, bx, by, bz);
    tri_detail::sheared<K>(r, tri + 6, cx, cy, cz);
    F u = cx * by - cy * bx;
    F v = ax * cy - ay * cx;
    F w = bx * ay - by * ax;
    if (any(active & ((u == F(0.0f)) | (v == F(0.0f)) | (w == F(0.0f)))))
        tri_detail::refine_in_double<K>(u, v, w, ax, ay, bx, by, cx, cy);
    const vbool<K> negative = (u < F(0.0f)) | (v < F(0.0f)) | (w < F(0.0f));
    const vbool<K> positive = (u > F(0.0f)) | (v > F(0.0f)) | (w > F(0.0f));
    const F det = u + v + w;
    vbool<K> valid = andnot(negative & positive, active) & (det != F(0.0f));
    if (none(valid)) return valid;
    const F t_scaled = (u * az + v * bz + w * cz) * r.sz;  // t * det
    const F signed_t = xorsign(t_scaled, det);             // t * |det|
    const F abs_det = abs(det);
    const F upper = kAnyHit ? r.tmax : hit.t;
    valid = valid & (signed_t > r.tmin * abs_det);
    valid = valid & (kAnyHit ? (signed_t < upper * abs_det) : (signed_t <= upper * abs_det));
    if (kAnyHit || none(valid)) return valid;
    const F inv_det = F(1.0f) / det;
    hit.t = select(valid, t_scaled * inv_det, hit.t);
    hit.u = select(valid, v * inv_det, hit.u);
    hit.v = select(valid, w * inv_det, hit.v);
    hit.prim = select(valid, vint<K>(prim), hit.prim);
    return valid;
}

PATINA_END_TARGET
