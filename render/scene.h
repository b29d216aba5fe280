// What the renderer reads: geometry with its shading data, materials, lights, the
// environment and the camera. Plain structs with pointers into arrays owned by the
// caller (the Python side keeps them alive), built once per render.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "brdf/table.h"
#include "core/vec3.h"
#include "fit/lobe_kernels.h"
#include "render/accel/bvh.h"
#include "render/accel/kdtree.h"
#include "render/camera/camera.h"
#include "render/lights/grid2.h"

namespace patina {

enum class MaterialKind : int { Lambert = 0, Conductor = 1, Table = 2, Mixture = 3, Emitter = 4, Dielectric = 5 };

struct Material {
    MaterialKind kind = MaterialKind::Lambert;
    float albedo[3] = {0.5f, 0.5f, 0.5f};  // Lambert's reflectance; for the others what the albedo AOV shows
    float alpha_x = 0.1f, alpha_y = 0.1f;  // Conductor: anisotropic GGX roughness (x along the tangent); Dielectric: alpha_x
    float eta[3] = {1, 1, 1}, k[3] = {0, 0, 0};  // Conductor: complex index per channel; Dielectric: eta[0] inside / outside
    const TableView* table = nullptr;      // Table: an RGB table
    MixtureParams mixture;                 // Mixture: a fitted analytic model
    float tint[3] = {1, 1, 1};             // scales Table, Mixture and Conductor values
    bool two_sided = false;
    // A clear coat over any of the above (car paint): a GGX dielectric interface of index
    // coat_eta reflects F; the base is seen through it, dimmed by (1 - F(cos_l)) (1 - F(cos_v))
    // and coloured by coat_tint. Roughness 0 (a smooth coat) is taken as alpha 1e-3.
    bool coat = false;
    float coat_eta = 1.5f, coat_alpha = 1e-3f;
    float coat_tint[3] = {1, 1, 1};
    // Table and Mixture are importance sampled through a proxy: a Lambert lobe picked with
    // probability proxy_diffuse, else GGX of roughness proxy_alpha. The pdf is the proxy's,
    // the value the material's own, so the estimate stays unbiased.
    float proxy_diffuse = 0.5f, proxy_alpha = 0.2f;
    int light = -1;  // Emitter: the quad light whose triangles these are
};

// Lights: delta lights (point, spot, goniometric) sampled at their position; area lights
// (quad, triangles: disks, spheres, emissive meshes) sampled uniformly by area over the very
// triangles the rays hit; the sun, a disc of uniform radiance at infinity; the environment.
enum class LightKind : int { Point = 0, Quad = 1, Environment = 2, Spot = 3, Sun = 4, Triangles = 5, Goniometric = 6 };

struct Light {
    LightKind kind = LightKind::Point;
    float position[3] = {0, 0, 0};  // Point, Spot, Goniometric: position; Quad: centre
    float u[3] = {1, 0, 0}, v[3] = {0, 0, 1};  // Quad: half-edge vectors (corners centre +- u +- v)
    float normal[3] = {0, -1, 0};   // Quad: unit normal, normalize(cross(u, v)); emits on this side
    float area = 4;                 // Quad: 4 |u x v|; Triangles: the total area
    // Point, Spot: intensity (W/sr); Quad, Triangles, Sun: radiance (W/(m^2 sr));
    // Goniometric: the factor (1/sr... per candela) that turns the table's candela into RGB W/sr
    float power[3] = {1, 1, 1};
    bool two_sided = false;
    float direction[3] = {0, -1, 0};  // Spot: the axis it shines along; Sun: towards the sun (unit)
    float cos_inner = 1, cos_outer = 0;  // Spot: full inside cos_inner, smoothly to none at cos_outer
    float cos_sun = 1;                   // Sun: cosine of the disc's angular radius...
    float sun_one_minus_cos = 0;         // ...and 1 - that cosine, computed without cancellation
    float frame_t[3] = {1, 0, 0}, frame_b[3] = {0, 0, 1};  // Sun: a frame around `direction`
    // Triangles: the light's triangles (scene triangle ids) and their area cdf (size + 1 values)
    std::vector<int32_t> triangles;
    std::vector<float> area_cdf;
    // Goniometric: the luminaire's axes in the world (photometric type C: gamma = 0 along
    // -axis_z, C = 0 along axis_x, C = 90 along axis_y) and its candela table over
    // (C, gamma) in radians
    float axis_x[3] = {1, 0, 0}, axis_y[3] = {0, 1, 0}, axis_z[3] = {0, 0, 1};
    Grid2View candela{};
    bool type_b = false;  // Goniometric: photometric type B (beam along axis_z, axis_y up) instead of C
};

// A light of one point (point, spot, goniometric luminaire): its intensity towards a direction,
// not a radiance over an area or a cone.
inline bool is_delta_light(const Light& l) {
    return l.kind == LightKind::Point || l.kind == LightKind::Spot || l.kind == LightKind::Goniometric;
}

// A lat-long environment (Mitsuba 3's convention: u -> phi = 2 pi u, v -> theta = pi v,
// d = (sin phi sin theta, cos theta, -cos phi sin theta), y up) or a constant radiance.
// Importance sampled by luminance x sin(theta), piecewise constant per pixel.
struct Environment {
    bool present = false;
    bool is_map = false;
    float constant[3] = {0, 0, 0};
    int width = 0, height = 0;
    const float* rgb = nullptr;  // height x width x 3, linear radiance
    float intensity = 1;
    float rotation = 0;          // radians about +y: the map is turned by this angle
    float cos_rotation = 1, sin_rotation = 0;
    std::vector<float> texels;   // a copy of rgb with one float of padding (the SIMD gathers load 4 floats per texel)
    std::vector<float> row_cdf;  // height + 1 values, 0 .. 1
    // height rows of width + 1 pairs: (column c's cdf, 0 .. 1; pixel c's pdf as in pixel_pdf,
    // 0 after the last column), so a sample's pdf is in the cache line of its cdf values
    std::vector<float> col_cdf_pdf;
    // Where a row's column search starts and ends: for u in [b, b + 1) / col_buckets, the
    // column is in [col_guide[b], col_guide[b + 1]] of the row (col_guide[b] = the last
    // column whose cdf is <= b / col_buckets), so a sample searches a few cdf values of one
    // or two cache lines instead of the whole row. height rows of col_buckets + 1 values.
    int col_buckets = 1;
    std::vector<int32_t> col_guide;
    std::vector<float> pixel_pdf;  // height x width: pdf over (u, v) in [0,1]^2
    float mean_luminance = 0;
};

// An orthonormal tangent t and bitangent b around unit n (Duff et al. 2017, "Building an
// orthonormal basis, revisited"): continuous everywhere but at n.z = -1's sign switch.
void orthonormal_frame(const Vec3f& n, Vec3f& t, Vec3f& b);

// Builds the sampling distribution of a map environment (no-op for a constant one).
void prepare_environment(Environment& env);

struct RenderScene {
    const KdTree* tree = nullptr;
    const Bvh* bvh = nullptr;  // when set: secondary and shadow rays through it, camera rays through the tree
    const float* vertices = nullptr;     // V x 3 (world space)
    const int32_t* indices = nullptr;    // T x 3, in the tree's triangle order
    const float* normals = nullptr;      // V x 3 unit shading normals
    const float* tangents = nullptr;     // V x 3 unit tangents, or nullptr (a frame from the normal)
    const int32_t* tri_material = nullptr;  // T material indices
    size_t triangle_count = 0;
    std::vector<Material> materials;
    std::vector<Light> lights;           // points and quads
    Environment env;
    Camera camera;
    float scene_radius = 1;              // bounding-sphere radius of the geometry (environment power)
    float ray_offset = 1e-4f;            // secondary-ray origin offset, scaled by the scene's size
    // Light selection, per shading point in proportion to each light's estimated irradiance
    // there (render/lights/selection_impl.h): an area light's flux / (4 pi max(d^2, size^2))
    // (d to its centre), a delta light's intensity towards the point / max(d^2, size^2) (its
    // spot cone or candela table included), an infinite one's (sun, environment) irradiance.
    // Lights first (selection[k] is lights[k]'s), then the environment.
    struct Selection {
        bool local;
        bool delta;       // a point, spot or goniometric light: weighed by its intensity towards the point
        float weight;     // area: flux (W); delta: intensity (W/sr; goniometric: per candela);
                          // infinite: irradiance (W/m^2); all of luminance
        float center[3];
        float size2;      // local: a squared size below which distance does not count
    };
    std::vector<Selection> selection;
};

// Sets scene_radius and ray_offset from the tree's bounds.
void prepare_scale(RenderScene& s);

// Fills `selection` from the lights' and the environment's estimated flux and irradiance.
void prepare_light_selection(RenderScene& s);

}  // namespace patina
