// A cache point of the high-frequency radiance cache (docs/radiance-cache.md): the incident
// radiance over one shading point A's hemisphere, as an R x R texture in the equal-area
// parametrization (render/cache/hemisphere.h), and the geometry A saw, as surfels in depth
// layers, for reprojection into a nearby point's hemisphere (render/cache/reprojection_impl.h).
//
// The cached quantity is indirect incident radiance: per texel one path-traced sample of the
// radiance arriving at A from that texel's solid angle, without the emission A sees
// directly (lights and the environment, which the integrators take by light sampling and
// MIS), i.e. the light the hit surface reflects towards A -- at max_depth 3 (Mitsuba's
// count) exactly the direct light at the hits, deeper the full indirect radiance.
#pragma once

#include <cstdint>
#include <vector>

#include "core/vec3.h"

namespace patina {

// A planar patch of what A saw: a square block of texels of one depth layer whose hits lie
// on one plane (merged from neighbours with close normals), its outline the block's border
// rays cut by that plane.
struct Surfel {
    Vec3f point, normal;    // on its plane; the normal faces A
    int16_t i0, j0, i1, j1; // texels [i0, i1) x [j0, j1) of A's texture (i: u, j: v)
    int32_t layer;
};

// A silhouette edge of a surfel: a texel edge where A's view jumps from the surfel to
// something much farther (or to nothing). Behind it lies space A could not see; from a
// nearby point that space projects between the edge and the edge's directions from A
// (its points at infinity), which is the surfel's unknown (shadow) mask.
struct Silhouette {
    Vec3f e0, e1;  // the edge's end points on the surfel's plane
    Vec3f d0, d1;  // their directions from A (unit, world)
    int32_t layer;
};

constexpr int kOutlinePoints = 8;  // a surfel's corners and edge midpoints, counter-clockwise

struct CachePoint {
    Vec3f p, ng;        // position and geometric normal (towards the viewer)
    Vec3f t, b, n;      // the hemisphere's frame: tangent, bitangent, shading normal
    int resolution = 0; // R: texels per side
    float reuse_radius = 0;  // the harmonic mean distance of A's hits (error criterion)
    // per texel (j * R + i): radiance (RGB), hit distance (inf: a miss), what A saw there
    std::vector<float> radiance, dist;
    std::vector<uint8_t> kind;  // kTexelHit, kTexelMiss, kTexelBelow (under the geometric surface)
    std::vector<float> hit_point, hit_normal;  // hits: where, and the unit normal there (facing A)
    std::vector<Surfel> surfels;       // sorted by layer, near to far
    std::vector<int32_t> layer_start;  // layer k: surfels [layer_start[k], layer_start[k + 1])
    // the surfels' outline points, structure of arrays for reprojecting N surfels at a time:
    // component c of point k of surfel s at outline[(3 k + c) * surfels.size() + s]
    std::vector<float> outline;
    std::vector<Silhouette> silhouettes;     // sorted by layer
    std::vector<int32_t> silhouette_start;   // per layer, as layer_start
};

constexpr uint8_t kTexelHit = 0, kTexelMiss = 1, kTexelBelow = 2;

}  // namespace patina
