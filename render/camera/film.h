// The image being rendered: per-pixel sums of weighted samples (radiance and AOVs) and
// their weights. Tiles own disjoint pixels, so a tile's sampler adds without locks.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include "render/integrators/integrator.h"

namespace patina {

// Weighted samples of one pixel summed apart, then added to the film in one write (a
// sampler that gives a pixel several samples with their filter weights: the adaptive
// antialiasing's pattern), the same sums Film::add would make.
struct FilmSum {
    double rgb[3] = {0, 0, 0}, albedo[3] = {0, 0, 0}, normal[3] = {0, 0, 0};
    double lux = 0, depth = 0, weight = 0, depth_weight = 0;
    // inline: the adaptive sampler adds 4 to 28 samples a pixel (a call each through the
    // shared library's PLT cost about 5 ns a camera ray on the converging lines)
    void add(const PathResult& r, float w) {
        for (int k = 0; k < 3; ++k) {
            rgb[k] += w * r.rgb[k];
            albedo[k] += w * r.albedo[k];
            normal[k] += w * r.normal[k];
        }
        lux += w * r.illuminance;
        if (std::isfinite(r.depth)) {
            depth += w * r.depth;
            depth_weight += w;
        }
        weight += w;
    }
};

class Film {
public:
    Film(int width, int height);
    int width() const { return m_width; }
    int height() const { return m_height; }
    // Adds one sample's result to a pixel with a filter weight.
    void add(int pixel, const PathResult& r, float weight) {
        double* p = &m_sums[kChannels * static_cast<size_t>(pixel)];
        for (int k = 0; k < 3; ++k) {
            p[kRgb + k] += weight * r.rgb[k];
            p[kAlbedo + k] += weight * r.albedo[k];
            p[kNormal + k] += weight * r.normal[k];
        }
        p[kLux] += weight * r.illuminance;
        if (std::isfinite(r.depth)) {
            p[kDepth] += weight * r.depth;
            p[kDepthWeight] += weight;
        }
        p[kWeight] += weight;
    }
    void add(int pixel, const FilmSum& s) {
        double* p = &m_sums[kChannels * static_cast<size_t>(pixel)];
        for (int k = 0; k < 3; ++k) {
            p[kRgb + k] += s.rgb[k];
            p[kAlbedo + k] += s.albedo[k];
            p[kNormal + k] += s.normal[k];
        }
        p[kLux] += s.lux;
        p[kDepth] += s.depth;
        p[kDepthWeight] += s.depth_weight;
        p[kWeight] += s.weight;
    }
    // The pixel's sums brought towards the core ahead of an add (its first and last cache line)
    void prefetch(int pixel) const {
        const double* p = &m_sums[kChannels * static_cast<size_t>(pixel)];
        __builtin_prefetch(p, 1);
        __builtin_prefetch(p + kChannels - 1, 1);
    }
    // Each pixel the weighted mean of its samples (H x W x 3 etc.); samples: the weight sum.
    void resolve(float* rgb, float* albedo, float* normal, float* depth, float* lux, float* samples) const;

    // The raw sums of the pixels [x0, x1) x [y0, y1), kChannels doubles a pixel, row by row:
    // a tile's accumulation handed to another process, which continues adding to it (a
    // distributed render, render_job.h), and taken back.
    static constexpr int kChannels = 13;  // rgb 3, albedo 3, normal 3, lux, depth, weight, depth weight
    void read(int x0, int y0, int x1, int y1, double* out) const;
    void write(int x0, int y0, int x1, int y1, const double* in);

private:
    // a pixel's sums side by side (read()'s order): one or two cache lines an add, not seven
    static constexpr int kRgb = 0, kAlbedo = 3, kNormal = 6, kLux = 9, kDepth = 10, kWeight = 11, kDepthWeight = 12;
    int m_width, m_height;
    std::vector<double> m_sums;  // kChannels a pixel
};

}  // namespace patina
