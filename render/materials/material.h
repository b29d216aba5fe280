// A material: one of the kinds below (each a type in its own file with its fields and its
// eval / pdf / sample), its albedo for the AOV, whether it is two-sided, and an optional
// clear coat over it. Every operation on a material (render/materials/material_impl.h, the
// cache's and antialiasing's queries below) goes through visit_kind (render/one_of_kinds.h),
// so a new kind is its file and its place in the list of kinds.
#pragma once

#include <algorithm>
#include <optional>

#include "render/materials/clear_coat.h"
#include "render/materials/conductor.h"
#include "render/materials/dielectric.h"
#include "render/materials/emitter.h"
#include "render/materials/lambert.h"
#include "render/materials/mixture.h"
#include "render/materials/rgl_material.h"
#include "render/materials/table_material.h"
#include "render/one_of_kinds.h"

namespace patina {

struct Material : OneOfKinds<Lambert, Conductor, TableMaterial, Mixture, Emitter, Dielectric, RglMaterial> {
    float albedo[3] = {0.5f, 0.5f, 0.5f};  // what the albedo AOV shows; weighs the coat's pick
    bool two_sided = false;
    std::optional<ClearCoat> coat;
};

// Whether sampling reads the pick uniform (to choose the coat, a lobe, or reflection against
// transmission); the others sample from (u1, u2) alone.
inline bool sampling_picks(const Material& m) {
    return m.coat || visit_kind(m, [](const auto& kind) { return kind.picks_lobe; });
}

// Glass: it refracts, has no back face to cull, and its points carry a relative index.
inline bool transmits(const Material& m) {
    return visit_kind(m, [](const auto& kind) { return kind.transmits; });
}

// The roughness of the narrowest reflection lobe the radiance cache would integrate
// (infinite for a diffuse one), none where it has nothing to integrate (glass, an emitter).
inline std::optional<float> reflection_alpha(const Material& m) {
    return visit_kind(m, [](const auto& kind) { return kind.reflection_alpha(); });
}

// The GGX roughness of its sharpest specular lobe (clear coat, conductor, dielectric), or
// infinity for none (Lambert; measured tables, RGL files and fitted mixtures have no analytic lobe to
// place): adaptive antialiasing looks for the highlights small lights make
// (render/antialiasing/highlights.cpp).
inline float highlight_alpha(const Material& m) {
    const float base = visit_kind(m, [](const auto& kind) { return kind.highlight_alpha(); });
    return m.coat ? std::min(base, m.coat->alpha) : base;
}

}  // namespace patina
