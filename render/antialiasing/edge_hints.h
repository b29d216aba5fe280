// The adaptive antialiasing's geometric pre-pass (thesis chapter 3: "first the block is
// rasterised on the GPU", which finds the pixels with geometric discontinuities without
// tracing rays): the scene's feature edges projected onto the image, and for every pixel
// the zones of the adaptive pattern they cross (docs/antialiasing.md).
//
// A feature edge is a triangle edge where the image can step: a boundary (one triangle; or
// more than two), a change of material, a crease (shading normals that differ across it by
// more than the threshold's contrast), or a silhouette (one triangle faces the camera, the
// other does not). A wire thinner than a pixel, which falls between the corner rays of
// level 1, is found this way. Hidden edges are kept here; the sampler drops a pixel's hint
// when all four of its corners see a surface nearer than the nearest edge crossing it.
//
// Shadow edges: for each point-like light (point, spot, goniometric) and the sun, the edges
// that are silhouettes seen from the light (or boundaries) are cast along the light's rays
// onto what lies behind them (rays traced through the tree at width 1, so every SIMD width
// sees the same), and the cast shadow is projected like a feature edge: a wire's shadow
// thinner than the gaps between the corner rays is found too. Area lights and environments
// cast soft shadows, left to the signal. The same pre-pass places the sub-pixel highlights
// of point-like lights (render/antialiasing/highlights.h) in `spots`.
#pragma once

#include <cstdint>
#include <vector>

#include "render/antialiasing/highlights.h"
#include "render/scene.h"

namespace patina {

struct AaEdgeHints {
    int width = 0, height = 0;
    // per pixel, bit j = zone j (u in [0.2 j, 0.2 (j + 1)]) crossed by a feature edge, in the
    // canonical frame of each orientation: [0] the pattern as it is (u = x), [1] turned 90
    // degrees counter-clockwise (u = 1 - y); 0: no edge
    std::vector<uint8_t> zones[2];
    std::vector<float> nearest;  // per pixel: the distance from the camera of the nearest edge crossing it
    // the sub-pixel highlights' pieces (render/antialiasing/highlights.h), sorted by pixel, one a pixel
    std::vector<AaSpot> spots;
    bool empty() const { return width == 0; }
    void resize(int w, int h);  // w x h pixels, no edge
};

// The scene's feature edges (crease and contrast as in aa_contrast: (1 - n1 . n2) / 2 above
// `threshold`) projected through the camera's pinhole (the centre of a thin lens).
// The edges are walked by `threads` threads (the same hints for any count).
AaEdgeHints project_feature_edges(const RenderScene& scene, float threshold, int threads = 1);

// The pixel crossings of one film-space segment (pixels, x right, y down) into `hints`; z0,
// z1: the camera-space depths (along the view axis) of its ends, tan_x, tan_y the camera's
// half-angle tangents, for the distances; crossings: the caller's scratch, kept from edge to
// edge (not a vector made and freed for each edge). Exposed for the tests.
void rasterise_edge(AaEdgeHints& hints, float x0, float y0, float x1, float y1, float z0, float z1, float tan_x,
                    float tan_y, std::vector<double>& crossings);

}  // namespace patina
