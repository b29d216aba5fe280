#include "render/antialiasing/sphere_silhouettes.h"

#include <cmath>

namespace patina {

void for_each_silhouette_piece(const SphereSet& spheres, const float eye[3],
                               const std::function<void(const double* a, const double* b)>& piece) {
    constexpr double kPi = 3.14159265358979323846;
    for (size_t k = 0; k < spheres.size(); ++k) {
        const double c[3] = {spheres.centre_x[k], spheres.centre_y[k], spheres.centre_z[k]}, r = spheres.radius[k];
        const double d[3] = {c[0] - eye[0], c[1] - eye[1], c[2] - eye[2]};
        const double d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        if (!(d2 > r * r)) continue;
        const double shrink = r * r / d2, len = std::sqrt(d2);
        const double m[3] = {c[0] - shrink * d[0], c[1] - shrink * d[1], c[2] - shrink * d[2]};
        const double rho = r * std::sqrt(1 - shrink) / std::cos(kPi / kSilhouettePieces);
        // a frame (u, v) across the view direction w
        const double w[3] = {d[0] / len, d[1] / len, d[2] / len};
        const double sign = std::copysign(1.0, w[2]), a = -1 / (sign + w[2]), b = w[0] * w[1] * a;
        const double u[3] = {1 + sign * w[0] * w[0] * a, sign * b, -sign * w[0]};
        const double v[3] = {b, sign + w[1] * w[1] * a, -w[1]};
        const auto at = [&](int i, double* p) {
            const double phi = 2 * kPi * i / kSilhouettePieces;
            for (int e = 0; e < 3; ++e) p[e] = m[e] + rho * (std::cos(phi) * u[e] + std::sin(phi) * v[e]);
        };
        double p0[3], p1[3];
        at(0, p0);
        for (int i = 1; i <= kSilhouettePieces; ++i) {
            at(i, p1);
            piece(p0, p1);
            for (int e = 0; e < 3; ++e) p0[e] = p1[e];
        }
    }
}

}  // namespace patina
