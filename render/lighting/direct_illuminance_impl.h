// The body of direct_illuminance_w{1,4,8,16}.cpp: the exact direct sum (direct_illuminance.h),
// N neighbouring sensors at a time. For each luminaire in turn: the N directions and squared
// distances, the sensors' responses, the luminaire's candela towards them, and one packet of N
// shadow rays through the renderer's BVH together (bvh_occluded_packet) for the lanes it lights.
// Every lane's arithmetic is the same at every width (exact division and square root, the
// fast inverse trigonometry's one polynomial, the terms added in the luminaires' order), so
// the wide paths give the scalar path's bits.
#pragma once

#include <cstdint>

#include "core/simd/kernel_width.h"
#include "render/accel/bvh_packet_occlusion.h"
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

// Lanes of `lit` whose ray from the sensor to the luminaire hits something: from the
// renderer's ray offset to kShadowShorten of the way short of the luminaire (the other lanes
// get an empty interval, which the traversal skips).
PATINA_INLINE B shadowed(const Bvh& occluders, float ray_offset, const V3& from, const WayToSource& w, B lit) {
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
    return lit & bvh_occluded_packet<N>(occluders, r);
}

// One luminaire's lux at N sensors: candela x response / d^2, 0 where it is hidden.
PATINA_INLINE F source_lux(const DirectSource& s, SensorKind kind, const SensorLanes& at, const Bvh* occluders,
                           float ray_offset) {
    const WayToSource w = way_to(s, at.point);
    const F response = sensor_response(kind, w.towards, at.normal);
    const B faced = at.real & (w.dist_squared > F(0.0f)) & (response > F(0.0f));
    if (none(faced)) return F(0.0f);
    const F lux = source_candela(s, -w.towards) * response / select(faced, w.dist_squared, F(1.0f));
    B lit = faced & (lux > F(0.0f));
    if (occluders && any(lit)) lit = andnot(shadowed(*occluders, ray_offset, at.point, w, lit), lit);
    return select(lit, lux, F(0.0f));
}

// Sensors [begin, end) in runs of kRunPackets packets, each run luminaire by luminaire: one
// luminaire's shadow rays from neighbouring packets walk the same part of the tree while it is
// in the cache.
constexpr size_t kRunPackets = 32;

inline void direct_sum(const DirectLighting& lighting, const IlluminanceSensors& sensors, float* lux,
                       float* per_source, size_t begin, size_t end) {
    enter_kernel();
    F total[kRunPackets];
    for (size_t run = begin; run < end; run += kRunPackets * N) {
        const size_t run_end = std::min(end, run + kRunPackets * N);
        for (F& t : total) t = F(0.0f);
        for (size_t k = 0; k < lighting.count; ++k) {
            for (size_t i = run, p = 0; i < run_end; i += N, ++p) {
                const int lanes = static_cast<int>(std::min<size_t>(N, run_end - i));
                const SensorLanes at = load_sensors(sensors, i, lanes);
                const F e = source_lux(lighting.sources[k], sensors.kind, at, lighting.occluders, lighting.ray_offset);
                total[p] += e;  // the luminaires' terms in their order, whatever the width
                if (per_source) store_lanes(per_source + k * sensors.count, i, lanes, e);
            }
        }
        for (size_t i = run, p = 0; i < run_end; i += N, ++p)
            store_lanes(lux, i, static_cast<int>(std::min<size_t>(N, run_end - i)), total[p]);
    }
}

}  // namespace render_detail
PATINA_END_TARGET
