#include "render/scene.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/constants.h"

namespace patina {
// Pixel weights for sampling: luminance x sin(theta), each pixel taking the largest
// luminance of its 3 x 3 neighbourhood. The radiance is filtered bilinearly, so a bright
// pixel lights up half of each neighbour too; dilating the weights keeps the pdf high
// wherever that happens (no fireflies next to the sun), and the estimate unbiased.
static std::vector<double> sampling_weights(const Environment& env) {
    const int w = env.width, h = env.height;
    std::vector<double> lum(static_cast<size_t>(w) * h), out(lum.size());
    for (size_t i = 0; i < lum.size(); ++i) lum[i] = std::max(0.0, luminance<double>(env.rgb + 3 * i));
    for (int r = 0; r < h; ++r) {
        const double sin_theta = std::sin(kPiDouble * (r + 0.5) / h);
        for (int c = 0; c < w; ++c) {
            double m = 0;
            for (int dr = -1; dr <= 1; ++dr)
                for (int dc = -1; dc <= 1; ++dc) {
                    const int rr = std::clamp(r + dr, 0, h - 1), cc = (c + dc + w) % w;
                    m = std::max(m, lum[static_cast<size_t>(rr) * w + cc]);
                }
            out[static_cast<size_t>(r) * w + c] = m * sin_theta;
        }
    }
    return out;
}

void orthonormal_frame(const Vec3f& n, Vec3f& t, Vec3f& b) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z), c = n.x * n.y * a;
    t = {1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x};
    b = {c, sign + n.y * n.y * a, -n.y};
}

void prepare_environment(Environment& env) {
    env.cos_rotation = std::cos(env.rotation);
    env.sin_rotation = std::sin(env.rotation);
    if (!env.present || !env.is_map) return;
    const int w = env.width, h = env.height;
    if (w < 1 || h < 1 || env.rgb == nullptr) throw std::invalid_argument("environment map has no pixels");
    const std::vector<double> weight = sampling_weights(env);
    env.texels.assign(env.rgb, env.rgb + 3 * static_cast<size_t>(w) * h);
    env.texels.push_back(0.0f);
    env.row_cdf.assign(h + 1, 0.0f);
    std::vector<float> col_cdf(static_cast<size_t>(h) * (w + 1), 0.0f);
    env.pixel_pdf.assign(static_cast<size_t>(h) * w, 0.0f);
    std::vector<double> row_sum(h, 0.0);
    double total = 0, lum_integral = 0;
    for (int r = 0; r < h; ++r) {
        const double sin_theta = std::sin(kPiDouble * (r + 0.5) / h);
        double acc = 0;
        float* cdf = &col_cdf[static_cast<size_t>(r) * (w + 1)];
        for (int c = 0; c < w; ++c) {
            const size_t i = static_cast<size_t>(r) * w + c;
            acc += weight[i];
            cdf[c + 1] = static_cast<float>(acc);
            lum_integral += std::max(0.0, luminance<double>(env.rgb + 3 * i)) * sin_theta;
        }
        for (int c = 1; c <= w; ++c) cdf[c] = acc > 0 ? static_cast<float>(cdf[c] / acc) : static_cast<float>(c) / w;
        cdf[w] = 1.0f;
        row_sum[r] = acc;
        total += acc;
    }
    lum_integral *= (2 * kPiDouble / w) * (kPiDouble / h);  // the integral of luminance over the sphere
    env.mean_luminance = static_cast<float>(lum_integral / (4 * kPiDouble) * env.intensity);
    double acc = 0;
    for (int r = 0; r < h; ++r) {
        acc += row_sum[r];
        env.row_cdf[r + 1] = total > 0 ? static_cast<float>(acc / total) : static_cast<float>(r + 1) / h;
    }
    env.row_cdf[h] = 1.0f;
    // pdf over (u, v): pixel weight / mean weight, so it integrates to 1 over the unit square
    for (size_t i = 0; i < env.pixel_pdf.size(); ++i)
        env.pixel_pdf[i] = total > 0 ? static_cast<float>(weight[i] * w * h / total) : 1.0f;
    env.col_cdf_pdf.assign(2 * static_cast<size_t>(h) * (w + 1), 0.0f);
    for (int r = 0; r < h; ++r)
        for (int c = 0; c <= w; ++c) {
            const size_t i = static_cast<size_t>(r) * (w + 1) + c;
            env.col_cdf_pdf[2 * i] = col_cdf[i];
            env.col_cdf_pdf[2 * i + 1] = c < w ? env.pixel_pdf[static_cast<size_t>(r) * w + c] : 0.0f;
        }
    // the column search's guide: a bucket per 4 columns (a power of two, so u * buckets and
    // b / buckets are exact in float). Not one per 16: a block of 16 lanes searches until its
    // last lane is done, and samples in dim stretches of a row (wide buckets) kept it at about 6
    // levels of dependent gathers on the studio map; with 4 columns a bucket, about 4.
    int buckets = 1;
    while (buckets < 1024 && buckets * 4 < w) buckets *= 2;
    env.col_buckets = buckets;
    env.col_guide.assign(static_cast<size_t>(h) * (buckets + 1), 0);
    for (int r = 0; r < h; ++r) {
        const float* cdf = &col_cdf[static_cast<size_t>(r) * (w + 1)];
        int32_t* guide = &env.col_guide[static_cast<size_t>(r) * (buckets + 1)];
        int c = 0;  // the last column (below w) whose cdf is <= b / buckets: cdf is non-decreasing
        for (int b = 0; b < buckets; ++b) {
            const float at = static_cast<float>(b) / static_cast<float>(buckets);
            while (c + 1 < w && cdf[c + 1] <= at) ++c;
            guide[b] = c;
        }
        guide[buckets] = w - 1;
    }
}

void prepare_scale(RenderScene& s) {
    Box3 b = s.tree->bounds;
    const SphereSet& spheres = s.tree->spheres;
    if (!spheres.empty()) {  // the triangles' box and the analytic spheres'
        Box3 round;
        sphere_bounds(spheres, round.lo, round.hi);
        for (int k = 0; k < 3; ++k) {
            b.lo[k] = s.triangle_count > 0 ? std::min(b.lo[k], round.lo[k]) : round.lo[k];
            b.hi[k] = s.triangle_count > 0 ? std::max(b.hi[k], round.hi[k]) : round.hi[k];
        }
    }
    float r2 = 0, extent = 0;
    for (int k = 0; k < 3; ++k) {
        r2 += 0.25f * (b.hi[k] - b.lo[k]) * (b.hi[k] - b.lo[k]);
        extent = std::max({extent, std::abs(b.lo[k]), std::abs(b.hi[k])});
    }
    s.scene_radius = s.triangle_count > 0 || !spheres.empty() ? std::max(std::sqrt(r2), 1e-3f) : 1.0f;
    // far enough off a surface for float positions at the scene's largest coordinate
    s.ray_offset = std::max(1e-5f, 2e-5f * std::max(extent, s.scene_radius));
}

void prepare_light_selection(RenderScene& s) {
    // area lights by flux and distance, delta lights by intensity (towards the point, when
    // selecting) and distance, infinite ones (sun, environment) by irradiance
    s.selection.clear();
    const float small2 = 1e-4f * s.scene_radius * s.scene_radius;
    const float* triangle_vertices = s.tree != nullptr ? s.tree->triangles.data() : nullptr;
    for (const Light& l : s.lights)
        s.selection.push_back(
            visit_kind(l, [&](const auto& kind) { return kind.selection(small2, triangle_vertices); }));
    if (s.env.present) {  // a uniform environment of mean luminance Y gives irradiance pi Y
        const double mean = s.env.is_map ? s.env.mean_luminance
                                         : std::max(0.0, luminance<double>(s.env.constant)) * s.env.intensity;
        s.selection.push_back({false, false, static_cast<float>(kPiDouble * mean), {0, 0, 0}, 0});
    }
}

}  // namespace patina
