// A spatial cell's distribution of incident radiance over directions (docs/radiance-cache.md,
// "The trained guide"): a quadtree over the unit square of sphere_square.h, as practical path
// guiding's (Mueller et al. 2017) directional part. Built from weighted samples (a training
// pass's records): a quadrant is subdivided while it holds more than kSplitFraction of the
// cell's energy and at least kMinSplitSamples samples, so the cells are fine where light
// comes from and coarse elsewhere, and never finer than the samples resolve (a single
// bright sample cannot grow a spike down to the deepest level). Every leaf keeps a floor
// share of the energy in proportion to its area (kFloorShare): a direction the training
// found dark may still hold light. Sampling descends the tree with two uniforms, each
// level's choice rescaling them; the density is the leaf's energy over its area, looked up
// from a direction by sign tests alone (density_at_direction: no arc tangent).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace patina::guiding {

struct DirectionalTreeParams {
    float split_fraction = 0.01f;  // a quadrant with more of the energy is subdivided...
    int min_split_samples = 8;     // ...if it holds at least this many samples...
    int max_depth = 10;            // ...down to this level (1 / 2^10 of the square a side)
    float floor_share = 0.1f;      // of the energy spread over the square by area
};

class DirectionalTree {
public:
    // From n samples at (uv[2i], uv[2i + 1]) in [0, 1)^2 with weights w[i] >= 0; empty when
    // their weights sum to nothing (or are not finite).
    void build(const float* uv, const float* w, size_t n, const DirectionalTreeParams& params = {});
    bool empty() const { return m_nodes.empty(); }
    // A point of the square drawn from the distribution by uniforms u1, u2 in [0, 1).
    void sample(float u1, float u2, float& u, float& v) const;
    // The density at (u, v) with respect to area on the unit square (integrates to 1).
    float density(float u, float v) const;
    // The same density at the point of the square a unit world direction d maps to
    // (sphere_square.h), without computing its azimuth: the descent's azimuth tests are
    // algebraic (azimuth_at_or_above).
    float density_at_direction(const float* d) const;
    size_t nodes() const { return m_nodes.size(); }

private:
    struct Node {
        float energy[4];      // quadrant q = ix + 2 iy (ix, iy: the upper half in u, v)
        int32_t child[4];     // the quadrant's node, or -1 for a leaf quadrant
    };
    int32_t build_node(std::vector<uint32_t>& idx, size_t begin, size_t end, float x0, float y0, float size,
                       int depth, double total, const float* uv, const float* w, const DirectionalTreeParams& p);
    double add_floor(int32_t node, double area, double per_area, float keep);
    // The lookup's start (density_at_direction): the square as 2^kTopLevel x 2^kTopLevel
    // cells, each the node of that level that covers it or, where a leaf is coarser, the
    // leaf's density, so a lookup walks only the levels below kTopLevel.
    static constexpr int kTopLevel = 4;
    struct TopCell {
        int32_t node;   // the node covering the cell at level kTopLevel, or -1: ...
        float density;  // ...a coarser leaf's density
    };
    void fill_top(int32_t node, int depth, uint32_t cx, uint32_t cy);
    std::vector<Node> m_nodes;
    std::vector<TopCell> m_top;  // row (v) major
    float m_total = 0;
};

}  // namespace patina::guiding
