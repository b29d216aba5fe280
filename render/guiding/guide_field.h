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
int normal_class(const float* n);

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
    int32_t build_node(std::vector<uint32_t>& idx, size_t begin, size_t end, const float* lo, const float* hi,
                       int depth, const std::vector<GuideRecord>& records, const GuideFieldParams& params);
    std::vector<Node> m_nodes;
    std::vector<DirectionalTree> m_trees;
    size_t m_leaves = 0;
};

}  // namespace patina::guiding
