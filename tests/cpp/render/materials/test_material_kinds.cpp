// The questions the cache, the guide and adaptive antialiasing ask of a material
// (render/materials/material.h), answered by each kind through visit_kind: the lobe the
// radiance cache would integrate, the sharpest highlight, glass, and whether sampling picks.
#include <gtest/gtest.h>

#include <cmath>
#include <type_traits>

#include "render/materials/material.h"

using namespace patina;

namespace {

template <class Kind>
Material material(const Kind& kind) {
    Material m;
    m.model = kind;
    return m;
}

Conductor conductor(float alpha_x, float alpha_y) {
    Conductor c;
    c.alpha_x = alpha_x;
    c.alpha_y = alpha_y;
    return c;
}

}  // namespace

TEST(MaterialKinds, TheCacheIntegratesReflectionLobesOnly) {
    EXPECT_TRUE(std::isinf(*reflection_alpha(material(Lambert{}))));    // diffuse: any texel
    EXPECT_EQ(*reflection_alpha(material(conductor(0.3f, 0.1f))), 0.1f);  // its narrower axis
    Mixture fit;
    fit.proxy.alpha = 0.25f;
    EXPECT_EQ(*reflection_alpha(material(fit)), 0.25f);  // measured and fitted: their proxy
    RglMaterial rgl;
    rgl.lobe_alpha = 0.15f;
    EXPECT_EQ(*reflection_alpha(material(rgl)), 0.15f);  // an RGL file: the lobe fitted to its peak
    EXPECT_FALSE(reflection_alpha(material(Dielectric{})));
    EXPECT_FALSE(reflection_alpha(material(Emitter{})));
}

TEST(MaterialKinds, TheSharpestHighlightIsTheNarrowestSpecularLobeCoatIncluded) {
    EXPECT_EQ(highlight_alpha(material(conductor(0.3f, 0.1f))), 0.3f);  // its wider axis
    Dielectric glass;
    glass.alpha = 0.05f;
    EXPECT_EQ(highlight_alpha(material(glass)), 0.05f);
    EXPECT_TRUE(std::isinf(highlight_alpha(material(Lambert{}))));
    EXPECT_TRUE(std::isinf(highlight_alpha(material(TableMaterial{}))));
    EXPECT_TRUE(std::isinf(highlight_alpha(material(RglMaterial{}))));
    Material coated = material(conductor(0.3f, 0.3f));
    coated.coat = ClearCoat{};
    coated.coat->alpha = 0.02f;
    EXPECT_EQ(highlight_alpha(coated), 0.02f);
}

TEST(MaterialKinds, GlassTransmitsAndSamplingPicksWhereThereIsAChoice) {
    EXPECT_TRUE(transmits(material(Dielectric{})));
    EXPECT_FALSE(transmits(material(Lambert{})));
    EXPECT_TRUE(sampling_picks(material(Dielectric{})));   // reflection or transmission
    EXPECT_TRUE(sampling_picks(material(TableMaterial{})));  // the proxy's lobe
    EXPECT_FALSE(sampling_picks(material(conductor(0.2f, 0.2f))));
    EXPECT_FALSE(sampling_picks(material(RglMaterial{})));  // its warps take (u1, u2) alone
    Material coated = material(Lambert{});
    coated.coat = ClearCoat{};
    EXPECT_TRUE(sampling_picks(coated));  // the coat or the base
}

TEST(MaterialKinds, VisitKindHandsOverTheKindHeld) {
    const Material m = material(Emitter{3});
    EXPECT_TRUE(m.is<Emitter>());
    EXPECT_EQ(visit_kind(m, [](const auto& kind) {
                  if constexpr (std::is_same_v<std::decay_t<decltype(kind)>, Emitter>) return kind.light;
                  else return -1;
              }),
              3);
}
