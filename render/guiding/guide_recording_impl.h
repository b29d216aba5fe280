// A training pass's measurements (docs/radiance-cache.md, "The trained guide"), compiled once
// per width with the wavefront integrator that calls these between its stages when the
// scratch has a sink (PathScratch::guide_sink: the guide's training passes only).
//
// Each vertex a path leaves becomes a record of the radiance that arrived back along the
// direction it left in: what the path gathered after the vertex, divided by its throughput
// after the vertex, times the cosine to the vertex's shading normal, divided by the
// direction's density. Only indirect light is recorded --
// what the path gathered after its next vertex's own emission (a light or the environment
// seen directly, which light sampling samples well): the guide learns where the light that
// light sampling cannot find comes from, the scene's lit surfaces. Plain scalar code in
// the paths' order, so the records have the same bits at every width.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/constants.h"
#include "core/simd/target.h"
#include "render/guiding/guide_record.h"
#include "render/integrators/integrator.h"

PATINA_BEGIN_TARGET
namespace guide_recording {
using patina::guiding::GuideRecord;
using patina::guiding::GuideRecordSink;
using patina::guiding::PendingVertex;

inline bool recording(const PathScratch& scratch) { return scratch.guide_sink != nullptr; }

// A batch starts: no vertex pending.
inline void start_records(PathScratch& scratch) {
    scratch.guide_sink->pending.clear();
    scratch.guide_sink->waiting.clear();
}

// After the bounce's emission and environment were added: the vertices that sent the
// bounce's rays note what their paths hold, the next vertex's own emission included.
template <class W>
inline void note_arrivals(const W& wavefront) {
    GuideRecordSink& sink = *wavefront.scratch.guide_sink;
    for (const int32_t v : sink.waiting) {
        PendingVertex& pv = sink.pending[v];
        std::copy(wavefront.results[pv.path].rgb, wavefront.results[pv.path].rgb + 3, pv.arrived);
    }
    sink.waiting.clear();
}

// After BRDF (or guide) sampling: each path that goes on leaves a pending vertex at its
// shading point, with the direction, density and throughput update_paths gave it.
template <class W>
inline void note_vertices(const W& wavefront) {
    PathScratch& scratch = wavefront.scratch;
    GuideRecordSink& sink = *scratch.guide_sink;
    const size_t np = scratch.sorted.size();
    if (sink.point_of_path.size() < scratch.throughput.size() / 3)
        sink.point_of_path.resize(scratch.throughput.size() / 3);
    for (size_t q = 0; q < np; ++q) sink.point_of_path[scratch.point_lanes.path[q]] = static_cast<int32_t>(q);
    for (const int32_t i : scratch.next_active) {
        const size_t q = static_cast<size_t>(sink.point_of_path[i]);
        PendingVertex pv;
        pv.path = i;
        std::copy(scratch.point_lanes.position.data() + 3 * q, scratch.point_lanes.position.data() + 3 * q + 3, pv.p);
        std::copy(scratch.point_lanes.normal.data() + 3 * q, scratch.point_lanes.normal.data() + 3 * q + 3, pv.n);
        std::copy(scratch.dir.data() + 3 * i, scratch.dir.data() + 3 * i + 3, pv.d);
        pv.pdf = scratch.prev_pdf[i];
        std::copy(scratch.throughput.data() + 3 * i, scratch.throughput.data() + 3 * i + 3, pv.thr);
        std::fill(pv.arrived, pv.arrived + 3, 0.0f);
        sink.waiting.push_back(static_cast<int32_t>(sink.pending.size()));
        sink.pending.push_back(pv);
    }
}

// The batch's paths have ended: each pending vertex's record from what its path gathered
// after it arrived (none where nothing came back: a zero adds nothing to any bin).
template <class W>
inline void finish_records(const W& wavefront) {
    GuideRecordSink& sink = *wavefront.scratch.guide_sink;
    for (const PendingVertex& pv : sink.pending) {
        const float* rgb = wavefront.results[pv.path].rgb;
        float li[3];
        for (int c = 0; c < 3; ++c) {
            const float gathered = std::max(0.0f, rgb[c] - pv.arrived[c]);
            li[c] = pv.thr[c] > 0.0f ? gathered / pv.thr[c] : 0.0f;
        }
        const float cosine = std::abs(pv.d[0] * pv.n[0] + pv.d[1] * pv.n[1] + pv.d[2] * pv.n[2]);
        const float value = luminance(li) * cosine / pv.pdf;
        if (!(value > 0.0f) || !std::isfinite(value)) continue;
        GuideRecord r;
        std::copy(pv.p, pv.p + 3, r.p);
        std::copy(pv.n, pv.n + 3, r.n);
        std::copy(pv.d, pv.d + 3, r.d);
        r.value = value;
        sink.records.push_back(r);
    }
    sink.pending.clear();
    sink.waiting.clear();
}

}  // namespace guide_recording
PATINA_END_TARGET
