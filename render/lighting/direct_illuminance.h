// Exact direct illuminance from point, spot and goniometric luminaires (issue 32): at each
// sensor the finite sum over the luminaires of I(towards the sensor) x the sensor's response
// / d^2, each term kept only if one shadow ray from the sensor to the luminaire is clear. No
// sampling: the same numbers on every run, at every SIMD width and thread count.
//
// Sensors go N at a time (direct_illuminance_impl.h, compiled per width by
// direct_illuminance_w{1,4,8,16}.cpp): per luminaire the N directions, candela, responses and
// one packet of N shadow rays through the BVH (bvh_packet_occlusion.h). Neighbouring sensors
// of a grid see a luminaire along nearly the same direction, so their shadow rays form
// coherent packets.
#pragma once

#include <cstddef>

#include "render/accel/bvh.h"
#include "render/lighting/direct_source.h"
#include "render/lighting/illuminance_sensors.h"

namespace patina {

// What the sum reads besides the sensors.
struct DirectLighting {
    const DirectSource* sources = nullptr;
    size_t count = 0;
    const Bvh* occluders = nullptr;  // null: nothing casts a shadow
    // shadow rays start this far from the sensor (the renderer's ray offset) and stop
    // kShadowShorten of the distance short of the luminaire
    float ray_offset = 1e-4f;
};

constexpr float kShadowShorten = 1e-4f;

// Sensors [begin, end): lux[i] the sum at sensor i; per_source (null, or count x sensors.count,
// row k the luminaire k's lux) each term.
struct DirectIlluminanceKernels {
    int width;
    void (*sum)(const DirectLighting& lighting, const IlluminanceSensors& sensors, float* lux, float* per_source,
                size_t begin, size_t end);
};

const DirectIlluminanceKernels& direct_illuminance_kernels_w1();
const DirectIlluminanceKernels& direct_illuminance_kernels_w4();
const DirectIlluminanceKernels& direct_illuminance_kernels_w8();
const DirectIlluminanceKernels& direct_illuminance_kernels_w16();
const DirectIlluminanceKernels& direct_illuminance_kernels_for(int width);  // 0: the CPU's widest

// Every sensor, split over `threads` (0: every core) at `width` (0: the CPU's widest).
void direct_illuminance(const DirectLighting& lighting, const IlluminanceSensors& sensors, float* lux,
                        float* per_source, int width, int threads);

}  // namespace patina
