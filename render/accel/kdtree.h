// A kd-tree over triangles, built with the surface-area heuristic (SAH) in
// O(N log N): binned, with the exact SAH at the triangle bounds near each axis's best
// binned plane (the event sweep of Wald and Havran, 2006, over those bounds), split
// clipping ("perfect splits"), an empty-space bonus and compact 8-byte nodes. Traversal
// lives in traverse.h; building in kdtree_build.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/accel/spheres.h"

namespace patina {

struct Box3 {
    float lo[3] = {0, 0, 0};
    float hi[3] = {0, 0, 0};
    float area() const;
    bool empty() const { return lo[0] > hi[0] || lo[1] > hi[1] || lo[2] > hi[2]; }
};

// 8 bytes. The low 2 bits of `bits` hold the split axis (0-2) or 3 for a leaf.
// Interior: `split` is the plane's position, the child below the plane is the next
// node, and bits >> 2 is the index of the child above it. Leaf: `first` indexes
// KdTree::leaf_prims and bits >> 2 is the number of triangles.
struct KdNode {
    union {
        float split;
        uint32_t first;
    };
    uint32_t bits;

    bool is_leaf() const { return (bits & 3u) == 3u; }
    int axis() const { return static_cast<int>(bits & 3u); }
    uint32_t above() const { return bits >> 2; }
    uint32_t count() const { return bits >> 2; }
};
static_assert(sizeof(KdNode) == 8, "kd-tree nodes are 8 bytes");

struct KdBuildOptions {
    int max_depth = 0;   // 0: 4.5 + log2(N), at most 64 (deeper trees cost packets more than they save)
    int max_leaf = 1;    // a node with this many triangles or fewer becomes a leaf
    float traversal_cost = 1.0f;
    float intersection_cost = 1.5f;
    float empty_bonus = 0.2f;  // cost reduction for a split that cuts off empty space
    int threads = 0;           // 0: all hardware threads (subtrees built in parallel)
};

struct KdTreeStats {
    size_t nodes = 0, leaves = 0, empty_leaves = 0, leaf_refs = 0;
    int depth = 0;
    double build_seconds = 0;
};

struct KdTree {
    std::vector<KdNode> nodes;
    std::vector<uint32_t> leaf_prims;
    std::vector<float> triangles;  // 9 floats per triangle: v0, v1, v2
    std::vector<float> normals;    // 3 floats per triangle: unit cross(v1 - v0, v2 - v0), 0 if degenerate
    Box3 bounds;  // the triangles'
    KdTreeStats stats;
    SphereSet spheres;  // analytic spheres, traced beside the tree (primitives triangle_count() on)

    size_t triangle_count() const { return triangles.size() / 9; }
};

// vertices: V x 3 floats; indices: T x 3, each < V (the caller checks both).
KdTree build_kdtree(const float* vertices, size_t vertex_count, const int32_t* indices, size_t triangle_count,
                    const KdBuildOptions& options);

}  // namespace patina
