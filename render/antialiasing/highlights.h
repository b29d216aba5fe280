// The adaptive antialiasing's highlight pre-pass (docs/antialiasing.md, "Highlights of point
// lights"): where a point-like light's highlight on a smooth GGX surface (a clear coat, a
// polished conductor or dielectric) is smaller than a pixel, a fixed pattern of rays hits it
// or misses it by luck, and its radiance is hundreds of times the image's. Its place is known
// from the geometry, as the shadow edges' are: the point of a mesh where the shading normal
// is the half-vector of the light and the camera (the mirror direction of the light meets the
// camera). Each such point is found per triangle (and per analytic sphere, where its exact
// normal is the half-vector), checked for visibility from the camera and
// the light, and projected; the lobe's roughness and how fast the normal turns away from the
// half-vector across the film give the spot's size in pixels. A spot smaller than a pixel
// gets a dense grid of rays over its neighbourhood (the pieces below), which the sampler adds
// with their area's weight in place of the pattern's rays there.
#pragma once

#include <vector>

#include "render/scene.h"

namespace patina {

// A highlight's neighbourhood within one pixel: [x0, x1] x [y0, y1] in the pixel's own
// coordinates ((0, 0) its top-left corner, x right, y down), sampled by a grid of
// kAaSpotGrid x kAaSpotGrid rays.
struct AaSpot {
    int pixel;  // index in the image
    float x0, y0, x1, y1;
};

// 8 x 8 rays over a neighbourhood of 4 lobe widths each side: the grid's step is one lobe
// width, where a midpoint rule integrates a GGX spot (1 + r^2 / a^2)^-2 to about 2 %, and
// the neighbourhood holds 94 % of its energy (the rest, spread thin, is left to the pattern).
inline constexpr int kAaSpotGrid = 8;
inline constexpr double kAaSpotWidths = 4;
// A spot whose neighbourhood reaches farther than this (pixels) from its centre is not
// sub-pixel: the corners and the signal see it.
inline constexpr double kAaSpotMaxHalf = 2;

// The pixels the sub-pixel highlights of the scene's point, spot and goniometric lights and
// the sun fall on (camera through its pinhole, as the edges), sorted by pixel, one piece a
// pixel (the bounding box where spots share a pixel). The triangles are searched by `threads`
// threads (the same pieces for any count).
std::vector<AaSpot> find_highlight_spots(const RenderScene& scene, int threads = 1);

}  // namespace patina
