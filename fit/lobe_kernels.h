// Batch kernels over the analytic lobes (microfacet.h), one copy per SIMD width
// (lobe_kernels_w1.cpp, lobe_kernels_w4.cpp with -msse4.1, lobe_kernels_w8.cpp with
// -mavx2 -mfma), chosen at run time like the table evaluator's. Arrays are (n, 3) rows of local directions.
#pragma once

#include <cstddef>

namespace patina {

// The specular lobes a mixture can hold (all lobes of one mixture are of one kind).
enum class LobeKind : int { GGX = 0, Beckmann = 1, BlinnPhong = 2, Ward = 3, AshikhminShirley = 4, Lafortune = 5 };
constexpr int kMaxLobes = 3;

// A Lambert base (RGB albedo rho) under 1 to kMaxLobes specular lobes, each with a shape
// (GGX / Beckmann / Ward roughness alpha, Blinn-Phong / Ashikhmin-Shirley / Lafortune
// exponent), per channel or shared, and an RGB weight (Schlick f0; Ward's specular albedo,
// as Ward has no Fresnel term; Lafortune's w in w (n + 2) / (2 pi) (Cx xi xo + Cy yi yo +
// Cz zi zo)^n, the Phong normalisation): the shared-shape colour model.
// Ward and Ashikhmin-Shirley are anisotropic about the local x axis (the tangent): shape is
// alpha_x / nu, shape_y alpha_y / nv; an isotropic lobe has shape_y equal to shape.
struct MixtureParams {
    float rho[3];
    LobeKind kind = LobeKind::GGX;
    int lobes = 1;
    float shape[kMaxLobes][3] = {};    // per channel (equal in the shared-shape fit)
    float shape_y[kMaxLobes][3] = {};  // Ward, Ashikhmin-Shirley: along y (= shape when isotropic)
    float weight[kMaxLobes][3] = {};
    float lafortune_c[kMaxLobes][3] = {};  // Lafortune: Cx, Cy, Cz of each lobe, shared by the channels
    // Optional clear coat: a smooth-to-rough dielectric layer (GGX of roughness coat_alpha,
    // exact Fresnel of index coat_eta) over the base, which is dimmed by (1 - F(cos_i)) (1 - F(cos_o)).
    bool coat = false;
    float coat_alpha = 0.05f;
    float coat_eta = 1.5f;
};

struct LobeKernels {
    int width;
    // out[i] = the mixture at (wi[i], wo[i]), (n, 3)
    void (*eval_mixture)(const MixtureParams& p, const float* wi, const float* wo, float* out, size_t n);
    // wo[i] sampled from a lobe (GGX, Beckmann, Blinn-Phong: D(h) cos(theta_h); Ward: its own
    // scheme, isotropic; Lafortune: the Phong lobe Cx = Cy = -1, Cz = 1 of exponent shape) of the
    // given shape, given wi and two uniforms; pdf[i] its density
    void (*sample_lobe)(LobeKind kind, float shape, const float* wi, const float* u1, const float* u2, float* wo,
                        float* pdf, size_t n);
    // cosine-weighted wo from two uniforms; pdf[i] = cos / pi
    void (*sample_lambert)(const float* u1, const float* u2, float* wo, float* pdf, size_t n);
    // wo[i] from Ward's sampling of the (anisotropic) lobe ax, ay; pdf[i] its density
    void (*sample_ward)(float ax, float ay, const float* wi, const float* u1, const float* u2, float* wo, float* pdf,
                        size_t n);
    // sum over rows and channels of ((model - measured) weight)^2, or with log_space of
    // (log(1 + model weight) - log(1 + measured weight))^2 (the losses of fit/loss.h)
    double (*loss_mixture)(const MixtureParams& p, const float* wi, const float* wo, const float* measured,
                           const float* weight, size_t n, bool log_space);
};

const LobeKernels& lobe_kernels_w1();
const LobeKernels& lobe_kernels_w4();
const LobeKernels& lobe_kernels_w8();
const LobeKernels& lobe_kernels_w16();
const LobeKernels& lobe_kernels_for(int width);  // 0 = default; throws std::invalid_argument

}  // namespace patina
