// A light: one of the kinds below, each a type in its own file with its fields. Delta lights
// (point, spot, goniometric) are sampled at their position; area lights (quad, triangles:
// disks, spheres, emissive meshes) uniformly by area over the very triangles the rays hit;
// the sun is a disc of uniform radiance at infinity. The environment is not a Light (see
// render/scene.h's Environment). Sampling (render/lights/sampling_impl.h), the delta lights'
// intensity (render/lights/delta_intensity_impl.h), the selection and the queries below go
// through visit_kind (render/one_of_kinds.h), so a new kind is its file, its place in the
// list of kinds and its sampling.
#pragma once

#include <type_traits>

#include "render/lights/goniometric_light.h"
#include "render/lights/point_light.h"
#include "render/lights/quad_light.h"
#include "render/lights/spot_light.h"
#include "render/lights/sun_light.h"
#include "render/lights/triangle_light.h"
#include "render/one_of_kinds.h"

namespace patina {

struct Light : OneOfKinds<PointLight, QuadLight, SpotLight, SunLight, TriangleLight, GoniometricLight> {};

// A light of one point (point, spot, goniometric luminaire): its intensity towards a direction,
// not a radiance over an area or a cone.
inline bool is_delta_light(const Light& l) {
    return visit_kind(l, [](const auto& kind) { return kind.is_delta; });
}

// A delta light's position (nullptr for the others).
inline const float* delta_position(const Light& l) {
    return visit_kind(l, [](const auto& kind) -> const float* {
        if constexpr (std::decay_t<decltype(kind)>::is_delta) return kind.position;
        else return nullptr;
    });
}

// The surface of an area light (a quad or triangles: what an emitter material names).
inline const AreaLight& area_of(const Light& l) {
    if (const QuadLight* quad = std::get_if<QuadLight>(&l.model)) return *quad;
    return *std::get_if<TriangleLight>(&l.model);
}

inline bool is_area_light(const Light& l) { return l.is<QuadLight>() || l.is<TriangleLight>(); }

}  // namespace patina
