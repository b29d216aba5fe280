// The one 3-vector type: Vec3<float> for scalar geometry (a shading point's position and
// frame), Vec3<vfloat<N>> for N vectors at once, one component per register (structure of
// arrays), as the SIMD kernels use them. The operations are written once for both.
#pragma once

#include <cmath>

#include "core/simd/target.h"

namespace patina {

// Plain data, outside the per-ISA namespaces so structs shared by every width (ShadingPoint)
// can hold one; its operations below are per ISA, like all code (core/simd/target.h).
template <class F>
struct Vec3 {
    F x, y, z;
};
using Vec3f = Vec3<float>;

}  // namespace patina

PATINA_BEGIN_TARGET

template <class F>
PATINA_INLINE F dot(const Vec3<F>& a, const Vec3<F>& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class F>
PATINA_INLINE Vec3<F> cross(const Vec3<F>& a, const Vec3<F>& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class F>
PATINA_INLINE Vec3<F> operator-(const Vec3<F>& a) {
    return {-a.x, -a.y, -a.z};
}
template <class F>
PATINA_INLINE Vec3<F> operator+(const Vec3<F>& a, const Vec3<F>& b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class F>
PATINA_INLINE Vec3<F> operator-(const Vec3<F>& a, const Vec3<F>& b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class F>
PATINA_INLINE Vec3<F> operator*(F s, const Vec3<F>& a) {
    return {s * a.x, s * a.y, s * a.z};
}

// Scalar vectors to and from the (n, 3) float arrays the kernels read and write.
PATINA_INLINE Vec3f load_vec3(const float* p) { return {p[0], p[1], p[2]}; }
PATINA_INLINE void store_vec3(const Vec3f& v, float* p) {
    p[0] = v.x;
    p[1] = v.y;
    p[2] = v.z;
}

// a / |a| (a zero vector stays zero), each component divided, as the scalar code always has.
PATINA_INLINE Vec3f normalize(const Vec3f& a) {
    const float len = std::sqrt(dot(a, a));
    return len > 0 ? Vec3f{a.x / len, a.y / len, a.z / len} : a;
}

PATINA_END_TARGET
