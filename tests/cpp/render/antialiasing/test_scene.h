// A scene for the adaptive antialiasing's pre-pass tests (tests/cpp/render/antialiasing/test_edge_hints.cpp,
// tests/cpp/render/antialiasing/test_highlights.cpp): triangles looked at from 2 m above z = 0, down -z, through a
// pinhole of tan(half fov) 0.5, so a metre on the plane z = 0 spans width / 4 pixels.
#pragma once

#include <cstdint>
#include <vector>

#include "render/accel/kdtree.h"
#include "render/scene.h"

namespace aa_test {

// The arrays stay the caller's: the scene points into them.
inline patina::RenderScene looking_down(const patina::KdTree& tree, const std::vector<int32_t>& indices,
                                        const std::vector<float>& normals, const std::vector<int32_t>& materials,
                                        int width, int height) {
    patina::RenderScene s;
    s.tree = &tree;
    s.indices = indices.data();
    s.normals = normals.data();
    s.tri_material = materials.data();
    s.triangle_count = indices.size() / 3;
    s.camera.position[2] = 2;
    s.camera.tan_half_fov = 0.5f;
    s.camera.width = width;
    s.camera.height = height;
    return s;
}

}  // namespace aa_test
