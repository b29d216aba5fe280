// SAH kd-tree construction in O(N log N), binned with an exact refinement.
//
// Every node bins its triangles' bounds (per axis, where each reference starts and
// ends; Shevtsov, Soupikov and Kapustin 2007) and evaluates the SAH at the bins'
// boundaries. Then, per axis, the bounds that fall in the two bins beside that axis's
// best boundary become bound events (start, end, or planar for a flat bound), sorted,
// and the exact SAH is evaluated at each of them as in the event sweep of Wald and
// Havran (2006), starting from the counts the bins give for the window's first bin. The
// plane chosen is therefore always a triangle bound, exactly evaluated. Triangles that
// straddle it are clipped to each child's box ("perfect splits").
//
// This replaced a build that switched to Wald and Havran's presorted event lists below
// 256 references: keeping those lists sorted (distributing every event to the children,
// merging the clipped triangles' new ones) cost more than binning anew, and the window
// of exact events finds trees with a lower SAH cost (docs/trace.md has the figures).
// Per node the work is O(n + bins + w log w), w the events in the windows.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <future>
#include <limits>
#include <thread>

#include "render/accel/kdtree.h"

namespace patina {

float Box3::area() const {
    const float dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    return 2.0f * (dx * dy + dy * dz + dz * dx);
}

namespace {

enum EventType : uint32_t { kEnd = 0, kPlanar = 1, kStart = 2 };

// An event packed into 64 bits so that sorting compares plain integers: the position's
// bits mapped to an unsigned key that sorts as the floats do (high 32 bits), then the
// type (end < planar < start at one position, as the sweep needs), then the triangle
// (30 bits; build_kdtree's callers refuse 2^30 triangles or more).
using Event = uint64_t;
uint32_t float_key(float x) {
    x += 0.0f;  // -0 -> +0: one position, one key
    uint32_t u;
    std::memcpy(&u, &x, 4);
    return (u & 0x80000000u) ? ~u : (u | 0x80000000u);
}
float key_float(uint32_t k) {
    const uint32_t u = (k & 0x80000000u) ? (k & 0x7fffffffu) : ~k;
    float x;
    std::memcpy(&x, &u, 4);
    return x;
}
Event make_event(float pos, uint32_t tri, EventType type) {
    return (uint64_t(float_key(pos)) << 32) | (uint64_t(type) << 30) | tri;
}
uint32_t event_key(Event e) { return static_cast<uint32_t>(e >> 32); }
EventType event_type(Event e) { return static_cast<EventType>((static_cast<uint32_t>(e) >> 30) & 3u); }

// A std::allocator that leaves resized elements uninitialised: event lists are resized
// to their worst case and then overwritten, and zeroing them first cost a tenth of the build.
template <class T>
struct UninitialisedAllocator : std::allocator<T> {
    template <class U>
    struct rebind {
        using other = UninitialisedAllocator<U>;
    };
    UninitialisedAllocator() = default;
    template <class U>
    UninitialisedAllocator(const UninitialisedAllocator<U>&) {}
    template <class U>
    void construct(U* p) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};
using EventList = std::vector<Event, UninitialisedAllocator<Event>>;

// A triangle's bounds within a node. No member initialisers: lists of them are sized
// for the worst case and then written.
struct Ref {
    float lo[3], hi[3];
    uint32_t tri;
};
using RefList = std::vector<Ref, UninitialisedAllocator<Ref>>;

// Bins per axis: one per two references, at least 4, at most kMaxBins. Fewer bins make
// the refinement's windows larger: one per four gave the 1M sphere a 2 % lower SAH cost
// but took 4 % more instructions and 18 % more mispredicted branches (cachegrind), one
// per reference more instructions again.
constexpr int kMaxBins = 128;
int bin_count(size_t n) { return static_cast<int>(std::clamp<size_t>(n / 2, 4, kMaxBins)); }

struct Split {
    int axis = -1;
    float pos = 0;
    bool planar_left = true;
    float cost = std::numeric_limits<float>::infinity();
};

// The next float towards -inf / +inf (finite inputs), without a libm call.
float next_down(float x) {
    if (x == 0.0f) return -std::numeric_limits<float>::denorm_min();
    uint32_t u;
    std::memcpy(&u, &x, 4);
    u = x > 0.0f ? u - 1 : u + 1;
    std::memcpy(&x, &u, 4);
    return x;
}
float next_up(float x) { return -next_down(-x); }

// Sutherland-Hodgman in double: the part of polygon src (n corners) on one side of the
// plane x[a] = plane (at or below it if `upper`, at or above it otherwise) into dst;
// returns its number of corners.
int clip_polygon(const double (*src)[3], int n, double (*dst)[3], int a, double plane, bool upper) {
    auto inside = [&](const double* p) { return upper ? p[a] <= plane : p[a] >= plane; };
    int m = 0;
    for (int i = 0; i < n; ++i) {
        const double* p = src[i];
        const double* q = src[i + 1 == n ? 0 : i + 1];
        const bool pin = inside(p), qin = inside(q);
        if (pin) {
            for (int c = 0; c < 3; ++c) dst[m][c] = p[c];
            ++m;
        }
        if (pin != qin) {
            const double s = (plane - p[a]) / (q[a] - p[a]);
            for (int c = 0; c < 3; ++c) dst[m][c] = p[c] + s * (q[c] - p[c]);
            dst[m][a] = plane;
            ++m;
        }
    }
    return m;
}

// The float bounds of a polygon, rounded outwards and kept inside `box`; false if empty.
bool polygon_bounds(const double (*poly)[3], int n, const Box3& box, float* out_lo, float* out_hi) {
    if (n == 0) return false;
    for (int a = 0; a < 3; ++a) {
        double lo = poly[0][a], hi = lo;
        for (int i = 1; i < n; ++i) {
            lo = std::min(lo, poly[i][a]);
            hi = std::max(hi, poly[i][a]);
        }
        out_lo[a] = std::max(box.lo[a], next_down(static_cast<float>(lo)));
        out_hi[a] = std::min(box.hi[a], next_up(static_cast<float>(hi)));
        if (out_lo[a] > out_hi[a]) return false;
    }
    return true;
}

// Bounds of the parts of triangle t inside the two children of `box` split at
// x[axis] = pos: the triangle is clipped once to the node's box (only against the planes
// some vertex lies beyond; a plane with every vertex inside leaves the polygon as it is),
// and that polygon once to each side of the split plane. Returns bit 0 if something lies
// in the left child, bit 1 in the right one.
int split_clipped_bounds(const float* t, const Box3& box, int axis, float pos, float* left_lo, float* left_hi,
                         float* right_lo, float* right_hi) {
    double poly[2][16][3];
    int n = 3;
    for (int v = 0; v < 3; ++v)
        for (int a = 0; a < 3; ++a) poly[0][v][a] = t[3 * v + a];
    int cur = 0;
    for (int a = 0; a < 3 && n > 0; ++a) {
        const float tlo = std::min({t[a], t[3 + a], t[6 + a]}), thi = std::max({t[a], t[3 + a], t[6 + a]});
        if (tlo < box.lo[a]) {
            n = clip_polygon(poly[cur], n, poly[1 - cur], a, box.lo[a], false);
            cur = 1 - cur;
        }
        if (thi > box.hi[a] && n > 0) {
            n = clip_polygon(poly[cur], n, poly[1 - cur], a, box.hi[a], true);
            cur = 1 - cur;
        }
    }
    Box3 left_box = box, right_box = box;
    left_box.hi[axis] = pos;
    right_box.lo[axis] = pos;
    double side[16][3];
    const int nl = clip_polygon(poly[cur], n, side, axis, pos, true);
    const bool left = polygon_bounds(side, nl, left_box, left_lo, left_hi);
    const int nr = clip_polygon(poly[cur], n, side, axis, pos, false);
    const bool right = polygon_bounds(side, nr, right_box, right_lo, right_hi);
    return int(left) | (int(right) << 1);
}

class Builder {
public:
    Builder(const std::vector<float>& triangles, const KdBuildOptions& opt, int max_depth)
        : m_tris(triangles), m_opt(opt), m_max_depth(max_depth) {}

    std::vector<KdNode> nodes;
    std::vector<uint32_t> leaf_prims;
    KdTreeStats stats;

    // Builds the subtree of a node into `nodes` and returns its index; consumes `refs`
    // (the list goes back to the pool). `parallel_depth` > 0 builds the two children in
    // parallel (the right one in its own Builder), then splices, so the tree is the same
    // for any number of threads.
    uint32_t build(const Box3& box, RefList& refs, int depth, int parallel_depth) {
        const size_t n = refs.size();
        stats.depth = std::max(stats.depth, depth);
        const uint32_t index = static_cast<uint32_t>(nodes.size());
        nodes.push_back(KdNode{});
        const Split split =
            (n <= static_cast<size_t>(m_opt.max_leaf) || depth >= m_max_depth) ? Split{} : find_split(refs, box, n);
        if (split.axis < 0 || !(split.cost < m_opt.intersection_cost * static_cast<float>(n))) {
            KdNode& node = nodes[index];
            node.first = static_cast<uint32_t>(leaf_prims.size());
            node.bits = (static_cast<uint32_t>(n) << 2) | 3u;
            for (const Ref& r : refs) leaf_prims.push_back(r.tri);
            ++stats.leaves;
            if (n == 0) ++stats.empty_leaves;
            stats.leaf_refs += n;
            give_refs(refs);
            return index;
        }
        Box3 left_box = box, right_box = box;
        left_box.hi[split.axis] = split.pos;
        right_box.lo[split.axis] = split.pos;
        RefList left = take_refs(), right = take_refs();
        left.resize(n);  // the worst case: every reference straddles the plane
        right.resize(n);
        const int a = split.axis;
        const float p = split.pos;
        size_t nl = 0, nr = 0;
        for (const Ref& r : refs) {
            // write to both, advance the side (or sides) that keeps it
            const bool planar = r.lo[a] == p && r.hi[a] == p;
            const bool to_left = planar ? split.planar_left : r.hi[a] <= p;
            const bool to_right = planar ? !split.planar_left : r.lo[a] >= p;
            left[nl] = r;
            right[nr] = r;
            nl += to_left;
            nr += to_right;
            if (!to_left && !to_right) {
                const int sides = split_clipped_bounds(&m_tris[9 * size_t(r.tri)], box, a, p, left[nl].lo,
                                                       left[nl].hi, right[nr].lo, right[nr].hi);
                nl += sides & 1;
                nr += sides >> 1;
            }
        }
        left.resize(nl);
        right.resize(nr);
        give_refs(refs);
        nodes[index].split = p;
        ++stats.nodes;
        uint32_t above;
        if (parallel_depth > 0 && nl + nr > 20000) {
            Builder other(m_tris, m_opt, m_max_depth);
            auto future = std::async(std::launch::async, [&] {
                other.build(right_box, right, depth + 1, parallel_depth - 1);
            });
            build(left_box, left, depth + 1, parallel_depth - 1);
            future.get();
            above = splice(other);
        } else {
            build(left_box, left, depth + 1, parallel_depth - 1);
            above = build(right_box, right, depth + 1, parallel_depth - 1);
        }
        nodes[index].bits = (above << 2) | static_cast<uint32_t>(a);
        return index;
    }

    // Appends another builder's subtree; returns the index of its root here.
    uint32_t splice(const Builder& other) {
        const uint32_t node_offset = static_cast<uint32_t>(nodes.size());
        const uint32_t prim_offset = static_cast<uint32_t>(leaf_prims.size());
        for (KdNode n : other.nodes) {
            if (n.is_leaf()) n.first += prim_offset;
            else n.bits = ((n.above() + node_offset) << 2) | (n.bits & 3u);
            nodes.push_back(n);
        }
        leaf_prims.insert(leaf_prims.end(), other.leaf_prims.begin(), other.leaf_prims.end());
        stats.nodes += other.stats.nodes;
        stats.leaves += other.stats.leaves;
        stats.empty_leaves += other.stats.empty_leaves;
        stats.leaf_refs += other.stats.leaf_refs;
        stats.depth = std::max(stats.depth, other.stats.depth);
        return node_offset;
    }
private:
    const std::vector<float>& m_tris;
    const KdBuildOptions& m_opt;
    int m_max_depth;
    EventList m_window[3];  // find_split's events beside each axis's best binned plane
    std::vector<uint8_t, UninitialisedAllocator<uint8_t>> m_bins;  // find_split's bins of each reference

    // Reference lists no longer needed, kept with their capacity: the build makes millions
    // of small nodes, and a level's lists near the root are megabytes of fresh pages.
    std::vector<RefList> m_ref_pool;

    RefList take_refs() {
        if (m_ref_pool.empty()) return {};
        RefList v = std::move(m_ref_pool.back());
        m_ref_pool.pop_back();
        v.clear();
        return v;
    }
    void give_refs(RefList& v) {
        // the lists in use at once are two a level of the recursion
        if (v.capacity() && m_ref_pool.size() < 128) m_ref_pool.push_back(std::move(v));
        v = RefList{};
    }

    // The SAH at bins - 1 evenly spaced planes per axis, from per-bin counts of where the
    // references start and end (a reference is on a plane's left if it starts in a bin
    // below it, on its right if it ends in a bin at or above it; one pass over the
    // references fills the bins of all three axes). Then, per axis, the exact SAH at every
    // bound in the two bins beside that axis's best plane: the split chosen is the best of
    // those, an exactly evaluated triangle bound. Refining every axis, not only the one
    // whose binned cost is least, matters: the bins miss the empty-space bonus of a plane
    // at a face, and refining only the best axis gave a box field a 25-100 % worse tree.
    Split find_split(const RefList& refs, const Box3& box, size_t n) {
        Split best;
        const float area = box.area();
        if (!(area > 0.0f)) return best;
        const int bins = bin_count(n);
        const float scale = m_opt.intersection_cost * 2.0f / area;  // K_I * (child area / 2) / (area / 2)
        const float bonus = 1.0f - m_opt.empty_bonus;
        float lo[3], extent[3], to_bin[3];
        for (int a = 0; a < 3; ++a) {
            lo[a] = box.lo[a];
            extent[a] = box.hi[a] - box.lo[a];
            to_bin[a] = extent[a] > 0.0f ? static_cast<float>(bins) / extent[a] : 0.0f;
        }
        // clamped as floats: NaN (0 * inf where an extent is tiny) goes to bin 0, and the bin
        // stays monotonic in x, which the refinement's counts rely on
        const float last_bin = static_cast<float>(bins - 1);
        auto bin_of = [&](float x, int a) {
            return static_cast<int>(std::min(std::max(0.0f, (x - lo[a]) * to_bin[a]), last_bin));
        };
        uint32_t starts[3][kMaxBins], ends[3][kMaxBins];
        for (int a = 0; a < 3; ++a) {
            std::fill(starts[a], starts[a] + bins, 0u);
            std::fill(ends[a], ends[a] + bins, 0u);
        }
        // each reference's bins (start x y z, end x y z), kept for the second pass
        m_bins.resize(8 * n);
        uint8_t* rb = m_bins.data();
        for (const Ref& r : refs) {
            for (int a = 0; a < 3; ++a) {
                const int s = bin_of(r.lo[a], a), e = bin_of(r.hi[a], a);
                rb[a] = static_cast<uint8_t>(s);
                rb[4 + a] = static_cast<uint8_t>(e);
                ++starts[a][s];
                ++ends[a][e];
            }
            rb += 8;
        }
        // per axis: the first of the two bins beside its best plane (-1: none), and the
        // counts left and right of that bin's lower boundary
        int window[3] = {-1, -1, -1};
        int64_t window_nl[3] = {0, 0, 0}, window_nr[3] = {0, 0, 0};
        for (int a = 0; a < 3; ++a) {
            if (!(extent[a] > 0.0f)) continue;
            const float hi = box.hi[a];
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            const float eb = box.hi[b] - box.lo[b], ec = box.hi[c] - box.lo[c];
            const float cap = eb * ec, girth = eb + ec;  // a child's area is 2 (cap + length * girth)
            size_t nl = 0, nr = n;
            float axis_best = std::numeric_limits<float>::infinity();
            for (int k = 1; k < bins; ++k) {
                const size_t nl_below = nl, nr_below = nr;
                nl += starts[a][k - 1];
                nr -= ends[a][k - 1];
                const float p = lo[a] + extent[a] * static_cast<float>(k) / static_cast<float>(bins);
                const float al = cap + (p - lo[a]) * girth, ar = cap + (hi - p) * girth;
                float cost = m_opt.traversal_cost + scale * (al * static_cast<float>(nl) + ar * static_cast<float>(nr));
                if (nl == 0 || nr == 0) cost *= bonus;
                if (cost < axis_best && p > lo[a] && p < hi) {
                    axis_best = cost;
                    window[a] = k - 1;
                    window_nl[a] = static_cast<int64_t>(nl_below);
                    window_nr[a] = static_cast<int64_t>(nr_below);
                }
            }
        }
        for (int a = 0; a < 3; ++a) {
            if (window[a] < 0) continue;
            collect_window(refs, a, static_cast<uint32_t>(window[a]), starts[a], ends[a], m_window[a]);
            std::sort(m_window[a].begin(), m_window[a].end());
            sweep(m_window[a].data(), m_window[a].size(), a, box, window_nl[a], window_nr[a], best);
        }
        return best;
    }

    // The events of axis a's bounds that lie in bins w and w + 1 (find_split's m_bins).
    void collect_window(const RefList& refs, int a, uint32_t w, const uint32_t* starts, const uint32_t* ends,
                        EventList& out) const {
        const uint8_t* rb = m_bins.data();
        const size_t n = refs.size();
        const uint32_t inside = starts[w] + starts[w + 1] + ends[w] + ends[w + 1];
        if (8 * size_t(inside) > n) {
            // the two bins hold a good part of the bounds (small nodes, few bins), so a test
            // per reference is a coin toss: write every event, keep those inside, no branch
            out.resize(2 * n);
            Event* o = out.data();
            for (const Ref& r : refs) {
                const bool start_in = static_cast<uint32_t>(rb[a]) - w < 2u;
                const bool end_in = static_cast<uint32_t>(rb[4 + a]) - w < 2u;
                rb += 8;
                const bool planar = r.lo[a] == r.hi[a];
                *o = make_event(r.lo[a], r.tri, planar ? kPlanar : kStart);
                o += start_in;
                *o = make_event(r.hi[a], r.tri, kEnd);
                o += end_in & !planar;
            }
            out.resize(static_cast<size_t>(o - out.data()));
            return;
        }
        out.clear();
        for (const Ref& r : refs) {
            const bool start_in = static_cast<uint32_t>(rb[a]) - w < 2u;
            const bool end_in = static_cast<uint32_t>(rb[4 + a]) - w < 2u;
            rb += 8;
            if (!(start_in | end_in)) continue;  // rarely taken in large nodes
            if (r.lo[a] == r.hi[a]) {
                out.push_back(make_event(r.lo[a], r.tri, kPlanar));
                continue;
            }
            if (start_in) out.push_back(make_event(r.lo[a], r.tri, kStart));
            if (end_in) out.push_back(make_event(r.hi[a], r.tri, kEnd));
        }
    }

    // The exact SAH at every position of a sorted run of axis a's events, `nl` and `nr` the
    // counts left and right of the run's first position (those of all references whose
    // bounds lie below the run); improves `best`.
    void sweep(const Event* e, size_t count, int a, const Box3& box, int64_t nl, int64_t nr, Split& best) const {
        const float scale = m_opt.intersection_cost * 2.0f / box.area();
        const float bonus = 1.0f - m_opt.empty_bonus;
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        const float eb = box.hi[b] - box.lo[b], ec = box.hi[c] - box.lo[c];
        const float cap = eb * ec, girth = eb + ec;
        const float lo = box.lo[a], hi = box.hi[a];
        // signed counts: converting them to float is one instruction
        auto cost = [&](float p, int64_t nl, int64_t nr) {
            const float al = cap + (p - lo) * girth, ar = cap + (hi - p) * girth;
            const float c = m_opt.traversal_cost + scale * (al * static_cast<float>(nl) + ar * static_cast<float>(nr));
            return c * ((nl == 0) | (nr == 0) ? bonus : 1.0f);
        };
        for (size_t i = 0; i < count;) {
            // all events at this position: ends, then planars, then starts (the sort order)
            const uint32_t key = event_key(e[i]);
            int64_t counts[3] = {0, 0, 0};
            do {
                ++counts[event_type(e[i])];
                ++i;
            } while (i < count && event_key(e[i]) == key);
            const int64_t ends = counts[kEnd], planars = counts[kPlanar], starts = counts[kStart];
            const float p = key_float(key);
            nr -= planars + ends;
            if (p > lo && p < hi) {
                const float with_left = cost(p, nl + planars, nr);
                if (with_left < best.cost) best = Split{a, p, true, with_left};
                if (planars) {
                    const float with_right = cost(p, nl, nr + planars);
                    if (with_right < best.cost) best = Split{a, p, false, with_right};
                }
            }
            nl += starts + planars;
        }
    }
};

}  // namespace

KdTree build_kdtree(const float* vertices, size_t vertex_count, const int32_t* indices, size_t triangle_count,
                    const KdBuildOptions& options) {
    (void)vertex_count;
    const auto start = std::chrono::steady_clock::now();
    KdTree tree;
    tree.triangles.resize(9 * triangle_count);
    for (size_t t = 0; t < triangle_count; ++t)
        for (int v = 0; v < 3; ++v)
            for (int a = 0; a < 3; ++a)
                tree.triangles[9 * t + 3 * v + a] = vertices[3 * size_t(indices[3 * t + v]) + a];

    tree.normals.resize(3 * triangle_count);
    for (size_t t = 0; t < triangle_count; ++t) {
        const float* p = &tree.triangles[9 * t];
        const double e1[3] = {double(p[3]) - p[0], double(p[4]) - p[1], double(p[5]) - p[2]};
        const double e2[3] = {double(p[6]) - p[0], double(p[7]) - p[1], double(p[8]) - p[2]};
        const double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        const double len = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        for (int a = 0; a < 3; ++a) tree.normals[3 * t + a] = len > 0 ? static_cast<float>(c[a] / len) : 0.0f;
    }

    Box3& bounds = tree.bounds;
    for (int a = 0; a < 3; ++a) {
        bounds.lo[a] = std::numeric_limits<float>::infinity();
        bounds.hi[a] = -std::numeric_limits<float>::infinity();
    }
    // Zero-area triangles (zero normal) can never be hit: they stay out of the tree, where
    // the rounding of the shear in the watertight test could otherwise report hits on them.
    RefList refs;
    refs.reserve(triangle_count);
    for (size_t t = 0; t < triangle_count; ++t) {
        const float* n = &tree.normals[3 * t];
        if (n[0] == 0.0f && n[1] == 0.0f && n[2] == 0.0f) continue;
        refs.push_back(Ref{});
        Ref& b = refs.back();
        b.tri = static_cast<uint32_t>(t);
        const float* v = &tree.triangles[9 * t];
        for (int a = 0; a < 3; ++a) {
            b.lo[a] = std::min({v[a], v[3 + a], v[6 + a]});
            b.hi[a] = std::max({v[a], v[3 + a], v[6 + a]});
            bounds.lo[a] = std::min(bounds.lo[a], b.lo[a]);
            bounds.hi[a] = std::max(bounds.hi[a], b.hi[a]);
        }
    }
    if (refs.empty()) bounds = Box3{};

    KdBuildOptions opt = options;
    opt.max_leaf = std::max(opt.max_leaf, 1);
    int max_depth = opt.max_depth;
    if (max_depth <= 0)
        max_depth = std::min(64, static_cast<int>(std::lround(4.5 + std::log2(std::max<size_t>(triangle_count, 1)))));
    const int threads = opt.threads > 0 ? opt.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    int parallel_depth = 0;
    while ((1 << parallel_depth) < threads) ++parallel_depth;

    Builder builder(tree.triangles, opt, max_depth);
    builder.build(bounds, refs, 0, parallel_depth);
    tree.nodes = std::move(builder.nodes);
    tree.leaf_prims = std::move(builder.leaf_prims);
    tree.stats = builder.stats;
    tree.stats.nodes = tree.nodes.size();
    tree.stats.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return tree;
}

}  // namespace patina
