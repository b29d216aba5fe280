// What the renderer reads: geometry with its shading data, materials, lights, the
// environment and the camera. Plain structs with pointers into arrays owned by the
// caller (the Python side keeps them alive), built once per render.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "brdf/table.h"
#include "core/vec3.h"
#include "fit/lobe_kernels.h"
#include "render/accel/bvh.h"
#include "render/accel/kdtree.h"
#include "render/camera/camera.h"
#include "render/lights/light.h"
#include "render/materials/material.h"

namespace patina {

// A lat-long environment (Mitsuba 3's convention: u -> phi = 2 pi u, v -> theta = pi v,
// d = (sin phi sin theta, cos theta, -cos phi sin theta), y up) or a constant radiance.
// Importance sampled by luminance x sin(theta), piecewise constant per pixel.
struct Environment {
    bool present = false;
    bool is_map = false;
    float constant[3] = {0, 0, 0};
    int width = 0, height = 0;
    const float* rgb = nullptr;  // height x width x 3, linear radiance
    float intensity = 1;
    float rotation = 0;          // radians about +y: the map is turned by this angle
    float cos_rotation = 1, sin_rotation = 0;
    std::vector<float> texels;   // a copy of rgb with one float of padding (the SIMD gathers load 4 floats per texel)
    std::vector<float> row_cdf;  // height + 1 values, 0 .. 1
    // height rows of width + 1 pairs: (column c's cdf, 0 .. 1; pixel c's pdf as in pixel_pdf,
    // 0 after the last column), so a sample's pdf is in the cache line of its cdf values
    std::vector<float> col_cdf_pdf;
    // Where a row's column search starts and ends: for u in [b, b + 1) / col_buckets, the
    // column is in [col_guide[b], col_guide[b + 1]] of the row (col_guide[b] = the last
    // column whose cdf is <= b / col_buckets), so a sample searches a few cdf values of one
    // or two cache lines instead of the whole row. height rows of col_buckets + 1 values.
    int col_buckets = 1;
    std::vector<int32_t> col_guide;
    std::vector<float> pixel_pdf;  // height x width: pdf over (u, v) in [0,1]^2
    float mean_luminance = 0;
};

// An orthonormal tangent t and bitangent b around unit n (Duff et al. 2017, "Building an
// orthonormal basis, revisited"): continuous everywhere but at n.z = -1's sign switch.
void orthonormal_frame(const Vec3f& n, Vec3f& t, Vec3f& b);

// Builds the sampling distribution of a map environment (no-op for a constant one).
void prepare_environment(Environment& env);

struct RenderScene {
    const KdTree* tree = nullptr;
    const Bvh* bvh = nullptr;  // when set: secondary and shadow rays through it, camera rays through the tree
    const float* vertices = nullptr;     // V x 3 (world space)
    const int32_t* indices = nullptr;    // T x 3, in the tree's triangle order
    const float* normals = nullptr;      // V x 3 unit shading normals
    const float* tangents = nullptr;     // V x 3 unit tangents, or nullptr (a frame from the normal)
    const int32_t* tri_material = nullptr;  // T material indices
    size_t triangle_count = 0;
    std::vector<Material> materials;
    std::vector<Light> lights;           // points and quads
    Environment env;
    Camera camera;
    float scene_radius = 1;              // bounding-sphere radius of the geometry (environment power)
    float ray_offset = 1e-4f;            // secondary-ray origin offset, scaled by the scene's size
    // Light selection (render/lights/light_selection.h): lights first (selection[k] is
    // lights[k]'s), then the environment.
    using Selection = LightSelection;
    std::vector<Selection> selection;
};

// Sets scene_radius and ray_offset from the tree's bounds.
void prepare_scale(RenderScene& s);

// Fills `selection` from the lights' and the environment's estimated flux and irradiance.
void prepare_light_selection(RenderScene& s);

}  // namespace patina
