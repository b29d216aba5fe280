// cache-guided's scene-wide guide (docs/radiance-cache.md, "The trained guide"): the incident
// radiance of the whole scene as practical path guiding's SD-tree (Mueller et al. 2017) holds
// it -- a binary tree over space, each leaf a directional quadtree (directional_tree.h) of
// the radiance the training passes' path vertices in that leaf measured, over the whole
// sphere in world space. Built from one list of records (guide_record.h) at a time, the same
// list giving the same field bit for bit: a node is split at the middle of its longest side
// while it holds more than max_leaf_records records; a leaf with fewer than
// min_leaf_records, or no light among them, has no distribution (its vertices are left to
// BRDF sampling). Read-only once built: any number of threads sample it at once.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/guiding/directional_tree.h"
#include "render/guiding/guide_record.h"

namespace patina::guiding {

// A leaf's records are split by their normal's class (normal_class: its largest component
// and that one's sign), one distribution each: the light a floor receives and a wall beside
// it receives are different hemispheres of the same sphere, and each distribution holds
// radiance x the cosine of its own surfaces (no mass under their horizon).
inline constexpr int kNormalClasses = 6;
inline int normal_class(const float* n) {  // inline: every guided vertex asks
    const float ax = n[0] < 0 ? -n[0] : n[0], ay = n[1] < 0 ? -n[1] : n[1], az = n[2] < 0 ? -n[2] : n[2];
    const int axis = az > (ay > ax ? ay : ax) ? 2 : (ay > ax ? 1 : 0);
    return 2 * axis + (n[axis] < 0 ? 1 : 0);
}

struct GuideFieldParams {
    size_t max_leaf_records = 2000;
    size_t min_leaf_records = 64;
    DirectionalTreeParams directions;
};

class GuideField {
public:
    void build(const std::vector<GuideRecord>& records, const GuideFieldParams& params = {});
    // The distribution (an index) for a point p with shading normal n: its leaf's for normals
    // like n, or -1 where there is none.
    int32_t distribution_at(const float* p, const float* n) const;
    // A unit world direction d drawn from distribution k by uniforms u1, u2 in [0, 1).
    void sample(int32_t k, float u1, float u2, float* d) const;
    // Distribution k's density (solid angle) at unit world direction d.
    float pdf(int32_t k, const float* d) const;
    size_t leaves() const { return m_leaves; }
    size_t distributions() const { return m_trees.size(); }
    bool empty() const { return m_trees.empty(); }

private:
    struct Node {
        int32_t axis;      // 0, 1, 2: split at `split` along it; -1: a leaf
        float split;
        int32_t child[2];  // below, above the split (an inner node)
        int32_t tree[kNormalClasses];  // a leaf's distribution per normal class, or -1
    };
    // The lookup's start: a kGridSide^3 grid over the records' bounds, each cell holding the
    // deepest node whose box holds the whole cell, so a lookup walks only the splits that
    // cut its cell (docs/radiance-cache.md, "The trained guide").
    static constexpr int kGridSide = 16;
    void build_grid();
    int32_t build_node(std::vector<uint32_t>& idx, size_t begin, size_t end, const float* lo, const float* hi,
                       int depth, const std::vector<GuideRecord>& records, const GuideFieldParams& params);
    std::vector<Node> m_nodes;
    std::vector<DirectionalTree> m_trees;
    std::vector<int32_t> m_grid;  // kGridSide^3 start nodes, x fastest
    float m_lo[3] = {0, 0, 0}, m_cells_per_unit[3] = {0, 0, 0};
    size_t m_leaves = 0;
};

}  // namespace patina::guiding
