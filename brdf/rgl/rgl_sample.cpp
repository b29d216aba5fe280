// Scalar code: the warps' marginal and conditional searches per sample (rgl_warp.Interpolant2D.sample
// is the double-precision reference).
#include "brdf/rgl/rgl_sample.h"

#include <algorithm>
#include <cmath>

#include "brdf/rgl/rgl_eval.h"

namespace patina {
namespace {

// The index i in [0, size - 2] with below(i) true and below(i + 1) false, below monotone
// (clamped at both ends).
template <class Below>
int find_interval(int size, Below below) {
    int first = 1, left = size - 2;
    while (left > 0) {
        const int half = left >> 1, middle = first + half;
        if (below(middle)) {
            first = middle + 1;
            left -= half + 1;
        } else {
            left = half;
        }
    }
    return std::clamp(first - 1, 0, size - 2);
}

// t in [0, 1] with integral_0^t ((1 - s) a + s b) ds = u: the inverse CDF of a linear density.
float solve_linear_density(float a, float b, float u) {
    if (std::abs(a - b) < 1e-4f * (a + b)) return std::clamp(2.0f * u / (a + b), 0.0f, 1.0f);
    const float root = (a - std::sqrt(std::max(a * a - 2.0f * u * (a - b), 0.0f))) / (a - b);
    return std::clamp(root, 0.0f, 1.0f);
}

struct WarpedPoint {
    float x, y, density;
};

// The warp applied to the uniform point (ux, uy): the row by the marginal CDF, the column by
// the row's conditional CDF (blended between the point's two rows), each inverted within
// its cell where the density is linear.
WarpedPoint warp_sample(const RglWarpView& w, const RglParams<1>& params, float ux, float uy) {
    const int cells = w.height * w.width;
    const auto blend = [&](const float* table, int stride, int index) {
        return rgl_blend<1>(table, stride, params, index);
    };
    const int row = find_interval(w.height, [&](int k) { return blend(w.marginal, w.height, k) < uy; });
    uy -= blend(w.marginal, w.height, row);
    const int start = row * w.width;
    const float r0 = blend(w.conditional, cells, start + w.width - 1);
    const float r1 = blend(w.conditional, cells, start + 2 * w.width - 1);
    const float fy = solve_linear_density(r0, r1, uy);
    ux *= (1.0f - fy) * r0 + fy * r1;
    const auto conditional_at = [&](int k) {
        return (1.0f - fy) * blend(w.conditional, cells, start + k) + fy * blend(w.conditional, cells, start + w.width + k);
    };
    const int col = find_interval(w.width, [&](int k) { return conditional_at(k) < ux; });
    ux -= conditional_at(col);
    const int node = start + col;
    const float c0 = (1.0f - fy) * blend(w.data, cells, node) + fy * blend(w.data, cells, node + w.width);
    const float c1 = (1.0f - fy) * blend(w.data, cells, node + 1) + fy * blend(w.data, cells, node + w.width + 1);
    const float fx = solve_linear_density(c0, c1, ux);
    const float scale = static_cast<float>((w.width - 1) * (w.height - 1));
    return {(col + fx) / (w.width - 1), (row + fy) / (w.height - 1), ((1.0f - fx) * c0 + fx * c1) * scale};
}

}  // namespace

RglSample rgl_sample(const RglView& v, const Vec3f& wi_in, float u1, float u2) {
    RglSample out{{0.0f, 0.0f, 1.0f}, 0.0f};
    if (!(wi_in.z > 0.0f)) return out;
    Vec3f wi = wi_in, unused = wi_in;
    rgl_detail::fold<1>(v, wi, unused);
    const float theta_i = rgl_detail::elevation<1>(wi), phi_i = fast_atan2(wi.y, wi.x);
    RglHints hints;
    const RglParams<1> params = rgl_params<1>(v, phi_i, theta_i, true, hints);
    const float lo = 1e-7f, hi = 1.0f - 1e-7f;
    const WarpedPoint s = warp_sample(v.luminance, params, std::clamp(u1, lo, hi), std::clamp(u2, lo, hi));
    const WarpedPoint u_m = warp_sample(v.vndf, params, s.x, s.y);
    const float theta_m = u_m.x * u_m.x * kHalfPi;
    const float phi_m = (2.0f * u_m.y - 1.0f) * kPi + (v.isotropic ? phi_i : 0.0f);
    const float sin_m = std::sin(theta_m);
    const Vec3f m{sin_m * std::cos(phi_m), sin_m * std::sin(phi_m), std::cos(theta_m)};
    const float cos_im = wi.x * m.x + wi.y * m.y + wi.z * m.z;
    Vec3f wo{2.0f * cos_im * m.x - wi.x, 2.0f * cos_im * m.y - wi.y, 2.0f * cos_im * m.z - wi.z};
    if (!(wo.z > 0.0f) || !(cos_im > 0.0f)) return out;
    // unfold: the mirror is its own inverse
    Vec3f wi_again = wi_in;
    rgl_detail::fold<1>(v, wi_again, wo);
    const float jacobian =
        std::max(static_cast<float>(2.0 * kPiDouble * kPiDouble) * u_m.x * sin_m, 1e-6f) * 4.0f * cos_im;
    out.wo = wo;
    out.pdf = s.density * u_m.density / jacobian;
    return out;
}

}  // namespace patina
