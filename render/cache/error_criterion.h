// When a shading point B may take its incident radiance from cache point A, and so where
// new cache points go (docs/radiance-cache.md): Ward's irradiance-cache error, the distance
// over A's harmonic mean hit distance plus the normals' divergence,
//     e(A, B) = |B - A| / R_A + sqrt(1 - nA . nB),
// B uses the A of least error if it is at most the bound (cache.error); a point no cache
// point serves becomes one. Reprojection corrects the parallax Ward's extrapolation could
// not, so the bound can be looser than an irradiance cache's; what it still bounds is what
// reprojection cannot know: geometry A did not see (the holes traced from B grow with it).
// R_A is at least kMinReusePixels pixel footprints (at A's distance from the camera) over
// the bound, as radiance caches clamp their radii to the image (Krivanek et al.): near
// corners the harmonic mean would otherwise place a cache point every pixel, where
// reprojection (unlike extrapolation) still serves a few pixels around.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/vec3.h"
#include "render/cache/cache_point.h"

PATINA_BEGIN_TARGET
namespace cache {

constexpr float kMinReusePixels = 3.0f;

inline float reuse_error(const Vec3f& pa, const Vec3f& na, float radius, const Vec3f& p, const Vec3f& n) {
    const Vec3f d = p - pa;
    const float dist = std::sqrt(dot(d, d));
    const float spread = std::sqrt(std::max(0.0f, 1.0f - dot(n, na)));
    return (radius > 0 ? dist / radius : INFINITY) + spread;
}

inline float reuse_error(const CachePoint& a, const Vec3f& p, const Vec3f& n) {
    return reuse_error(a.p, a.n, a.reuse_radius, p, n);
}

}  // namespace cache
PATINA_END_TARGET
