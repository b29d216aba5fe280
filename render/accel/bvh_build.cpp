// Top-down build of the 8-wide BVH. A node starts as one range of triangles; the child with
// the largest surface area is split in two by the binned SAH (32 bins per axis over the
// centroids) until the node has eight children or none is worth splitting, then each child
// is built the same way. Deep in a degenerate input (beyond kForcedDepth) ranges are halved
// by count instead, so no path exceeds kBvhMaxDepth nodes and the traversal stack suffices.
// Leaves of at most a block are packed into blocks shared with other small leaves nearby.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "render/accel/bvh.h"

namespace patina {
namespace {

constexpr int kBins = 32;
// Below this depth splits are the SAH's; from it on they halve the count: each level then
// divides the largest child by at least 4, so 2^27 triangles need at most 14 levels more.
constexpr int kForcedDepth = kBvhMaxDepth - 20;

struct PrimRef {
    Box3 box;
    float centroid[3];
    uint32_t prim;
};

Box3 empty_box() {
    Box3 b;
    for (int a = 0; a < 3; ++a) {
        b.lo[a] = std::numeric_limits<float>::infinity();
        b.hi[a] = -std::numeric_limits<float>::infinity();
    }
    return b;
}

void grow(Box3& b, const Box3& o) {
    for (int a = 0; a < 3; ++a) {
        b.lo[a] = std::min(b.lo[a], o.lo[a]);
        b.hi[a] = std::max(b.hi[a], o.hi[a]);
    }
}

void grow(Box3& b, const float* p) {
    for (int a = 0; a < 3; ++a) {
        b.lo[a] = std::min(b.lo[a], p[a]);
        b.hi[a] = std::max(b.hi[a], p[a]);
    }
}

float half_area(const Box3& b) {
    if (b.empty()) return 0.0f;
    const float x = b.hi[0] - b.lo[0], y = b.hi[1] - b.lo[1], z = b.hi[2] - b.lo[2];
    return x * y + y * z + z * x;
}

float blocks_of(size_t n) { return static_cast<float>((n + kBvhBlock - 1) / kBvhBlock); }

struct Range {
    size_t begin = 0, end = 0;
    Box3 bounds, centroids;
    size_t size() const { return end - begin; }
};

struct Split {
    int axis = -1;
    int bin = 0;  // the left side holds bins [0, bin]
    float cost = std::numeric_limits<float>::infinity();
};

class Builder {
public:
    Builder(const float* tri, size_t n, const BvhBuildOptions& opt, Bvh& out) : opt_(opt), out_(out) {
        refs_.resize(n);
        for (size_t i = 0; i < n; ++i) {
            PrimRef& r = refs_[i];
            r.box = empty_box();
            for (int k = 0; k < 3; ++k) grow(r.box, tri + 9 * i + 3 * k);
            for (int a = 0; a < 3; ++a) r.centroid[a] = 0.5f * (r.box.lo[a] + r.box.hi[a]);
            r.prim = static_cast<uint32_t>(i);
        }
        tri_ = tri;
    }

    void build() {
        if (refs_.empty()) return;
        Range all = measure(0, refs_.size());
        out_.bounds = all.bounds;
        for (int a = 0; a < 3; ++a) out_.extent[a] = std::max(std::fabs(all.bounds.lo[a]), std::fabs(all.bounds.hi[a]));
        out_.root = build_node(all, 1);
    }

private:
    Range measure(size_t begin, size_t end) const {
        Range r;
        r.begin = begin;
        r.end = end;
        r.bounds = empty_box();
        r.centroids = empty_box();
        for (size_t i = begin; i < end; ++i) {
            grow(r.bounds, refs_[i].box);
            grow(r.centroids, refs_[i].centroid);
        }
        return r;
    }

    int bin_of(const Range& r, int axis, const PrimRef& p) const {
        const float lo = r.centroids.lo[axis], ext = r.centroids.hi[axis] - lo;
        const int b = static_cast<int>((p.centroid[axis] - lo) * (kBins / ext));
        return std::clamp(b, 0, kBins - 1);
    }

    // The cheapest binned split of r by the SAH (cost relative to r's area); axis -1 when the
    // centroids coincide.
    Split find_split(const Range& r) const {
        Split best;
        for (int axis = 0; axis < 3; ++axis) {
            if (!(r.centroids.hi[axis] > r.centroids.lo[axis])) continue;
            Box3 box[kBins];
            size_t count[kBins] = {};
            for (auto& b : box) b = empty_box();
            for (size_t i = r.begin; i < r.end; ++i) {
                const int b = bin_of(r, axis, refs_[i]);
                grow(box[b], refs_[i].box);
                ++count[b];
            }
            float right_cost[kBins];  // bins (b, kBins) on the right
            Box3 acc = empty_box();
            size_t n = 0;
            for (int b = kBins - 1; b > 0; --b) {
                grow(acc, box[b]);
                n += count[b];
                right_cost[b - 1] = half_area(acc) * blocks_of(n);
            }
            acc = empty_box();
            n = 0;
            for (int b = 0; b < kBins - 1; ++b) {
                grow(acc, box[b]);
                n += count[b];
                if (n == 0 || n == r.size()) continue;
                const float cost = half_area(acc) * blocks_of(n) + right_cost[b];
                if (cost < best.cost) best = Split{axis, b, cost};
            }
        }
        if (best.axis >= 0) {
            const float area = half_area(r.bounds);
            best.cost = opt_.node_cost + opt_.block_cost * (area > 0 ? best.cost / area : 0.0f);
        }
        return best;
    }

    // Splits r into two (SAH, or halved by count when forced or when the SAH found nothing).
    void split(const Range& r, const Split& s, bool forced, Range& left, Range& right) {
        size_t mid;
        if (!forced && s.axis >= 0) {
            auto it = std::partition(refs_.begin() + r.begin, refs_.begin() + r.end,
                                     [&](const PrimRef& p) { return bin_of(r, s.axis, p) <= s.bin; });
            mid = static_cast<size_t>(it - refs_.begin());
        } else {
            int axis = 0;
            for (int a = 1; a < 3; ++a)
                if (r.centroids.hi[a] - r.centroids.lo[a] > r.centroids.hi[axis] - r.centroids.lo[axis]) axis = a;
            mid = r.begin + r.size() / 2;
            std::nth_element(refs_.begin() + r.begin, refs_.begin() + mid, refs_.begin() + r.end,
                             [&](const PrimRef& a, const PrimRef& b) {
                                 return a.centroid[axis] < b.centroid[axis] ||
                                        (a.centroid[axis] == b.centroid[axis] && a.prim < b.prim);
                             });
        }
        left = measure(r.begin, mid);
        right = measure(mid, r.end);
    }

    void set_lane(BvhBlock& blk, int lane, uint32_t prim) const {
        blk.prim[lane] = static_cast<int32_t>(prim);
        for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a) blk.v[k][a][lane] = tri_[9 * size_t(prim) + 3 * k + a];
    }

    static uint32_t leaf_ref(size_t first, size_t blocks) {
        return kBvhLeaf | static_cast<uint32_t>((blocks - 1) << kBvhBlockBits) | static_cast<uint32_t>(first);
    }

    uint32_t make_leaf(const Range& r) {
        const size_t n = r.size(), nb = (n + kBvhBlock - 1) / kBvhBlock;
        const size_t first = out_.blocks.size();
        out_.blocks.resize(first + nb);
        for (size_t b = 0; b < nb; ++b)
            for (int l = 0; l < kBvhBlock; ++l)
                set_lane(out_.blocks[first + b], l, refs_[r.begin + std::min(b * kBvhBlock + l, n - 1)].prim);
        ++out_.stats.leaves;
        return leaf_ref(first, nb);
    }

    // A node's leaf children of at most a block each go into blocks shared with other small
    // leaves: first fit (largest first) into the blocks still open (the last kOpenBlocks made,
    // near in the tree and in memory), else a new one. A leaf's reference is its block, whose
    // other lanes hold other leaves' triangles; a ray entering the leaf tests those too. They are
    // real triangles, so a hit among them is a true hit and the closest (or any) hit is unchanged,
    // while the blocks' padding (30 % of them at 5.6 triangles a leaf) shrinks.
    void make_shared_leaves(const Range* kids, const bool* final, int count, uint32_t* child) {
        int order[kBvhWidth], n = 0;
        for (int i = 0; i < count; ++i)
            if (final[i] && kids[i].size() <= static_cast<size_t>(kBvhBlock)) order[n++] = i;
        std::stable_sort(order, order + n, [&](int a, int b) { return kids[a].size() > kids[b].size(); });
        for (int j = 0; j < n; ++j) {
            const Range& r = kids[order[j]];
            OpenBlock* into = nullptr;
            for (OpenBlock& o : open_)
                if (o.fill + static_cast<int>(r.size()) <= kBvhBlock) {
                    into = &o;
                    break;
                }
            if (!into) {
                if (open_.size() == kOpenBlocks) open_.erase(open_.begin());
                open_.push_back(OpenBlock{out_.blocks.size(), 0});
                out_.blocks.emplace_back();
                into = &open_.back();
            }
            BvhBlock& blk = out_.blocks[into->block];
            for (size_t i = r.begin; i < r.end; ++i) set_lane(blk, into->fill++, refs_[i].prim);
            for (int l = into->fill; l < kBvhBlock; ++l) set_lane(blk, l, refs_[r.end - 1].prim);  // padding
            child[order[j]] = leaf_ref(into->block, 1);
            ++out_.stats.leaves;
        }
    }

    bool leaf_allowed(const Range& r) const {
        return r.size() <= static_cast<size_t>(std::min(opt_.max_leaf, kBvhBlock * kBvhMaxLeafBlocks));
    }

    uint32_t build_node(const Range& r, int depth) {
        out_.stats.depth = std::max(out_.stats.depth, depth);
        const bool forced = depth >= kForcedDepth;
        Range kids[kBvhWidth];
        bool final[kBvhWidth] = {};
        int count = 1;
        kids[0] = r;
        while (count < kBvhWidth) {
            // the open child with the largest area (the most triangles when forced)
            int pick = -1;
            for (int i = 0; i < count; ++i) {
                if (final[i]) continue;
                if (pick < 0 || (forced ? kids[i].size() > kids[pick].size()
                                        : half_area(kids[i].bounds) > half_area(kids[pick].bounds)))
                    pick = i;
            }
            if (pick < 0) break;
            const Range& k = kids[pick];
            if (k.size() <= 1) {
                final[pick] = true;
                continue;
            }
            Split s;
            if (!forced) s = find_split(k);
            if (leaf_allowed(k)) {
                const float leaf_cost = opt_.block_cost * blocks_of(k.size());
                if (forced || s.axis < 0 || leaf_cost <= s.cost) {
                    final[pick] = true;
                    continue;
                }
            }
            Range a, b;
            split(k, s, forced, a, b);
            kids[pick] = a;
            kids[count++] = b;
        }
        if (count == 1) return make_leaf(r);
        const size_t index = out_.nodes.size();
        out_.nodes.emplace_back();
        ++out_.stats.nodes;
        BvhNode node;
        for (int i = 0; i < kBvhWidth; ++i) {
            const Box3 box = i < count ? kids[i].bounds : empty_box();
            for (int a = 0; a < 3; ++a) {
                node.box[2 * a][i] = box.lo[a];
                node.box[2 * a + 1][i] = box.hi[a];
            }
            node.child[i] = kBvhEmpty;
        }
        make_shared_leaves(kids, final, count, node.child);
        for (int i = 0; i < count; ++i)
            if (node.child[i] == kBvhEmpty)
                node.child[i] = final[i] ? make_leaf(kids[i]) : build_node(kids[i], depth + 1);
        out_.nodes[index] = node;
        return static_cast<uint32_t>(index);
    }

    const BvhBuildOptions& opt_;
    Bvh& out_;
    const float* tri_ = nullptr;
    std::vector<PrimRef> refs_;
    struct OpenBlock {
        size_t block;
        int fill;  // lanes in use; the others repeat the last triangle
    };
    static constexpr size_t kOpenBlocks = 4;
    std::vector<OpenBlock> open_;
};

}  // namespace

Bvh build_bvh(const float* triangles, size_t triangle_count, const BvhBuildOptions& options) {
    if (triangle_count >= (size_t(1) << kBvhBlockBits))
        throw std::invalid_argument("a BVH holds fewer than 2^27 triangles");
    const auto start = std::chrono::steady_clock::now();
    Bvh bvh;
    Builder(triangles, triangle_count, options, bvh).build();
    bvh.stats.blocks = bvh.blocks.size();
    bvh.stats.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return bvh;
}

}  // namespace patina
