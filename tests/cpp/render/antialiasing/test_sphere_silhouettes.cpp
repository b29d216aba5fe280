// The analytic spheres' silhouettes for the edge hints: a closed polygon of
// kSilhouettePieces pieces whose corners see the sphere's rim (the line from the eye through
// a corner passes the centre at between r and r / cos(pi / pieces)), nothing from inside.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "render/antialiasing/sphere_silhouettes.h"

using namespace patina;

TEST(AaSphereSilhouettes, CornersGrazeTheSphereAndThePolygonCloses) {
    SphereSet s;
    const float frame[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const float c0[3] = {0.3f, -0.2f, 0.1f}, c1[3] = {4, 2, -30}, c2[3] = {0, 0, 5};
    s.add(c0, 1.0f, frame);
    s.add(c1, 0.25f, frame);
    s.add(c2, 2.0f, frame);  // the eye is inside this one: no silhouette
    const float eye[3] = {0.5f, 0.4f, 4.5f};
    std::vector<std::vector<double>> corners;
    int pieces = 0;
    double last[3] = {0, 0, 0};
    for_each_silhouette_piece(s, eye, [&](const double* a, const double* b) {
        if (pieces % kSilhouettePieces != 0) {
            for (int e = 0; e < 3; ++e) EXPECT_EQ(a[e], last[e]) << "piece " << pieces;  // end to end
        }
        for (int e = 0; e < 3; ++e) last[e] = b[e];
        corners.push_back({a[0], a[1], a[2], double(pieces / kSilhouettePieces)});
        ++pieces;
    });
    ASSERT_EQ(pieces, 2 * kSilhouettePieces);
    const double slack = 1 / std::cos(3.14159265358979 / kSilhouettePieces);
    for (const auto& p : corners) {
        const int k = static_cast<int>(p[3]);
        const double c[3] = {s.centre_x[k], s.centre_y[k], s.centre_z[k]}, r = s.radius[k];
        double d[3], w[3], dd = 0, along = 0, w2 = 0;
        for (int e = 0; e < 3; ++e) {
            d[e] = p[e] - eye[e];
            w[e] = c[e] - eye[e];
            dd += d[e] * d[e];
        }
        for (int e = 0; e < 3; ++e) along += w[e] * d[e] / std::sqrt(dd);
        for (int e = 0; e < 3; ++e) w2 += w[e] * w[e];
        const double miss = std::sqrt(w2 - along * along);  // the line's distance from the centre
        EXPECT_GE(miss, r * (1 - 1e-9));
        EXPECT_LE(miss, r * slack * (1 + 1e-9));
    }
}
