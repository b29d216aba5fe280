// The silhouettes of the analytic spheres (render/accel/spheres.h) for the adaptive
// antialiasing's edge hints (render/antialiasing/edge_hints.h): a tessellated sphere's silhouette is found
// among its triangle edges (one triangle facing the camera, its neighbour not); an analytic
// sphere has no edges, so its contour seen from the camera's pinhole is given as a polygon
// here: the circle where the view rays graze the sphere (centre c - (r^2 / D^2) (c - eye),
// radius r sqrt(1 - r^2 / D^2), D = |c - eye|), circumscribed so that no part of the true
// contour lies outside it.
#pragma once

#include <functional>

#include "render/accel/spheres.h"

namespace patina {

inline constexpr int kSilhouettePieces = 256;  // a 256-gon: 0.008 % of the radius off the circle

// piece(a, b) for each piece of each sphere's silhouette seen from `eye` (world space); none
// for a sphere the eye is inside of.
void for_each_silhouette_piece(const SphereSet& spheres, const float eye[3],
                               const std::function<void(const double* a, const double* b)>& piece);

}  // namespace patina
