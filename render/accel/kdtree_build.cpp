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

#if defined(__SSE2__) && defined(__x86_64__)
#include <emmintrin.h>
#endif

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
// References in a node whose lists are beyond the first caches (28 bytes each).
constexpr size_t kLargeNode = 4096;
int bin_count(size_t n) { return static_cast<int>(std::clamp<size_t>(n / 2, 4, kMaxBins)); }

// Four floats or ints in one register (SSE on x86), through the compiler's vector
// extensions: the bin pass does an axis a lane, so does the binned SAH.
typedef float V4 __attribute__((vector_size(16)));
typedef int32_t V4I __attribute__((vector_size(16)));
V4 load4(const float* p) {
    V4 v;
    std::memcpy(&v, p, sizeof(v));
    return v;
}
V4I load4i(const uint32_t* p) {
    V4I v;
    std::memcpy(&v, p, sizeof(v));
    return v;
}
// The bins of a reference's bounds, lanes 0-2 of lo and hi (lane 3 lands in bin 0 and is not
// used): (x - lo) * to_bin clamped to [0, last] as floats, then truncated, packed into one
// word as bytes (start x y z, 0, end x y z, 0). Clamped as floats, NaN (0 * inf where an
// extent is tiny) goes to bin 0 and the bin stays monotonic in x, which the refinement's
// counts rely on. The clamps are max(b, 0) and min(b, last) with SSE's semantics (the second
// operand where either is NaN), written out with the vector extensions elsewhere.
uint64_t bins_of(V4 ref_lo, V4 ref_hi, V4 lo, V4 to_bin, V4 zero, V4 last) {
    V4 s = (ref_lo - lo) * to_bin, e = (ref_hi - lo) * to_bin;
#if defined(__SSE2__) && defined(__x86_64__)
    s = _mm_min_ps(_mm_max_ps(s, zero), last);
    e = _mm_min_ps(_mm_max_ps(e, zero), last);
    const __m128i words = _mm_packs_epi32(_mm_cvttps_epi32(s), _mm_cvttps_epi32(e));
    return static_cast<uint64_t>(_mm_cvtsi128_si64(_mm_packus_epi16(words, words)));
#else
    s = zero < s ? s : zero;
    s = s < last ? s : last;
    e = zero < e ? e : zero;
    e = e < last ? e : last;
    const V4I si = __builtin_convertvector(s, V4I), ei = __builtin_convertvector(e, V4I);
    return uint64_t(si[0]) | uint64_t(si[1]) << 8 | uint64_t(si[2]) << 16 | uint64_t(ei[0]) << 32 |
           uint64_t(ei[1]) << 40 | uint64_t(ei[2]) << 48;
#endif
}

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

// A polygon's float bounds, rounded outwards and kept inside a box, gathered corner by corner.
struct ClippedBounds {
    double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                    std::numeric_limits<double>::infinity()};
    double hi[3] = {-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                    -std::numeric_limits<double>::infinity()};
    bool any = false;
    void add(const double* p) {
        for (int c = 0; c < 3; ++c) {
            lo[c] = std::min(lo[c], p[c]);
            hi[c] = std::max(hi[c], p[c]);
        }
        any = true;
    }
    // false if empty
    bool to_float(const Box3& box, float* out_lo, float* out_hi) const {
        if (!any) return false;
        for (int a = 0; a < 3; ++a) {
            out_lo[a] = std::max(box.lo[a], next_down(static_cast<float>(lo[a])));
            out_hi[a] = std::min(box.hi[a], next_up(static_cast<float>(hi[a])));
            if (out_lo[a] > out_hi[a]) return false;
        }
        return true;
    }
};

// The bounds of the parts of polygon src (n corners) at or below and at or above the plane
// x[a] = plane: the corners clip_polygon would give for each side, without building the two
// polygons, and a crossing point computed once where both sides need it (the same arithmetic
// as clip_polygon, so the same bounds).
void split_polygon(const double (*src)[3], int n, int a, double plane, ClippedBounds& below, ClippedBounds& above) {
    for (int i = 0; i < n; ++i) {
        const double* p = src[i];
        const double* q = src[i + 1 == n ? 0 : i + 1];
        const bool p_below = p[a] <= plane, p_above = p[a] >= plane;
        const bool q_below = q[a] <= plane, q_above = q[a] >= plane;
        if (p_below) below.add(p);
        if (p_above) above.add(p);
        const bool cross_below = p_below != q_below, cross_above = p_above != q_above;
        if (cross_below | cross_above) {
            const double s = (plane - p[a]) / (q[a] - p[a]);
            double x[3];
            for (int c = 0; c < 3; ++c) x[c] = p[c] + s * (q[c] - p[c]);
            x[a] = plane;
            if (cross_below) below.add(x);
            if (cross_above) above.add(x);
        }
    }
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
    ClippedBounds below, above;
    split_polygon(poly[cur], n, axis, pos, below, above);
    const bool left = below.to_float(left_box, left_lo, left_hi);
    const bool right = above.to_float(right_box, right_lo, right_hi);
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
        // the worst case: every reference straddles the plane
        RefList left = take_refs(n), right = take_refs(n);
        const int a = split.axis;
        const float p = split.pos;
        size_t nl = 0, nr = 0;
        // Large nodes: each reference written to the side that keeps it (their lists are
        // beyond the caches, where writing both sides doubles the memory traffic; their
        // references come in runs on one side, so the branch is mostly predicted). Small
        // nodes: written to both, the side (or sides) that keeps it advanced, no branch.
        auto clip = [&](const Ref& r) {
            const int sides = split_clipped_bounds(&m_tris[9 * size_t(r.tri)], box, a, p, left[nl].lo, left[nl].hi,
                                                   right[nr].lo, right[nr].hi);
            left[nl].tri = right[nr].tri = r.tri;
            nl += sides & 1;
            nr += sides >> 1;
        };
        if (n > kLargeNode) {
            for (size_t i = 0; i < n; ++i) {
                const Ref& r = refs[i];
                __builtin_prefetch(&r + 16);
                const bool planar = r.lo[a] == p && r.hi[a] == p;
                const bool to_left = planar ? split.planar_left : r.hi[a] <= p;
                const bool to_right = planar ? !split.planar_left : r.lo[a] >= p;
                if (to_left) left[nl++] = r;
                else if (to_right) right[nr++] = r;
                else clip(r);
            }
        } else {
            for (const Ref& r : refs) {
                const bool planar = r.lo[a] == p && r.hi[a] == p;
                const bool to_left = planar ? split.planar_left : r.hi[a] <= p;
                const bool to_right = planar ? !split.planar_left : r.lo[a] >= p;
                left[nl] = r;
                right[nr] = r;
                nl += to_left;
                nr += to_right;
                if (!to_left && !to_right) clip(r);
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
    std::vector<uint64_t, UninitialisedAllocator<uint64_t>> m_bins;  // find_split's bins of each reference

    // Reference lists no longer needed, kept with their capacity: the build makes millions
    // of small nodes, and a level's lists near the root are megabytes of fresh pages (each
    // page's first touch is a page fault, a tenth of the build when lists were not reused).
    // Sorted by capacity into power-of-two classes, so a node takes a list that holds its
    // worst case without growing, and a small node does not take a large list that a large
    // node will need.
    static constexpr int kPoolClasses = 40;
    static constexpr size_t kPoolPerClass = 16;
    std::vector<RefList> m_ref_pool[kPoolClasses];

    static int capacity_class(size_t n) {  // the least c with n <= 2^c
        int c = 0;
        while ((size_t(1) << c) < n) ++c;
        return c;
    }
    // A list that holds `n` references without growing, its contents undefined.
    RefList take_refs(size_t n) {
        const int need = capacity_class(n);
        for (int c = need; c < kPoolClasses; ++c) {
            if (m_ref_pool[c].empty()) continue;
            RefList v = std::move(m_ref_pool[c].back());
            m_ref_pool[c].pop_back();
            v.resize(n);
            return v;
        }
        RefList v;
        v.reserve(size_t(1) << need);
        v.resize(n);
        return v;
    }
    void give_refs(RefList& v) {
        // the class of the largest power of two it holds
        int c = capacity_class(v.capacity());
        if ((size_t(1) << c) > v.capacity()) --c;
        if (c >= 0 && c < kPoolClasses && m_ref_pool[c].size() < kPoolPerClass) m_ref_pool[c].push_back(std::move(v));
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
        const float last_bin = static_cast<float>(bins - 1);
        // Per bin, how many references start (lanes 0-2: x, y, z) and end (lanes 4-6) in it.
        // Two copies, for even and odd references, summed afterwards: neighbouring references
        // usually fall in the same bins, and one copy would chain every increment on the one
        // before through memory.
        // (the copies are not 4 KB apart: the same bin in both would alias in the store buffer)
        alignas(16) uint32_t counts[2][kMaxBins + 2][8];
        std::memset(counts[0], 0, sizeof(counts[0][0]) * static_cast<size_t>(bins));
        std::memset(counts[1], 0, sizeof(counts[0][0]) * static_cast<size_t>(bins));
        // each reference's bins (start x y z, 0, end x y z, 0), kept for the windows
        m_bins.resize(n);
        uint64_t* rb = m_bins.data();
        const V4 v_lo = {lo[0], lo[1], lo[2], 0.0f}, v_to_bin = {to_bin[0], to_bin[1], to_bin[2], 0.0f};
        const V4 v_zero = {0.0f, 0.0f, 0.0f, 0.0f};
        const V4 v_last = {last_bin, last_bin, last_bin, last_bin};
        for (size_t i = 0; i < n; ++i) {
            const Ref& r = refs[i];
            // a right child's list comes back from memory, its left sibling's subtree done
            __builtin_prefetch(&r + 16);
            // lane 3 of lo is hi[0], of hi the triangle's bits: both times 0, so bin 0 (unused)
            const uint64_t b = bins_of(load4(r.lo), load4(r.hi), v_lo, v_to_bin, v_zero, v_last);
            rb[i] = b;
            uint32_t (*c)[8] = counts[i & 1];
            ++c[b & 0xff][0];
            ++c[(b >> 8) & 0xff][1];
            ++c[(b >> 16) & 0xff][2];
            ++c[(b >> 32) & 0xff][4];
            ++c[(b >> 40) & 0xff][5];
            ++c[(b >> 48) & 0xff][6];
        }
        alignas(16) uint32_t starts[kMaxBins][4], ends[kMaxBins][4];
        for (int k = 0; k < bins; ++k)
            for (int a = 0; a < 4; ++a) {
                starts[k][a] = counts[0][k][a] + counts[1][k][a];
                ends[k][a] = counts[0][k][4 + a] + counts[1][k][4 + a];
            }
        // The binned SAH at the bins' boundaries, the three axes in three lanes (the same
        // operations per lane as one axis at a time). Per axis: the first of the two bins
        // beside its best plane (-1: none), and the counts left and right of that bin's lower
        // boundary.
        V4 v_hi = v_lo, v_extent = v_lo, v_cap = v_lo, v_girth = v_lo;
        V4I valid = {0, 0, 0, 0};
        for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            const float eb = box.hi[b] - box.lo[b], ec = box.hi[c] - box.lo[c];
            v_hi[a] = box.hi[a];
            v_extent[a] = extent[a];
            v_cap[a] = eb * ec;  // a child's area is 2 (cap + length * girth)
            v_girth[a] = eb + ec;
            valid[a] = extent[a] > 0.0f ? -1 : 0;
        }
        const V4 v_bins = {static_cast<float>(bins), static_cast<float>(bins), static_cast<float>(bins),
                           static_cast<float>(bins)};
        const float tc = m_opt.traversal_cost;
        V4I v_nl = {0, 0, 0, 0}, v_nr = {0, 0, 0, 0};
        v_nr += static_cast<int32_t>(n);
        V4I v_window = {-1, -1, -1, -1}, v_window_nl = v_nl, v_window_nr = v_nl;
        V4 axis_best = v_zero + std::numeric_limits<float>::infinity();
        for (int k = 1; k < bins; ++k) {
            const V4I nl_below = v_nl, nr_below = v_nr;
            v_nl += load4i(starts[k - 1]);
            v_nr -= load4i(ends[k - 1]);
            const V4 p = v_lo + v_extent * static_cast<float>(k) / v_bins;
            const V4 al = v_cap + (p - v_lo) * v_girth, ar = v_cap + (v_hi - p) * v_girth;
            V4 cost = tc + scale * (al * __builtin_convertvector(v_nl, V4) + ar * __builtin_convertvector(v_nr, V4));
            cost = ((v_nl == 0) | (v_nr == 0)) ? cost * bonus : cost;
            const V4I better = (cost < axis_best) & (p > v_lo) & (p < v_hi) & valid;
            axis_best = better ? cost : axis_best;
            v_window = better ? k - 1 : v_window;
            v_window_nl = better ? nl_below : v_window_nl;
            v_window_nr = better ? nr_below : v_window_nr;
        }
        const int window[3] = {v_window[0], v_window[1], v_window[2]};
        const int64_t window_nl[3] = {v_window_nl[0], v_window_nl[1], v_window_nl[2]};
        const int64_t window_nr[3] = {v_window_nr[0], v_window_nr[1], v_window_nr[2]};
        collect_windows(refs, window, starts, ends);
        for (int a = 0; a < 3; ++a) {
            if (window[a] < 0) continue;
            std::sort(m_window[a].begin(), m_window[a].end());
            sweep(m_window[a].data(), m_window[a].size(), a, box, window_nl[a], window_nr[a], best);
        }
        return best;
    }

    // The events of each axis's bounds that lie in bins w[a] and w[a] + 1 (w[a] < 0: none),
    // into m_window[a], in one pass over the references and their bins (m_bins). All
    // six tests of a reference are done at once on its eight bin bytes (below).
    void collect_windows(const RefList& refs, const int* w, const uint32_t (*starts)[4], const uint32_t (*ends)[4]) {
        const size_t n = refs.size();
        uint64_t pattern = 0, present = 0;
        size_t inside = 0;
        for (int a = 0; a < 3; ++a) {
            m_window[a].resize(2 * n);
            if (w[a] < 0) continue;
            pattern |= (uint64_t(w[a]) << (8 * a)) | (uint64_t(w[a]) << (32 + 8 * a));
            present |= (uint64_t(0x80) << (8 * a)) | (uint64_t(0x80) << (32 + 8 * a));
            inside += starts[w[a]][a] + starts[w[a] + 1][a] + ends[w[a]][a] + ends[w[a] + 1][a];
        }
        // Where the windows hold a good part of the bounds (small nodes, few bins), a test per
        // reference is a coin toss: no branch, every event written and kept where it belongs.
        // Elsewhere references with nothing in a window are skipped, by a branch rarely taken.
        if (8 * inside > 3 * n) collect_windows<false>(refs, pattern, present);
        else collect_windows<true>(refs, pattern, present);
    }
    template <bool kSkip>
    void collect_windows(const RefList& refs, uint64_t pattern, uint64_t present) {
        constexpr uint64_t kHigh = 0x8080808080808080ull, kLow7 = 0x7f7f7f7f7f7f7f7full;
        Event* out[3] = {m_window[0].data(), m_window[1].data(), m_window[2].data()};
        const uint64_t* rb = m_bins.data();
        const size_t n = refs.size();
        for (size_t i = 0; i < n; ++i) {
            // per byte, bin b and window w (both < 128): (b + 128 - w) without borrows, then
            // b - w mod 256, which is 0 or 1 where b is in the window; bit 7 of each byte of
            // `in` says that (the zero-byte test without false positives)
            const uint64_t d = ((rb[i] | kHigh) - pattern) ^ kHigh;
            const uint64_t z = d & ~0x0101010101010101ull;
            const uint64_t in = ~(((z & kLow7) + kLow7) | z) & present;
            if (kSkip && in == 0) continue;
            const Ref& r = refs[i];
            for (int a = 0; a < 3; ++a) {
                const bool start_in = (in >> (8 * a + 7)) & 1;
                const bool end_in = (in >> (32 + 8 * a + 7)) & 1;
                const bool planar = r.lo[a] == r.hi[a];
                Event*& o = out[a];
                *o = make_event(r.lo[a], r.tri, planar ? kPlanar : kStart);
                o += start_in;
                *o = make_event(r.hi[a], r.tri, kEnd);
                o += end_in & !planar;
            }
        }
        for (int a = 0; a < 3; ++a) m_window[a].resize(static_cast<size_t>(out[a] - m_window[a].data()));
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
    // Room for the usual tree (a 1M-triangle sphere: 0.42 nodes and 2.05 leaf entries a
    // triangle), so that the arrays do not grow by copying; pages never written cost nothing.
    builder.nodes.reserve(refs.size() + 1);
    builder.leaf_prims.reserve(3 * refs.size());
    builder.build(bounds, refs, 0, parallel_depth);
    tree.nodes = std::move(builder.nodes);
    tree.leaf_prims = std::move(builder.leaf_prims);
    tree.stats = builder.stats;
    tree.stats.nodes = tree.nodes.size();
    tree.stats.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return tree;
}

}  // namespace patina
