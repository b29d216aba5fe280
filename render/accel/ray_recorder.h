// Records the rays that reach the tracing kernels, so that the rays of a real render (camera,
// bounce and shadow rays, in the batches and order the integrator traced them) can be saved
// and replayed in the benchmark. Off unless started; while off, a kernel pays one relaxed
// atomic load per batch.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/accel/trace_kernels.h"

namespace patina {

struct RecordedRays {
    std::vector<float> origins, directions;  // n x 3
    std::vector<float> tmin, tmax;           // n
    std::vector<uint8_t> any_hit;            // n: 1 for an occlusion (shadow) query
    bool truncated = false;                  // the limit was reached: later rays were dropped
};

// Starts recording (discarding anything recorded before), at most `limit` rays.
void start_ray_recording(size_t limit);
// Stops recording and hands over what was recorded.
RecordedRays stop_ray_recording();
bool ray_recording_on();
// Called by the kernels with each batch they trace (any thread).
void record_rays(const RayBatch& rays, size_t begin, size_t end, bool any_hit);

}  // namespace patina
