#include "render/guiding/directional_tree.h"

#include "render/guiding/sphere_square.h"

#include <algorithm>
#include <cmath>

namespace patina::guiding {

int32_t DirectionalTree::build_node(std::vector<uint32_t>& idx, size_t begin, size_t end, float x0, float y0,
                                    float size, int depth, double total, const float* uv, const float* w,
                                    const DirectionalTreeParams& p) {
    const int32_t node = static_cast<int32_t>(m_nodes.size());
    m_nodes.push_back(Node{{0, 0, 0, 0}, {-1, -1, -1, -1}});
    const float h = 0.5f * size, xm = x0 + h, ym = y0 + h;
    // the samples by quadrant (stable: the same order on every machine and thread count)
    const auto lower_v = [&](uint32_t i) { return !(uv[2 * i + 1] >= ym); };
    const auto lower_u = [&](uint32_t i) { return !(uv[2 * i] >= xm); };
    const size_t mid = std::stable_partition(idx.begin() + begin, idx.begin() + end, lower_v) - idx.begin();
    const size_t q1 = std::stable_partition(idx.begin() + begin, idx.begin() + mid, lower_u) - idx.begin();
    const size_t q3 = std::stable_partition(idx.begin() + mid, idx.begin() + end, lower_u) - idx.begin();
    const size_t bounds[5] = {begin, q1, mid, q3, end};  // quadrants 0, 1 (iy 0), 2, 3 (iy 1)
    for (int q = 0; q < 4; ++q) {
        double e = 0;
        for (size_t k = bounds[q]; k < bounds[q + 1]; ++k) e += w[idx[k]];
        m_nodes[node].energy[q] = static_cast<float>(e);
        const size_t count = bounds[q + 1] - bounds[q];
        if (e > p.split_fraction * total && count >= static_cast<size_t>(p.min_split_samples) && depth + 1 < p.max_depth) {
            const int32_t child = build_node(idx, bounds[q], bounds[q + 1], x0 + (q & 1) * h, y0 + (q >> 1) * h, h,
                                             depth + 1, total, uv, w, p);
            m_nodes[node].child[q] = child;
        }
    }
    return node;
}

// Each leaf quadrant's energy becomes keep x its own + per_area x its area; returns the node's sum.
double DirectionalTree::add_floor(int32_t node, double area, double per_area, float keep) {
    double sum = 0;
    for (int q = 0; q < 4; ++q) {
        Node& n = m_nodes[node];
        const int32_t c = n.child[q];
        const double e = c >= 0 ? add_floor(c, 0.25 * area, per_area, keep)
                                : keep * static_cast<double>(n.energy[q]) + per_area * 0.25 * area;
        m_nodes[node].energy[q] = static_cast<float>(e);
        sum += e;
    }
    return sum;
}

void DirectionalTree::build(const float* uv, const float* w, size_t n, const DirectionalTreeParams& params) {
    m_nodes.clear();
    m_top.clear();
    m_total = 0;
    double total = 0;
    for (size_t i = 0; i < n; ++i) total += w[i];
    if (!(total > 0) || !std::isfinite(total)) return;
    std::vector<uint32_t> idx(n);
    for (size_t i = 0; i < n; ++i) idx[i] = static_cast<uint32_t>(i);
    build_node(idx, 0, n, 0.0f, 0.0f, 1.0f, 0, total, uv, w, params);
    m_total = static_cast<float>(add_floor(0, 1.0, params.floor_share * total, 1.0f - params.floor_share));
    m_top.assign(size_t{1} << (2 * kTopLevel), TopCell{-1, 0.0f});
    fill_top(0, 0, 0, 0);
}

// Node `node` at `depth` covers cell (cx, cy) of its level; its quadrants go into the top
// cells they cover.
void DirectionalTree::fill_top(int32_t node, int depth, uint32_t cx, uint32_t cy) {
    const float size = std::ldexp(1.0f, -(depth + 1));  // as density's halvings give it
    for (int q = 0; q < 4; ++q) {
        const uint32_t qx = 2 * cx + (q & 1), qy = 2 * cy + (q >> 1);
        const int32_t child = m_nodes[node].child[q];
        if (child >= 0 && depth + 1 < kTopLevel) {
            fill_top(child, depth + 1, qx, qy);
            continue;
        }
        const int span = 1 << (kTopLevel - depth - 1);  // top cells a side the quadrant covers
        const TopCell cell = child >= 0 ? TopCell{child, 0.0f}
                                        : TopCell{-1, m_nodes[node].energy[q] / (m_total * size * size)};
        for (int j = 0; j < span; ++j)
            for (int i = 0; i < span; ++i)
                m_top[((qy * span + j) << kTopLevel) + qx * span + i] = cell;
    }
}

// u -> the choice between shares a (below) and b (above), u rescaled to [0, 1) in the choice.
static int choose(float a, float b, float& u) {
    const float pa = a / (a + b);
    if (u < pa) {
        u = std::min(u / pa, 0x1.fffffep-1f);
        return 0;
    }
    u = std::min((u - pa) / (1.0f - pa), 0x1.fffffep-1f);
    return 1;
}

void DirectionalTree::sample(float u1, float u2, float& u, float& v) const {
    float x0 = 0, y0 = 0, size = 1;
    int32_t node = 0;
    for (;;) {
        const Node& n = m_nodes[node];
        const int ix = choose(n.energy[0] + n.energy[2], n.energy[1] + n.energy[3], u1);
        const int iy = choose(n.energy[ix], n.energy[ix + 2], u2);
        const int q = ix + 2 * iy;
        size *= 0.5f;
        x0 += ix * size;
        y0 += iy * size;
        if (n.child[q] < 0) break;
        node = n.child[q];
    }
    u = std::min(x0 + u1 * size, 0x1.fffffep-1f);
    v = std::min(y0 + u2 * size, 0x1.fffffep-1f);
}

float DirectionalTree::density(float u, float v) const {
    if (m_nodes.empty()) return 0.0f;
    float x0 = 0, y0 = 0, size = 1;
    int32_t node = 0;
    for (;;) {
        const Node& n = m_nodes[node];
        size *= 0.5f;
        const int ix = u >= x0 + size ? 1 : 0, iy = v >= y0 + size ? 1 : 0;
        const int q = ix + 2 * iy;
        x0 += ix * size;
        y0 += iy * size;
        if (n.child[q] < 0) return n.energy[q] / (m_total * size * size);
        node = n.child[q];
    }
}

float DirectionalTree::density_at_direction(const float* d) const {
    if (m_nodes.empty()) return 0.0f;
    const float v = std::min(std::max(0.5f * (d[2] + 1.0f), 0.0f), 0x1.fffffep-1f);
    const AzimuthBoundaries& bounds = AzimuthBoundaries::get();
    // the top cell: its column by the descent's own azimuth tests, its row by v's bits
    uint32_t cell_u = 0;  // the cell's column at `level`: u in [cell_u, cell_u + 1) / 2^level
    for (int level = 1; level <= kTopLevel; ++level)
        cell_u = 2 * cell_u + (level == 1 ? (d[1] < 0.0f || (d[1] == 0.0f && d[0] < 0.0f) ? 1u : 0u)
                                          : (azimuth_at_or_above(d, bounds, cell_u, level) ? 1u : 0u));
    const uint32_t cell_v = static_cast<uint32_t>(v * static_cast<float>(1 << kTopLevel));
    const TopCell& top = m_top[(cell_v << kTopLevel) + cell_u];
    if (top.node < 0) return top.density;
    float size = 1.0f / static_cast<float>(1 << kTopLevel), y0 = static_cast<float>(cell_v) * size;
    int32_t node = top.node;
    for (int level = kTopLevel + 1;; ++level) {
        const Node& n = m_nodes[node];
        size *= 0.5f;
        int ix;
        if (level <= AzimuthBoundaries::kLevels)
            ix = azimuth_at_or_above(d, bounds, cell_u, level) ? 1 : 0;
        else {  // deeper than the table (max_depth above its levels): the azimuth itself
            float u, unused;
            direction_to_square(d, u, unused);
            ix = u >= static_cast<float>(2 * cell_u + 1) * size ? 1 : 0;
        }
        const int iy = v >= y0 + size ? 1 : 0;
        const int q = ix + 2 * iy;
        cell_u = 2 * cell_u + static_cast<uint32_t>(ix);
        y0 += iy * size;
        if (n.child[q] < 0) return n.energy[q] / (m_total * size * size);
        node = n.child[q];
    }
}

}  // namespace patina::guiding
