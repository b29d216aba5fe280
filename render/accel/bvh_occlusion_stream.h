// A stream of shadow rays through the 8-wide BVH in full packets (issue 32). A packet of K
// rays (bvh_packet_occlusion.h) splits where its rays part -- at an occluder's outline -- and
// its few lanes left would go on alone; here they wait at that node instead, with the lanes of
// other packets of the batch that split at the same node, and go on together as a packet again
// once K have gathered (or when the batch ends): the coherent ray tracing's full lanes, kept by
// compaction. Made for the exact direct illuminance (render/lighting/), whose batch is one
// luminaire's shadow rays from a run of neighbouring sensors' packets.
//
// Each lane's answer is a boolean (blocked or not) and a ray's tests are the same lane by lane
// whichever packet holds it (bvh_packet_occlusion.h), so the answers are those of the packets
// alone at every width.
#pragma once

#include <cstdint>
#include <vector>

#include "render/accel/bvh.h"
#include "render/accel/bvh_packet_occlusion.h"
#include "render/accel/ray_packet.h"
#include "render/accel/sphere_test.h"

PATINA_BEGIN_TARGET

template <int K>
class BvhOcclusionStream {
public:
    // A batch of up to `packets` packets (slots packets x K).
    BvhOcclusionStream(const Bvh& bvh, size_t packets) : bvh_(bvh), blocked_bits_(packets) {
        for (std::vector<float>& row : rays_) row.resize(packets * K);
    }

    // Packet p's rays (slots p K ...), lanes `open` of r (as prepare_packet leaves it): the
    // spheres and the tree's nodes the lanes share now; the rest when finish() is called.
    void trace(const RayPacket<K>& r, vbool<K> open, size_t p) {
        if constexpr (K > 1) keep_rays(r, p);  // a single ray never splits
        const vbool<K> by_sphere = bvh_.spheres.empty()
                                       ? vbool<K>(false)
                                       : occluded_by_spheres<K>(bvh_.spheres, r.org, r.dir, r.tmin, r.tmax);
        open = andnot(by_sphere, open);
        blocked_bits_[p] = 0;  // before the traversal: a bucket it flushes may hold this packet's lanes
        waiting_bits_ = 0;
        const vbool<K> by_triangle =
            none(open) ? vbool<K>(false) : bvh_occluded_triangles_from<K>(bvh_, r, bvh_.root, open, WaitAtSplit{this, p});
        blocked_bits_[p] |= static_cast<uint32_t>(movemask(by_sphere | by_triangle)) & ~waiting_bits_;
    }

    // The waiting rays, in packets of what has gathered at each node.
    void finish() {
        if constexpr (K > 1)
            for (Bucket& b : buckets_)
                if (b.count > 0) flush(b);
    }

    // Packet p's lanes blocked (after finish()).
    vbool<K> blocked(size_t p) const { return lanes_of(blocked_bits_[p]); }

    // The lanes whose bits are set.
    static vbool<K> lanes_of(uint32_t bits) {
        if constexpr (K == 1) {
            return bits != 0;
        } else {
            alignas(64) static constexpr int32_t kLaneBit[16] = {1 << 0, 1 << 1, 1 << 2,  1 << 3,  1 << 4,  1 << 5,
                                                                  1 << 6, 1 << 7, 1 << 8,  1 << 9,  1 << 10, 1 << 11,
                                                                  1 << 12, 1 << 13, 1 << 14, 1 << 15};
            const vint<K> bit = load_n<K>(kLaneBit);
            return (vint<K>(static_cast<int32_t>(bits)) & bit) == bit;
        }
    }

private:
    // The rays waiting at one node: slots.
    struct Bucket {
        uint32_t node = 0;
        int count = 0;
        uint32_t slot[K];
    };
    // Distinct nodes that wait at once; a node whose bucket is taken by another flushes it.
    // Neighbouring packets split at the same few nodes (a ball's outline), so few collide.
    static constexpr int kBuckets = 64;
    enum Row { OrgX, OrgY, OrgZ, DirX, DirY, DirZ, Tmin, Tmax, kRows };

    // The split handler: each open lane entering some child waits at `node`; none is blocked yet.
    struct WaitAtSplit {
        BvhOcclusionStream* stream;
        size_t packet;
        PATINA_INLINE vbool<K> operator()(const Bvh&, const RayPacket<K>&, const bvh_packet_detail::BoxLanes<K>&,
                                          uint32_t node, const int* entered, vbool<K> open) const {
            int entering = 0;
            for (int c = 0; c < kBvhWidth; ++c) entering |= entered[c];
            const int waiting = movemask(open) & entering;
            stream->waiting_bits_ |= static_cast<uint32_t>(waiting);
            for (int m = waiting; m; m &= m - 1)
                stream->wait(node, static_cast<uint32_t>(packet * K + __builtin_ctz(static_cast<unsigned>(m))));
            return open & lanes_of(static_cast<uint32_t>(waiting));
        }
    };

    void keep_rays(const RayPacket<K>& r, size_t p) {
        const vfloat<K> rows[kRows] = {r.org[0], r.org[1], r.org[2], r.dir[0], r.dir[1], r.dir[2], r.tmin, r.tmax};
        for (int row = 0; row < kRows; ++row) store_n<K>(&rays_[row][p * K], rows[row]);
    }

    void wait(uint32_t node, uint32_t slot) {
        Bucket& b = buckets_[(node * 0x9E3779B1u) >> 26];  // Fibonacci hashing onto 64 buckets
        if (b.count > 0 && b.node != node) flush(b);
        b.node = node;
        b.slot[b.count++] = slot;
        if (b.count == K) flush(b);
    }

    // The bucket's rays as one packet from its node; lanes past its count repeat its first ray
    // (so the packet's signs and axes stay uniform) and are not open.
    void flush(Bucket& b) {
        alignas(64) float lanes[kRows][K];
        for (int j = 0; j < K; ++j)
            for (int row = 0; row < kRows; ++row) lanes[row][j] = rays_[row][b.slot[j < b.count ? j : 0]];
        RayPacket<K> r;
        for (int a = 0; a < 3; ++a) {
            r.org[a] = load_n<K>(lanes[OrgX + a]);
            r.dir[a] = load_n<K>(lanes[DirX + a]);
        }
        r.tmin = load_n<K>(lanes[Tmin]);
        r.tmax = load_n<K>(lanes[Tmax]);
        prepare_packet<K>(r);
        const vbool<K> blocked = bvh_occluded_triangles_from<K>(bvh_, r, bvh_.root, first_lanes(b.count),
                                                                bvh_packet_detail::SplitIntoSingleRays<K>{});
        for (int m = movemask(blocked); m; m &= m - 1) {
            const uint32_t slot = b.slot[__builtin_ctz(static_cast<unsigned>(m))];
            blocked_bits_[slot / K] |= 1u << (slot % K);
        }
        b.count = 0;
    }

    static vbool<K> first_lanes(int count) {
        alignas(64) static constexpr int32_t kLaneIndex[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
        return load_n<K>(kLaneIndex) < vint<K>(count);
    }

    const Bvh& bvh_;
    std::vector<float> rays_[kRows];
    uint32_t waiting_bits_ = 0;
    std::vector<uint32_t> blocked_bits_;  // per packet, bit j: lane j blocked
    Bucket buckets_[kBuckets];
};

PATINA_END_TARGET
