// SAH kd-tree construction in O(N log N) (Wald and Havran, "On building fast
// kd-trees for ray tracing, and on doing that in O(N log N)", 2006).
//
// Every node keeps, per axis, its triangles' bound events (start, end, or planar for
// flat bounds) sorted by position. One sweep per axis evaluates the SAH at every
// event; the chosen split then divides the lists in order. Only triangles that
// straddle the plane are clipped to each child's box ("perfect splits") and get new
// events, which are sorted (few) and merged in, so no list is ever sorted again.
//
// Above kSweepBelow triangles a node chooses its plane from binned counts instead
// (Shevtsov, Soupikov, Kapustin 2007): O(n) per node with no sorted lists, still
// with perfect splits. Each subtree that gets small enough sorts its events once,
// O(n log kSweepBelow), and continues with the exact sweep; the whole build stays
// O(N log N), most of it in the sweep, and is several times faster on large meshes.
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

// An event packed into 64 bits so that sorting and merging compare plain integers: the
// position's bits mapped to an unsigned key that sorts as the floats do (high 32 bits),
// then the type (end < planar < start at one position, as the sweep needs), then the
// triangle (30 bits; build_kdtree's callers refuse 2^30 triangles or more).
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
uint32_t event_tri(Event e) { return static_cast<uint32_t>(e) & 0x3fffffffu; }
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

struct NodeEvents {
    EventList axis[3];
};

// Sorts a node's events by position, then type (bits 30-63), keeping the given order of
// equal ones: LSD radix sort over the bits in which the list's keys differ (positions in
// a small node share their high bits), 11 bits a pass; std::stable_sort for short lists,
// where the histograms would cost more than the sort.
void sort_events(EventList& ev, EventList& scratch) {
    const size_t n = ev.size();
    if (n < 128) {
        std::stable_sort(ev.begin(), ev.end(), [](Event a, Event b) { return (a >> 30) < (b >> 30); });
        return;
    }
    uint64_t lo = ~uint64_t(0), hi = 0;
    for (const Event e : ev) {
        lo = std::min(lo, e >> 30);
        hi = std::max(hi, e >> 30);
    }
    const int bits = hi == lo ? 0 : 64 - __builtin_clzll(hi ^ lo);  // the differing low bits of (e >> 30)
    // digits of 11 bits for long lists, of 8 for short ones, whose histograms would
    // otherwise cost more than the pass itself
    const int digit = n < 4096 ? 8 : 11;
    scratch.resize(n);
    Event* src = ev.data();
    Event* dst = scratch.data();
    for (int shift = 30; shift < 30 + bits; shift += digit) {
        const uint64_t mask = (uint64_t(1) << digit) - 1;
        uint32_t count[1 << 11];
        std::fill(count, count + mask + 1, 0u);
        for (size_t i = 0; i < n; ++i) ++count[(src[i] >> shift) & mask];
        uint32_t sum = 0;
        for (uint64_t b = 0; b <= mask; ++b) {
            const uint32_t c = count[b];
            count[b] = sum;
            sum += c;
        }
        for (size_t i = 0; i < n; ++i) dst[count[(src[i] >> shift) & mask]++] = src[i];
        std::swap(src, dst);
    }
    if (src != ev.data()) ev.swap(scratch);  // an odd number of passes left the result in scratch
}

enum Side : uint8_t { kBoth = 0, kLeftOnly = 1, kRightOnly = 2 };

// A triangle's bounds within a node, for the binned phase.
struct Ref {
    Box3 b;
    uint32_t tri;
};

constexpr size_t kSweepBelow = 256;  // nodes with fewer references use the exact sweep
static_assert(2 * kSweepBelow < (size_t(1) << 21), "the sweep counts a position's events in 21-bit fields");
constexpr int kBins = 128;

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

// Bounds of the part of triangle t inside `box` (Sutherland-Hodgman in double);
// false if nothing of it is inside. Only the planes that some vertex lies beyond are
// clipped against (a plane with every vertex inside leaves the polygon as it is), which
// for a triangle straddling one split plane is one plane of six.
bool clipped_bounds(const float* t, const Box3& box, Box3& out) {
    double poly[2][16][3];
    int n = 3;
    float tlo[3], thi[3];
    for (int a = 0; a < 3; ++a) {
        tlo[a] = std::min({t[a], t[3 + a], t[6 + a]});
        thi[a] = std::max({t[a], t[3 + a], t[6 + a]});
    }
    for (int v = 0; v < 3; ++v)
        for (int a = 0; a < 3; ++a) poly[0][v][a] = t[3 * v + a];
    int cur = 0;
    for (int a = 0; a < 3 && n > 0; ++a) {
        for (int upper = 0; upper < 2 && n > 0; ++upper) {
            if (upper ? !(thi[a] > box.hi[a]) : !(tlo[a] < box.lo[a])) continue;
            const double plane = upper ? box.hi[a] : box.lo[a];
            auto inside = [&](const double* p) { return upper ? p[a] <= plane : p[a] >= plane; };
            double(*src)[3] = poly[cur];
            double(*dst)[3] = poly[1 - cur];
            int m = 0;
            for (int i = 0; i < n; ++i) {
                const double* p = src[i];
                const double* q = src[(i + 1) % n];
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
            n = m;
            cur = 1 - cur;
        }
    }
    if (n == 0) return false;
    for (int a = 0; a < 3; ++a) {
        double lo = poly[cur][0][a], hi = lo;
        for (int i = 1; i < n; ++i) {
            lo = std::min(lo, poly[cur][i][a]);
            hi = std::max(hi, poly[cur][i][a]);
        }
        // round outwards, then keep inside the box
        out.lo[a] = std::max(box.lo[a], next_down(static_cast<float>(lo)));
        out.hi[a] = std::min(box.hi[a], next_up(static_cast<float>(hi)));
        if (out.lo[a] > out.hi[a]) return false;
    }
    return true;
}

// Appends triangles' bound events to a node's three lists through raw pointers, the lists
// sized beforehand for the worst case (two events an axis a triangle) and cut to what was
// written at the end: no capacity check per event.
class EventWriter {
public:
    EventWriter(NodeEvents& ev, size_t max_triangles) : m_ev(ev) {
        for (int a = 0; a < 3; ++a) {
            const size_t size = ev.axis[a].size();
            ev.axis[a].resize(size + 2 * max_triangles);
            m_at[a] = ev.axis[a].data() + size;
        }
    }
    ~EventWriter() {
        for (int a = 0; a < 3; ++a) m_ev.axis[a].resize(static_cast<size_t>(m_at[a] - m_ev.axis[a].data()));
    }
    EventWriter(const EventWriter&) = delete;
    EventWriter& operator=(const EventWriter&) = delete;

    void add(uint32_t tri, const Box3& b) {
        for (int a = 0; a < 3; ++a) {
            if (b.lo[a] == b.hi[a]) {
                *m_at[a]++ = make_event(b.lo[a], tri, kPlanar);
            } else {
                *m_at[a]++ = make_event(b.lo[a], tri, kStart);
                *m_at[a]++ = make_event(b.hi[a], tri, kEnd);
            }
        }
    }

private:
    NodeEvents& m_ev;
    Event* m_at[3];
};

class Builder {
public:
    Builder(const std::vector<float>& triangles, const KdBuildOptions& opt, int max_depth)
        : m_tris(triangles), m_opt(opt), m_max_depth(max_depth), m_side(triangles.size() / 9, kBoth) {}

    std::vector<KdNode> nodes;
    std::vector<uint32_t> leaf_prims;
    KdTreeStats stats;

    // Builds the subtree of a node into `nodes` and returns its index; consumes `ev`
    // (its lists go back to the pool). `parallel_depth` > 0 builds the two children in
    // parallel (each in its own Builder), then splices.
    uint32_t build(const Box3& box, NodeEvents& ev, size_t n, int depth, int parallel_depth) {
        stats.depth = std::max(stats.depth, depth);
        const uint32_t index = static_cast<uint32_t>(nodes.size());
        nodes.push_back(KdNode{});
        const Split split = (n <= static_cast<size_t>(m_opt.max_leaf) || depth >= m_max_depth)
                                ? Split{}
                                : find_split(ev, box, n);
        if (split.axis < 0 || !(split.cost < m_opt.intersection_cost * static_cast<float>(n))) {
            make_leaf(index, ev, n);
            release(ev);
            return index;
        }
        Box3 left_box = box, right_box = box;
        left_box.hi[split.axis] = split.pos;
        right_box.lo[split.axis] = split.pos;
        NodeEvents left_ev, right_ev;
        size_t nl = 0, nr = 0;
        distribute(ev, split, left_box, right_box, left_ev, right_ev, nl, nr);
        release(ev);  // the parent's lists serve the children's children
        nodes[index].split = split.pos;
        ++stats.nodes;

        uint32_t above;
        if (parallel_depth > 0 && nl + nr > 20000) {
            Builder right(m_tris, m_opt, m_max_depth);
            auto future = std::async(std::launch::async, [&] {
                right.build(right_box, right_ev, nr, depth + 1, parallel_depth - 1);
            });
            build(left_box, left_ev, nl, depth + 1, parallel_depth - 1);
            future.get();
            above = splice(right);
        } else {
            build(left_box, left_ev, nl, depth + 1, parallel_depth - 1);
            above = build(right_box, right_ev, nr, depth + 1, parallel_depth - 1);
        }
        nodes[index].bits = (above << 2) | static_cast<uint32_t>(split.axis);
        return index;
    }

    // The binned phase for large nodes; hands each small enough subtree to build().
    uint32_t build_binned(const Box3& box, std::vector<Ref>& refs, int depth, int parallel_depth) {
        const size_t n = refs.size();
        if (n <= kSweepBelow || depth >= m_max_depth) {
            NodeEvents ev;
            for (int a = 0; a < 3; ++a) ev.axis[a] = take();
            {
                EventWriter out(ev, n);
                for (const Ref& r : refs) out.add(r.tri, r.b);
            }
            give_refs(refs);
            EventList scratch = take();
            for (int a = 0; a < 3; ++a) sort_events(ev.axis[a], scratch);
            m_pool.push_back(std::move(scratch));
            return build(box, ev, n, depth, parallel_depth);
        }
        stats.depth = std::max(stats.depth, depth);
        const uint32_t index = static_cast<uint32_t>(nodes.size());
        nodes.push_back(KdNode{});
        const Split split = find_binned_split(refs, box, n);
        if (split.axis < 0 || !(split.cost < m_opt.intersection_cost * static_cast<float>(n))) {
            KdNode& node = nodes[index];
            node.first = static_cast<uint32_t>(leaf_prims.size());
            node.bits = (static_cast<uint32_t>(n) << 2) | 3u;
            for (const Ref& r : refs) leaf_prims.push_back(r.tri);
            ++stats.leaves;
            stats.leaf_refs += n;
            return index;
        }
        Box3 left_box = box, right_box = box;
        left_box.hi[split.axis] = split.pos;
        right_box.lo[split.axis] = split.pos;
        std::vector<Ref> left = take_refs(), right = take_refs();
        left.reserve(n / 2 + n / 8);
        right.reserve(n / 2 + n / 8);
        const int a = split.axis;
        const float p = split.pos;
        for (const Ref& r : refs) {
            if (r.b.lo[a] == p && r.b.hi[a] == p) (split.planar_left ? left : right).push_back(r);
            else if (r.b.hi[a] <= p) left.push_back(r);
            else if (r.b.lo[a] >= p) right.push_back(r);
            else {
                Ref c{Box3{}, r.tri};
                const float* t = &m_tris[9 * size_t(r.tri)];
                if (clipped_bounds(t, left_box, c.b)) left.push_back(c);
                if (clipped_bounds(t, right_box, c.b)) right.push_back(c);
            }
        }
        give_refs(refs);
        nodes[index].split = p;
        uint32_t above;
        if (parallel_depth > 0) {
            Builder other(m_tris, m_opt, m_max_depth);
            auto future = std::async(std::launch::async, [&] {
                other.build_binned(right_box, right, depth + 1, parallel_depth - 1);
            });
            build_binned(left_box, left, depth + 1, parallel_depth - 1);
            future.get();
            above = splice(other);
        } else {
            build_binned(left_box, left, depth + 1, parallel_depth - 1);
            above = build_binned(right_box, right, depth + 1, parallel_depth - 1);
        }
        nodes[index].bits = (above << 2) | static_cast<uint32_t>(a);
        return index;
    }

private:
    const std::vector<float>& m_tris;
    const KdBuildOptions& m_opt;
    int m_max_depth;
    std::vector<uint8_t> m_side;  // scratch, per triangle
    // Event lists no longer needed, kept with their capacity: the sweep phase builds
    // millions of small nodes, and allocating their lists anew cost a fifth of the build.
    std::vector<EventList> m_pool;
    NodeEvents m_scratch[2];  // the clipped triangles' new events, per child

    // Reference lists of the binned phase, likewise: a level's lists are megabytes, and fresh
    // ones are fresh pages the kernel must zero.
    std::vector<std::vector<Ref>> m_ref_pool;

    std::vector<Ref> take_refs() {
        if (m_ref_pool.empty()) return {};
        std::vector<Ref> v = std::move(m_ref_pool.back());
        m_ref_pool.pop_back();
        v.clear();
        return v;
    }
    void give_refs(std::vector<Ref>& v) {
        if (v.capacity() && m_ref_pool.size() < 8) m_ref_pool.push_back(std::move(v));
        v = std::vector<Ref>{};
    }

    EventList take() {
        if (m_pool.empty()) return {};
        EventList v = std::move(m_pool.back());
        m_pool.pop_back();
        v.clear();
        return v;
    }
    void release(NodeEvents& ev) {
        for (EventList& v : ev.axis)
            if (v.capacity()) m_pool.push_back(std::move(v));
    }

    Split find_split(const NodeEvents& ev, const Box3& box, size_t n) const {
        Split best;
        const float area = box.area();
        if (!(area > 0.0f)) return best;
        const float scale = m_opt.intersection_cost * 2.0f / area;  // K_I * (child area / 2) / (area / 2)
        const float bonus = 1.0f - m_opt.empty_bonus;
        for (int a = 0; a < 3; ++a) {
            // a child's surface area is linear in the split position: 2 (cap + len * girth)
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
            const Event* e = ev.axis[a].data();
            const size_t count = ev.axis[a].size();
            int64_t nl = 0, nr = static_cast<int64_t>(n);
            for (size_t i = 0; i < count;) {
                // all events at this position: ends, then planars, then starts (the sort order),
                // counted as 21-bit fields of one integer indexed by the type (the sweep's
                // nodes hold at most kSweepBelow triangles, two events each)
                const uint32_t key = event_key(e[i]);
                uint64_t counts = 0;
                do {
                    counts += uint64_t(1) << (21 * event_type(e[i]));
                    ++i;
                } while (i < count && event_key(e[i]) == key);
                constexpr uint64_t kField = (uint64_t(1) << 21) - 1;
                const int64_t ends = static_cast<int64_t>(counts & kField);
                const int64_t planars = static_cast<int64_t>((counts >> 21) & kField);
                const int64_t starts = static_cast<int64_t>(counts >> 42);
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
        return best;
    }

    // SAH at kBins - 1 evenly spaced planes per axis, from per-bin counts of where the
    // references start and end (a reference is on a plane's left if it starts in a bin
    // below it, on its right if it ends in a bin at or above it). One pass over the
    // references fills the bins of all three axes.
    Split find_binned_split(const std::vector<Ref>& refs, const Box3& box, size_t n) const {
        Split best;
        const float area = box.area();
        if (!(area > 0.0f)) return best;
        const float scale = m_opt.intersection_cost * 2.0f / area;
        const float bonus = 1.0f - m_opt.empty_bonus;
        float lo[3], extent[3], to_bin[3];
        for (int a = 0; a < 3; ++a) {
            lo[a] = box.lo[a];
            extent[a] = box.hi[a] - box.lo[a];
            to_bin[a] = extent[a] > 0.0f ? kBins / extent[a] : 0.0f;
        }
        uint32_t starts[3][kBins] = {}, ends[3][kBins] = {};
        for (const Ref& r : refs) {
            for (int a = 0; a < 3; ++a) {
                ++starts[a][std::clamp(static_cast<int>((r.b.lo[a] - lo[a]) * to_bin[a]), 0, kBins - 1)];
                ++ends[a][std::clamp(static_cast<int>((r.b.hi[a] - lo[a]) * to_bin[a]), 0, kBins - 1)];
            }
        }
        for (int a = 0; a < 3; ++a) {
            if (!(extent[a] > 0.0f)) continue;
            const float hi = box.hi[a];
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            const float eb = box.hi[b] - box.lo[b], ec = box.hi[c] - box.lo[c];
            const float cap = eb * ec, girth = eb + ec;
            size_t nl = 0, nr = n;
            for (int k = 1; k < kBins; ++k) {
                nl += starts[a][k - 1];
                nr -= ends[a][k - 1];
                const float p = lo[a] + extent[a] * static_cast<float>(k) / kBins;
                const float al = cap + (p - lo[a]) * girth, ar = cap + (hi - p) * girth;
                float cost = m_opt.traversal_cost + scale * (al * static_cast<float>(nl) + ar * static_cast<float>(nr));
                if (nl == 0 || nr == 0) cost *= bonus;
                if (cost < best.cost && p > lo[a] && p < hi) best = Split{a, p, true, cost};
            }
        }
        return best;
    }

    void make_leaf(uint32_t index, const NodeEvents& ev, size_t n) {
        KdNode& node = nodes[index];
        node.first = static_cast<uint32_t>(leaf_prims.size());
        node.bits = (static_cast<uint32_t>(n) << 2) | 3u;
        for (const Event e : ev.axis[0])
            if (event_type(e) != kEnd) leaf_prims.push_back(event_tri(e));
        ++stats.leaves;
        if (n == 0) ++stats.empty_leaves;
        stats.leaf_refs += n;
    }

    void distribute(const NodeEvents& ev, const Split& s, const Box3& left_box, const Box3& right_box,
                    NodeEvents& left, NodeEvents& right, size_t& nl, size_t& nr) {
        // One pass over the split axis sides every triangle. Its start comes before its end
        // (a flat bound is one planar event instead), so a start at or above the plane says
        // right and one below it says both; an end at or below the plane, seen later, says
        // left; a planar event says left or right. A table indexed by the type, the
        // comparison that type needs and the side so far replaces the branches: the event
        // types come in no predictable order.
        const EventList& e = ev.axis[s.axis];
        const uint32_t split_key = float_key(s.pos);
        const uint32_t planar_key = s.planar_left ? split_key + 1 : split_key;  // planar events below it go left
        static constexpr uint8_t kNext[3][2][4] = {
            // kEnd: key <= split ? left : as it was
            {{kBoth, kLeftOnly, kRightOnly, kBoth}, {kLeftOnly, kLeftOnly, kLeftOnly, kLeftOnly}},
            // kPlanar: key < planar_key ? left : right
            {{kRightOnly, kRightOnly, kRightOnly, kRightOnly}, {kLeftOnly, kLeftOnly, kLeftOnly, kLeftOnly}},
            // kStart: key >= split ? right : both
            {{kBoth, kBoth, kBoth, kBoth}, {kRightOnly, kRightOnly, kRightOnly, kRightOnly}},
        };
        for (const Event x : e) {
            const uint32_t key = event_key(x);
            const EventType type = event_type(x);
            const bool test = type == kEnd ? key <= split_key : type == kPlanar ? key < planar_key : key >= split_key;
            uint8_t& side = m_side[event_tri(x)];
            side = kNext[type][test][side];
        }
        // straddling triangles, clipped to each side, get new events
        NodeEvents& left_new = m_scratch[0];
        NodeEvents& right_new = m_scratch[1];
        for (int a = 0; a < 3; ++a) {
            left_new.axis[a].clear();
            right_new.axis[a].clear();
        }
        nl = nr = 0;
        {
            EventWriter left_out(left_new, e.size()), right_out(right_new, e.size());
            for (const Event x : e) {
                // one visit per triangle, at its start or planar event; counted without a
                // branch, which only the straddling triangles take
                const bool first = event_type(x) != kEnd;
                const uint32_t tri = event_tri(x);
                const uint8_t side = m_side[tri];
                nl += first & (side == kLeftOnly);
                nr += first & (side == kRightOnly);
                if (first && side == kBoth) {
                    Box3 b;
                    const float* t = &m_tris[9 * size_t(tri)];
                    if (clipped_bounds(t, left_box, b)) {
                        left_out.add(tri, b);
                        ++nl;
                    }
                    if (clipped_bounds(t, right_box, b)) {
                        right_out.add(tri, b);
                        ++nr;
                    }
                }
            }
        }
        for (int a = 0; a < 3; ++a) {
            left.axis[a] = take();
            right.axis[a] = take();
            EventList& l = left.axis[a];
            EventList& r = right.axis[a];
            const EventList& src = ev.axis[a];
            // sized for the worst case: every event written is kept or overwritten
            l.resize(src.size());
            r.resize(src.size());
            size_t nl_events = 0, nr_events = 0;
            for (const Event x : src) {
                // write both, advance the one that keeps it: no unpredictable branch
                const uint8_t side = m_side[event_tri(x)];
                l[nl_events] = x;
                r[nr_events] = x;
                nl_events += side == kLeftOnly;
                nr_events += side == kRightOnly;
            }
            l.resize(nl_events);
            r.resize(nr_events);
            merge_in(l, left_new.axis[a]);
            merge_in(r, right_new.axis[a]);
        }
    }

    // Merges the (few, unsorted) events of clipped triangles into a sorted list, in
    // place from the back: only the events above the lowest new one move, each once.
    static void merge_in(EventList& sorted, EventList& extra) {
        if (extra.empty()) return;
        std::sort(extra.begin(), extra.end());
        const size_t n = sorted.size(), m = extra.size();
        sorted.resize(n + m);
        Event* e = sorted.data();
        size_t i = n, j = m, k = n + m;
        while (j > 0) {
            if (i > 0 && e[i - 1] > extra[j - 1]) e[--k] = e[--i];
            else e[--k] = extra[--j];
        }
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
    std::vector<Ref> refs;
    refs.reserve(triangle_count);
    for (size_t t = 0; t < triangle_count; ++t) {
        const float* n = &tree.normals[3 * t];
        if (n[0] == 0.0f && n[1] == 0.0f && n[2] == 0.0f) continue;
        refs.push_back(Ref{Box3{}, static_cast<uint32_t>(t)});
        Box3& b = refs.back().b;
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
    builder.build_binned(bounds, refs, 0, parallel_depth);
    tree.nodes = std::move(builder.nodes);
    tree.leaf_prims = std::move(builder.leaf_prims);
    tree.stats = builder.stats;
    tree.stats.nodes = tree.nodes.size();
    tree.stats.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return tree;
}

}  // namespace patina
