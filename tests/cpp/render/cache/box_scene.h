// The cache integrators' test scene (tests/cpp/render/integrators/test_cache_integrators.cpp, and
// the trained guide's, tests/cpp/render/guiding/): a small closed box lit by a quad light
// under its ceiling, with coloured walls, an occluder, and camera samples for its pixels.
#pragma once

#include <cstdint>
#include <vector>

#include "render/accel/kdtree.h"
#include "render/integrators/integrator.h"
#include "render/render_job.h"
#include "render/samplers/rng.h"
#include "render/scene.h"

namespace patina::test {

inline Material lambert(float r, float g, float b) {
    Material m;
    const float rgb[3] = {r, g, b};
    Lambert model;
    for (int k = 0; k < 3; ++k) m.albedo[k] = model.reflectance[k] = rgb[k];
    m.model = model;
    return m;
}

inline Conductor metal(float alpha) {
    Conductor c;
    c.alpha_x = c.alpha_y = alpha;
    for (int k = 0; k < 3; ++k) c.eta[k] = 0.2f, c.k[k] = 3.0f;
    return c;
}

struct BoxScene {
    std::vector<float> vertices, normals;
    std::vector<int32_t> indices, materials;
    KdTree tree;
    RenderScene scene;

    // a parallelogram corner + a e1 + b e2 (a, b in [0, 1]), two triangles
    void quad(Vec3f c, Vec3f e1, Vec3f e2, int material) {
        const Vec3f n = normalize(cross(e1, e2));
        const int32_t base = static_cast<int32_t>(vertices.size() / 3);
        const Vec3f p[4] = {c, c + e1, c + e1 + e2, c + e2};
        for (const Vec3f& q : p) {
            vertices.insert(vertices.end(), {q.x, q.y, q.z});
            normals.insert(normals.end(), {n.x, n.y, n.z});
        }
        indices.insert(indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
        materials.insert(materials.end(), {material, material});
    }

    // glossy_floor: the floor a narrow GGX conductor (lobes narrower than two texels at
    // resolution 16: its texel hits take cache.hit_paths paths, split_glossy_hits)
    BoxScene(int width, int height, bool glossy_floor = false) {
        const float s = 2.0f;
        quad({-1, 0, -1}, {0, 0, s}, {s, 0, 0}, glossy_floor ? 5 : 0);   // floor
        quad({-1, 2, -1}, {s, 0, 0}, {0, 0, s}, 0);   // ceiling
        quad({-1, 0, -1}, {s, 0, 0}, {0, s, 0}, 0);   // back
        quad({-1, 0, -1}, {0, s, 0}, {0, 0, s}, 1);   // left, red
        quad({1, 0, -1}, {0, 0, s}, {0, s, 0}, 2);    // right, green
        quad({-1, 0, 1}, {0, s, 0}, {s, 0, 0}, 0);    // front (closed: a furnace-like box)
        // an occluder in the middle, and the light under the ceiling
        quad({-0.3f, 0.6f, -0.3f}, {0.6f, 0, 0}, {0, 0, 0.6f}, 4);
        quad({-0.25f, 1.98f, -0.25f}, {0.5f, 0, 0}, {0, 0, 0.5f}, 3);
        tree = build_kdtree(vertices.data(), vertices.size() / 3, indices.data(), indices.size() / 3, KdBuildOptions{});
        scene.tree = &tree;
        scene.vertices = vertices.data();
        scene.indices = indices.data();
        scene.normals = normals.data();
        scene.tri_material = materials.data();
        scene.triangle_count = indices.size() / 3;
        Material white = lambert(0.7f, 0.7f, 0.7f), red = lambert(0.6f, 0.06f, 0.06f),
                 green = lambert(0.1f, 0.5f, 0.1f), emitter, glossy, narrow;
        glossy.model = metal(0.4f);   // a rough metal: integrated over the texels
        narrow.model = metal(0.25f);  // 0.25 < 2 texels (0.31 at R = 16): split at the texel hits
        emitter.model = Emitter{0};
        for (Material* m : {&white, &red, &green, &emitter, &glossy, &narrow}) m->two_sided = true;
        scene.materials = {white, red, green, emitter, glossy, narrow};
        QuadLight l;
        const float c[3] = {0, 1.98f, 0}, u[3] = {0.25f, 0, 0}, v[3] = {0, 0, 0.25f};
        for (int k = 0; k < 3; ++k) l.center[k] = c[k], l.u[k] = u[k], l.v[k] = v[k], l.radiance[k] = 15.0f;
        l.normal[0] = 0, l.normal[1] = -1, l.normal[2] = 0;  // cross(u, v) = (0, -1/16, 0)
        l.area = 4 * 0.25f * 0.25f;
        l.two_sided = true;
        scene.lights = {Light{l}};
        Camera& cam = scene.camera;
        cam.position[0] = 0, cam.position[1] = 1, cam.position[2] = 0.95f;
        cam.forward[0] = 0, cam.forward[1] = 0, cam.forward[2] = -1;
        cam.tan_half_fov = 0.9f;
        cam.width = width, cam.height = height;
        prepare_scale(scene);
        prepare_light_selection(scene);
    }
};

inline std::vector<CameraSample> pixel_samples(int width, int height, int spp, uint32_t seed) {
    std::vector<CameraSample> cs;
    for (int s = 0; s < spp; ++s)
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const uint32_t key = path_key(seed, static_cast<uint32_t>(y * width + x), static_cast<uint32_t>(s));
                cs.push_back(CameraSample{x + uniform(key, 0), y + uniform(key, 1), stream_key(seed, static_cast<uint32_t>(y * width + x)), static_cast<uint32_t>(s)});
            }
    return cs;
}

// A render job's settings for the box: tiles of 8 pixels, paths of 5 segments, cache points of 16 x 16.
inline RenderOptions box_job_settings(IntegratorMode mode, int threads, int spp, int width = 0) {
    RenderOptions st;
    st.spp = spp;
    st.max_depth = 5;
    st.seed = 5;
    st.threads = threads;
    st.width = width;
    st.tile_size = 8;
    st.mode = mode;
    st.cache.resolution = 16;
    return st;
}

// A job's RGB image (its other outputs dropped).
inline std::vector<float> resolved_rgb(const RenderScene& scene, const RenderJob& job) {
    const size_t n = static_cast<size_t>(scene.camera.width) * scene.camera.height;
    std::vector<float> rgb(3 * n), albedo(3 * n), normal(3 * n), depth(n), lux(n), samples(n);
    job.resolve(rgb.data(), albedo.data(), normal.data(), depth.data(), lux.data(), samples.data());
    return rgb;
}

// A render job run to its end, its RGB image.
inline std::vector<float> rendered_rgb(const RenderScene& scene, const RenderOptions& settings) {
    RenderJob job(scene, settings);
    job.start();
    job.wait();
    return resolved_rgb(scene, job);
}

}  // namespace patina::test
