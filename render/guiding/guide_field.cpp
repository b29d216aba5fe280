#include "render/guiding/guide_field.h"

#include <algorithm>
#include <cmath>

#include "render/guiding/sphere_square.h"

namespace patina::guiding {

namespace {
constexpr int kMaxSpatialDepth = 40;  // identical positions cannot be split apart
}

int32_t GuideField::build_node(std::vector<uint32_t>& idx, size_t begin, size_t end, const float* lo, const float* hi,
                               int depth, const std::vector<GuideRecord>& records, const GuideFieldParams& params) {
    const int32_t node = static_cast<int32_t>(m_nodes.size());
    m_nodes.push_back(Node{-1, 0.0f, {-1, -1}, {-1, -1, -1, -1, -1, -1}});
    const size_t count = end - begin;
    if (count > params.max_leaf_records && depth < kMaxSpatialDepth) {
        int axis = 0;
        for (int a = 1; a < 3; ++a)
            if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
        const float split = 0.5f * (lo[axis] + hi[axis]);
        const size_t mid = std::stable_partition(idx.begin() + begin, idx.begin() + end, [&](uint32_t i) {
                               return records[i].p[axis] < split;
                           }) - idx.begin();
        float lo2[3] = {lo[0], lo[1], lo[2]}, hi1[3] = {hi[0], hi[1], hi[2]};
        hi1[axis] = split;
        lo2[axis] = split;
        const int32_t below = build_node(idx, begin, mid, lo, hi1, depth + 1, records, params);
        const int32_t above = build_node(idx, mid, end, lo2, hi, depth + 1, records, params);
        m_nodes[node].axis = axis;
        m_nodes[node].split = split;
        m_nodes[node].child[0] = below;
        m_nodes[node].child[1] = above;
        return node;
    }
    ++m_leaves;
    // the leaf's records by normal class (stable), a distribution for each class with enough
    std::stable_sort(idx.begin() + begin, idx.begin() + end,
                     [&](uint32_t a, uint32_t b) { return normal_class(records[a].n) < normal_class(records[b].n); });
    std::vector<float> uv, w;
    for (size_t k0 = begin; k0 < end;) {
        const int c = normal_class(records[idx[k0]].n);
        size_t k1 = k0;
        while (k1 < end && normal_class(records[idx[k1]].n) == c) ++k1;
        const size_t n = k1 - k0;
        if (n >= params.min_leaf_records) {
            uv.resize(2 * n);
            w.resize(n);
            for (size_t k = 0; k < n; ++k) {
                const GuideRecord& r = records[idx[k0 + k]];
                direction_to_square(r.d, uv[2 * k], uv[2 * k + 1]);
                w[k] = r.value;
            }
            DirectionalTree tree;
            tree.build(uv.data(), w.data(), n, params.directions);
            if (!tree.empty()) {
                m_nodes[node].tree[c] = static_cast<int32_t>(m_trees.size());
                m_trees.push_back(std::move(tree));
            }
        }
        k0 = k1;
    }
    return node;
}

void GuideField::build(const std::vector<GuideRecord>& records, const GuideFieldParams& params) {
    m_nodes.clear();
    m_trees.clear();
    m_grid.clear();
    m_leaves = 0;
    if (records.empty()) return;
    float lo[3], hi[3];
    for (int a = 0; a < 3; ++a) lo[a] = hi[a] = records[0].p[a];
    for (const GuideRecord& r : records)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], r.p[a]), hi[a] = std::max(hi[a], r.p[a]);
    std::vector<uint32_t> idx(records.size());
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<uint32_t>(i);
    build_node(idx, 0, idx.size(), lo, hi, 0, records, params);
    for (int a = 0; a < 3; ++a) {
        m_lo[a] = lo[a];
        m_cells_per_unit[a] = hi[a] > lo[a] ? kGridSide / (hi[a] - lo[a]) : 0.0f;
    }
    build_grid();
}

void GuideField::build_grid() {
    m_grid.assign(static_cast<size_t>(kGridSide) * kGridSide * kGridSide, 0);
    for (int k = 0; k < kGridSide; ++k)
        for (int j = 0; j < kGridSide; ++j)
            for (int i = 0; i < kGridSide; ++i) {
                const int c[3] = {i, j, k};
                float lo[3], hi[3];
                for (int a = 0; a < 3; ++a) {
                    const float unit = m_cells_per_unit[a] > 0 ? 1.0f / m_cells_per_unit[a] : 0.0f;
                    lo[a] = m_lo[a] + c[a] * unit;
                    hi[a] = m_lo[a] + (c[a] + 1) * unit;
                }
                int32_t node = 0;
                for (;;) {  // down while the split leaves the whole cell on one side
                    const Node& n = m_nodes[node];
                    if (n.axis < 0) break;
                    if (hi[n.axis] <= n.split) node = n.child[0];
                    else if (lo[n.axis] >= n.split) node = n.child[1];
                    else break;
                }
                m_grid[(static_cast<size_t>(k) * kGridSide + j) * kGridSide + i] = node;
            }
}

int32_t GuideField::distribution_at(const float* p, const float* n) const {
    if (m_nodes.empty()) return -1;
    size_t cell = 0;
    for (int a = 2; a >= 0; --a) {
        const float x = (p[a] - m_lo[a]) * m_cells_per_unit[a];
        const int c = x >= 0.0f ? static_cast<int>(std::min(x, static_cast<float>(kGridSide - 1))) : 0;
        cell = cell * kGridSide + static_cast<size_t>(c);
    }
    int32_t node = m_grid[cell];
    while (m_nodes[node].axis >= 0) {
        const Node& n = m_nodes[node];
        node = n.child[p[n.axis] < n.split ? 0 : 1];
    }
    return m_nodes[node].tree[normal_class(n)];
}

void GuideField::sample(int32_t k, float u1, float u2, float* d) const {
    float u, v;
    m_trees[k].sample(u1, u2, u, v);
    square_to_direction(u, v, d);
}

float GuideField::pdf(int32_t k, const float* d) const {
    return m_trees[k].density_at_direction(d) * (1.0f / kSphereArea);
}

}  // namespace patina::guiding
