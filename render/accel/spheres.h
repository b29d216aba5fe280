// The scene's analytic spheres (scene key "analytic": true on a sphere shape, docs/scene.md):
// exact spheres beside the triangles, intersected by every trace entry point N rays at a time
// (sphere_test.h) instead of being tessellated. A short structure-of-arrays list rather than
// leaves of the kd-tree or the BVH: a scene has a handful of them (the bench's gold sphere has
// one and no triangles at all), each test is a few lanes of arithmetic, and a list keeps both
// structures and their builders untouched. Primitive ids continue the triangles': sphere k is
// primitive prim_base + k (prim_base = the triangle count), so a hit's material is
// tri_material[prim] as for a triangle.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>


namespace patina {

struct SphereSet {
    std::vector<float> centre_x, centre_y, centre_z, radius;  // centres and radii (world space)
    // The object frame of each sphere, for its tangents (9 floats: the world directions of the
    // object's unit x, y and z axes): tangents run along its parallels about the object's y,
    // as the tessellated sphere's do (python/patina/geometry/shapes.py, sphere).
    std::vector<float> axes;
    int32_t prim_base = 0;

    size_t size() const { return radius.size(); }
    bool empty() const { return radius.empty(); }
    bool owns(int32_t prim) const { return prim >= prim_base && prim < prim_base + static_cast<int32_t>(size()); }
    // sphere k as (centre, radius); axes as given (unit, orthogonal); throws std::invalid_argument
    void add(const float centre[3], float r, const float frame[9]);
};

// The smallest box around the spheres into lo, hi (none: lo = +inf, hi = -inf).
void sphere_bounds(const SphereSet& spheres, float lo[3], float hi[3]);

}  // namespace patina
