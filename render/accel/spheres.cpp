#include "render/accel/spheres.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace patina {

void SphereSet::add(const float centre[3], float r, const float frame[9]) {
    for (int a = 0; a < 3; ++a)
        if (!std::isfinite(centre[a])) throw std::invalid_argument("an analytic sphere's centre is not finite");
    if (!(r > 0.0f) || !std::isfinite(r)) throw std::invalid_argument("an analytic sphere needs a finite radius > 0");
    for (int i = 0; i < 3; ++i) {
        const float* e = frame + 3 * i;
        const float len2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
        if (!(std::fabs(len2 - 1.0f) < 1e-4f))
            throw std::invalid_argument("an analytic sphere's frame must have unit axes");
    }
    centre_x.push_back(centre[0]);
    centre_y.push_back(centre[1]);
    centre_z.push_back(centre[2]);
    radius.push_back(r);
    axes.insert(axes.end(), frame, frame + 9);
}

void sphere_bounds(const SphereSet& s, float lo[3], float hi[3]) {
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::numeric_limits<float>::infinity();
        hi[a] = -std::numeric_limits<float>::infinity();
    }
    for (size_t k = 0; k < s.size(); ++k) {
        const float c[3] = {s.centre_x[k], s.centre_y[k], s.centre_z[k]};
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], c[a] - s.radius[k]);
            hi[a] = std::max(hi[a], c[a] + s.radius[k]);
        }
    }
}

}  // namespace patina
