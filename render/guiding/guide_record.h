// What a training pass of cache-guided's scene-wide guide measures (docs/radiance-cache.md,
// "The trained guide"): at each path vertex, the direction its path left in and the
// incident radiance that arrived along it, weighted by 1 / the density it was drawn with,
// so that a directional bin's sum of values estimates the bin's integral of incident
// radiance. The per-width recording (guide_recording_impl.h) fills a sink per training
// tile; the trainer merges the tiles' records in tile order (guide_training.h).
#pragma once

#include <cstdint>
#include <vector>

namespace patina::guiding {

struct GuideRecord {
    float p[3];   // the vertex
    float n[3];   // its shading normal
    float d[3];   // the world direction its path left in (unit)
    float value;  // luminance of the radiance that arrived along d x the cosine to n / the density d was drawn with
};

// A path vertex whose record waits for what its path brings back (guide_recording_impl.h).
struct PendingVertex {
    int32_t path;
    float p[3], n[3], d[3];
    float pdf;          // the density its direction was drawn with (the guide/BRDF mixture's)
    float thr[3];       // the path's throughput after the vertex (BRDF x cosine / pdf, roulette)
    float arrived[3];   // the path's radiance when its next vertex's own emission had been added
};

// One training tile's records, and the bookkeeping of the batch in flight.
struct GuideRecordSink {
    std::vector<GuideRecord> records;
    std::vector<PendingVertex> pending;
    std::vector<int32_t> waiting;        // pending vertices whose next vertex is not reached yet
    std::vector<int32_t> point_of_path;  // per path: its shading point at the current bounce
};

}  // namespace patina::guiding
