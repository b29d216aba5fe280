// An 8-wide bounding volume hierarchy over triangles, for incoherent rays traced one at a
// time with the SIMD lanes over a node's children (bvh_traverse.h). Each node holds its eight
// children's boxes as structure of arrays; leaves are runs of blocks of eight triangles, also
// structure of arrays, tested up to eight at a time (eight-triangle blocks measured about 10 %
// faster than four-triangle ones at width 8); leaves of less than a block share blocks. Built top down with the binned surface-area
// heuristic (bvh_build.cpp); the kd-tree (kdtree.h) keeps the coherent camera rays.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/accel/kdtree.h"

namespace patina {

constexpr int kBvhWidth = 8;       // children per node
constexpr int kBvhBlock = 8;       // triangles per leaf block
constexpr int kBvhMaxDepth = 64;   // nodes on a root-to-leaf path, at most (the builder ensures it)
constexpr int kBvhMaxLeafBlocks = 16;

// A child reference: an interior node's index, a leaf (kBvhLeaf | blocks - 1 << 27 | first
// block), or kBvhEmpty for an unused slot (whose box is empty: lo = +inf, hi = -inf).
constexpr uint32_t kBvhLeaf = 0x80000000u;
constexpr uint32_t kBvhEmpty = 0xffffffffu;
constexpr uint32_t kBvhBlockBits = 27;
inline bool bvh_is_leaf(uint32_t child) { return (child & kBvhLeaf) != 0; }
inline uint32_t bvh_leaf_first(uint32_t child) { return child & ((1u << kBvhBlockBits) - 1); }
inline uint32_t bvh_leaf_blocks(uint32_t child) { return ((child >> kBvhBlockBits) & 15u) + 1; }

// box[2 a] and box[2 a + 1]: the children's lower and upper bounds on axis a.
struct alignas(32) BvhNode {
    float box[6][kBvhWidth];
    uint32_t child[kBvhWidth];
};
static_assert(sizeof(BvhNode) == 224, "a node is seven 32-byte lines");

// v[corner][axis][lane]: triangle `lane`'s corner (v0, v1, v2) on each axis; a block that is
// not full repeats its last triangle (the same primitive, so the same hit). A block may hold
// several small leaves (bvh_build.cpp): a ray entering one tests the others' triangles too,
// real triangles whose hits are true hits, so the closest and any hit are unchanged. 320 bytes,
// aligned to 64: five cache lines wherever the array starts.
struct alignas(64) BvhBlock {
    float v[3][3][kBvhBlock];
    int32_t prim[kBvhBlock];
};

struct BvhBuildOptions {
    int max_leaf = 8;              // triangles a leaf may hold when the SAH prefers it (at most 128)
    float node_cost = 1.0f;        // SAH cost of testing a node's children, against
    float block_cost = 1.0f;       // the cost of testing a block of triangles
};

struct BvhStats {
    size_t nodes = 0, leaves = 0, blocks = 0;
    int depth = 0;
    double build_seconds = 0;
};

struct Bvh {
    std::vector<BvhNode> nodes;
    std::vector<BvhBlock> blocks;
    uint32_t root = kBvhEmpty;  // a child reference: node 0, a single leaf, or empty
    Box3 bounds;
    // Per axis, the largest |coordinate| of the geometry: box-test rounding margins scale with it.
    float extent[3] = {0, 0, 0};
    BvhStats stats;
    SphereSet spheres;  // analytic spheres, traced beside the hierarchy (a copy of the kd-tree's)
};

// triangles: 9 floats each (v0, v1, v2), e.g. KdTree::triangles; primitive i is triangle i.
Bvh build_bvh(const float* triangles, size_t triangle_count, const BvhBuildOptions& options = {});

}  // namespace patina
