// The body of direct_illuminance_w{1,4,8,16}.cpp: the exact direct sum (direct_illuminance.h),
// N neighbouring sensors at a time. For each luminaire in turn: the N directions and squared
// distances, the sensors' responses, the luminaire's candela towards them, and one packet of N
// shadow rays for the lanes it lights, through the renderer's BVH in a stream that gathers the
// lanes of packets split at an occluder's outline into full packets (bvh_occlusion_stream.h).
// Every lane's arithmetic is the same at every width (exact division and square root, the
// fast inverse trigonometry's one polynomial, the terms added in the luminaires' order), so
// the wide paths give the scalar path's bits.
#pragma once

#include <algorithm>
#include <cstdint>
#include <optional>

#include "core/simd/kernel_width.h"
#include "render/accel/bvh_occlusion_stream.h"
#include "render/accel/ray_packet.h"
#include "render/lighting/direct_illuminance.h"
#include "render/lighting/sensor_response_impl.h"
#include "render/lighting/source_intensity_impl.h"

PATINA_BEGIN_TARGET
namespace render_detail {
using namespace kernel_width;

// N sensors: their points, normals (or facings) and which lanes hold a sensor at all (the
// last packet's may not).
struct SensorLanes {
    V3 point, normal;
    B real;
};

inline SensorLanes load_sensors(const IlluminanceSensors& sensors, size_t i, int lanes) {
    alignas(64) static constexpr int32_t kLaneIndex[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
    SensorLanes s;
    s.point = load_rows(sensors.points, i, lanes);
    s.normal = sensors.normals ? load_rows(sensors.normals, i, lanes) : V3{F(0.0f), F(0.0f), F(0.0f)};
    s.real = load_n<N>(kLaneIndex) < I(lanes);
    return s;
}

// The way from N sensors to a luminaire: unit directions and squared distances. A sensor at
// the luminaire itself gets dist_squared = 0 and a harmless direction (it receives nothing).
struct WayToSource {
    V3 towards;
    F dist_squared, dist;
};

PATINA_INLINE WayToSource way_to(const DirectSource& s, const V3& from) {
    const V3 to{F(s.position[0]) - from.x, F(s.position[1]) - from.y, F(s.position[2]) - from.z};
    WayToSource w;
    w.dist_squared = dot(to, to);
    w.dist = sqrt_exact(w.dist_squared);
    const B apart = w.dist_squared > F(0.0f);
    const F inverse = F(1.0f) / select(apart, w.dist, F(1.0f));
    w.towards = V3{select(apart, to.x * inverse, F(0.0f)), select(apart, to.y * inverse, F(0.0f)),
                   select(apart, to.z * inverse, F(1.0f))};
    return w;
}

// The shadow rays of the lanes `lit`: from the renderer's ray offset to kShadowShorten of the
// way short of the luminaire (the other lanes get an empty interval, which the traversal skips).
PATINA_INLINE RayPacket<N> shadow_rays(float ray_offset, const V3& from, const WayToSource& w, B lit) {
    RayPacket<N> r;
    r.org[0] = from.x;
    r.org[1] = from.y;
    r.org[2] = from.z;
    r.dir[0] = w.towards.x;
    r.dir[1] = w.towards.y;
    r.dir[2] = w.towards.z;
    r.tmin = F(ray_offset);
    r.tmax = select(lit, w.dist * F(1.0f - kShadowShorten), F(-1.0f));
    prepare_packet<N>(r);
    return r;
}

// One luminaire's lux at N sensors as if nothing were in the way (candela x response / d^2),
// and the lanes it lights, whose shadow rays are still to trace.
struct UnshadowedLux {
    F lux;
    B lit;
};

PATINA_INLINE UnshadowedLux unshadowed_lux(const DirectSource& s, SensorKind kind, const SensorLanes& at,
                                           const WayToSource& w) {
    const F response = sensor_response(kind, w.towards, at.normal);
    const B faced = at.real & (w.dist_squared > F(0.0f)) & (response > F(0.0f));
    if (none(faced)) return UnshadowedLux{F(0.0f), B(false)};
    const F lux = source_candela(s, -w.towards) * response / select(faced, w.dist_squared, F(1.0f));
    const B lit = faced & (lux > F(0.0f));
    return UnshadowedLux{lux, lit};
}

// Sensors [begin, end) in runs of kRunPackets packets, each run luminaire by luminaire: the
// luminaire's lux at every packet of the run first, their shadow rays through one stream
// (bvh_occlusion_stream.h: the lanes of packets that split at an occluder's outline gathered
// into full packets again), then each packet's terms. One luminaire's shadow rays from
// neighbouring packets walk the same part of the tree while it is in the cache.
constexpr size_t kRunPackets = 256;

// One run's sums, luminaire by luminaire.
class DirectRun {
public:
    DirectRun(const DirectLighting& lighting, const IlluminanceSensors& sensors, float* per_source)
        : lighting_(lighting), sensors_(sensors), per_source_(per_source) {
        if (lighting.occluders) stream_.emplace(*lighting.occluders, kRunPackets);
    }

    // Sensors [run, run_end) into lux.
    void sum(size_t run, size_t run_end, float* lux) {
        for (F& t : total_) t = F(0.0f);
        for (size_t k = 0; k < lighting_.count; ++k) {
            for (size_t i = run, p = 0; i < run_end; i += N, ++p) light(k, i, lanes(i, run_end), p);
            if (stream_) stream_->finish();
            for (size_t i = run, p = 0; i < run_end; i += N, ++p) add(k, i, lanes(i, run_end), p);
        }
        for (size_t i = run, p = 0; i < run_end; i += N, ++p) store_lanes(lux, i, lanes(i, run_end), total_[p]);
    }

private:
    static int lanes(size_t i, size_t run_end) { return static_cast<int>(std::min<size_t>(N, run_end - i)); }

    // Luminaire k's lux at packet p (sensors i ...), its shadow rays into the stream.
    void light(size_t k, size_t i, int lanes, size_t p) {
        const SensorLanes at = load_sensors(sensors_, i, lanes);
        const WayToSource w = way_to(lighting_.sources[k], at.point);
        unshadowed_[p] = unshadowed_lux(lighting_.sources[k], sensors_.kind, at, w);
        if (stream_ && any(unshadowed_[p].lit))
            stream_->trace(shadow_rays(lighting_.ray_offset, at.point, w, unshadowed_[p].lit), unshadowed_[p].lit, p);
    }

    // Luminaire k's term at packet p: its lux where the shadow ray is clear.
    void add(size_t k, size_t i, int lanes, size_t p) {
        B lit = unshadowed_[p].lit;
        if (stream_ && any(lit)) lit = andnot(stream_->blocked(p), lit);
        const F e = select(lit, unshadowed_[p].lux, F(0.0f));
        total_[p] += e;  // the luminaires' terms in their order, whatever the width
        if (per_source_) store_lanes(per_source_ + k * sensors_.count, i, lanes, e);
    }

    const DirectLighting& lighting_;
    const IlluminanceSensors& sensors_;
    float* per_source_;
    std::optional<BvhOcclusionStream<N>> stream_;
    F total_[kRunPackets];
    UnshadowedLux unshadowed_[kRunPackets];
};

inline void direct_sum(const DirectLighting& lighting, const IlluminanceSensors& sensors, float* lux,
                       float* per_source, size_t begin, size_t end) {
    enter_kernel();
    DirectRun runs(lighting, sensors, per_source);
    for (size_t run = begin; run < end; run += kRunPackets * N) runs.sum(run, std::min(end, run + kRunPackets * N), lux);
}

}  // namespace render_detail
PATINA_END_TARGET
