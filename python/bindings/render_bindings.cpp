// patina._core.RenderScene: the preview renderer's scene (RenderJob, its options and results:
// render_job_bindings.cpp), and the kernels' own entry points (sensor illuminance, sample
// points, Grid2). The Python side (python/patina/render/prepare.py) checks the scene file,
// computes what follows from it (light geometry, sampling proxies) and builds these; here
// values are only converted and checked, with std::invalid_argument (ValueError) naming the
// material, light or key.
#include <nanobind/stl/string.h>
#include <nanobind/stl/unique_ptr.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <initializer_list>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bindings.h"
#include "record.h"
#include "core/parallel.h"
#include "render/integrators/integrator.h"
#include "render/lights/grid2.h"
#include "render/render_options.h"
#include "render/samplers/sample_numbers.h"
#include "render/scene.h"

namespace nb = nanobind;

namespace patina_py {
namespace {

using Rows3 = nb::ndarray<const float, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;
using Tris = nb::ndarray<const int32_t, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;
using IntVector = nb::ndarray<const int32_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using Image = nb::ndarray<const float, nb::shape<-1, -1, 3>, nb::c_contig, nb::device::cpu>;

// A material's or light's dictionary read key by key: every value the renderer
// takes must be there (the defaults are the scene reader's, python/patina/scene/reading.py,
// not ours), and a key nothing read is an error naming it, as Mitsuba 3 rejects unused
// properties, so a misspelled key cannot silently leave its value at the struct's default.
class Fields {
public:
    Fields(const nb::dict& d, std::string what) : d_(d), what_(std::move(what)) {}

    // "<what>: <message>" as std::invalid_argument (ValueError in Python)
    [[noreturn]] void fail(const std::string& message) const { throw std::invalid_argument(what_ + ": " + message); }

    nb::object take(const char* key) {
        if (!d_.contains(key)) fail("missing key '" + std::string(key) + "'");
        read_.emplace_back(key);
        return d_[key];
    }
    template <class T>
    T as(const char* key, const char* expected) {
        nb::object o = take(key);
        T value;
        if (!nb::try_cast<T>(o, value)) fail("'" + std::string(key) + "' must be " + expected);
        return value;
    }
    float real(const char* key) {
        const float x = as<float>(key, "a number");
        if (!std::isfinite(x)) fail("'" + std::string(key) + "' is not finite (as a 32-bit float)");
        return x;
    }
    bool flag(const char* key) { return as<bool>(key, "a bool"); }
    int integer(const char* key) { return as<int>(key, "an integer"); }
    std::string text(const char* key) { return as<std::string>(key, "a string"); }
    void vec3(const char* key, float* out) {
        const std::vector<float> v = as<std::vector<float>>(key, "3 numbers");
        if (v.size() != 3) fail("'" + std::string(key) + "' must be 3 numbers, not " + std::to_string(v.size()));
        for (int k = 0; k < 3; ++k) {
            if (!std::isfinite(v[k])) fail("'" + std::string(key) + "' is not finite (as 32-bit floats)");
            out[k] = v[k];
        }
    }
    // a vector the renderer takes as a direction: unit length (computed beside the scene)
    void unit3(const char* key, float* out) {
        vec3(key, out);
        const double len = std::sqrt(double(out[0]) * out[0] + double(out[1]) * out[1] + double(out[2]) * out[2]);
        if (!(std::abs(len - 1) <= 1e-5))
            fail("'" + std::string(key) + "' must be a unit vector (its length is " + std::to_string(len) + ")");
    }

    // Every key of the dictionary was read, else the first one that was not is named.
    void finish() const {
        for (auto item : d_) {
            std::string key;
            if (!nb::try_cast<std::string>(item.first, key)) fail("its keys must be strings");
            if (std::find(read_.begin(), read_.end(), key) == read_.end()) {
                std::string known;
                for (const auto& k : read_) known += (known.empty() ? "" : ", ") + k;
                fail("unknown key '" + key + "' (the renderer reads " + known + ")");
            }
        }
    }

private:
    const nb::dict& d_;
    std::string what_;
    std::vector<std::string> read_;
};

// The camera's numbers finite (as 32-bit floats), else the one-line error naming the field.
void check_camera(const patina::Camera& c) {
    auto finite = [](const char* name, const float* v, int n) {
        for (int k = 0; k < n; ++k)
            if (!std::isfinite(v[k])) throw std::invalid_argument(std::string("the camera: '") + name + "' is not finite");
    };
    finite("position", c.position, 3);
    finite("forward", c.forward, 3);
    finite("right", c.right, 3);
    finite("up", c.up, 3);
    finite("tan_half_fov", &c.tan_half_fov, 1);
    finite("aperture_radius", &c.aperture_radius, 1);
    finite("focus_distance", &c.focus_distance, 1);
}

// Arrays are taken as Python objects and kept: the scene points into their buffers.
std::unique_ptr<SceneHandle> make_scene(nb::object accel_obj, nb::object indices_obj, nb::object normals_obj,
                                        nb::object tangents, nb::object tri_material_obj, const patina::Camera& camera) {
    auto h = std::make_unique<SceneHandle>();
    const Tris indices = nb::cast<Tris>(indices_obj);
    const Rows3 normals = nb::cast<Rows3>(normals_obj);
    const IntVector tri_material = nb::cast<IntVector>(tri_material_obj);
    Accel& accel = nb::cast<Accel&>(accel_obj);
    patina::RenderScene& s = h->scene;
    const size_t nt = indices.shape(0);
    if (accel.tree.triangle_count() != nt)
        throw std::invalid_argument("indices has " + std::to_string(nt) + " triangles, the accel " +
                                    std::to_string(accel.tree.triangle_count()));
    if (tri_material.shape(0) != nt + accel.tree.spheres.size())
        throw std::invalid_argument("tri_material needs one entry per triangle, then one per analytic sphere");
    const size_t nv = normals.shape(0);
    for (size_t i = 0; i < 3 * nt; ++i)
        if (indices.data()[i] < 0 || static_cast<size_t>(indices.data()[i]) >= nv)
            throw std::invalid_argument("triangle " + std::to_string(i / 3) + " refers to a vertex without a normal");
    s.tree = &accel.tree;
    // secondary and shadow rays through the BVH; PATINA_TRACER=kdtree keeps every ray on the
    // kd-tree (to measure one against the other, docs/performance.md)
    const char* tracer = std::getenv("PATINA_TRACER");
    s.bvh = tracer && std::string(tracer) == "kdtree" ? nullptr : &bvh_of(accel);
    s.indices = indices.data();
    s.normals = normals.data();
    s.tri_material = tri_material.data();
    s.triangle_count = nt;
    h->keep = {accel_obj, indices_obj, normals_obj, tri_material_obj};
    if (!tangents.is_none()) {
        const Rows3 t = nb::cast<Rows3>(tangents);
        if (t.shape(0) != nv) throw std::invalid_argument("tangents needs one row per vertex");
        s.tangents = t.data();
        h->keep.push_back(tangents);
    }
    check_camera(camera);
    s.camera = camera;
    patina::prepare_scale(s);
    return h;
}

// A material's or light's fields, named "<where> (<kind>)" in its errors, and its kind: the
// key "kind" read and looked up in `names` (else the one-line error naming it).
template <class Kind>
Fields kind_fields(const nb::dict& d, const std::string& where, const char* what,
                   std::initializer_list<std::pair<const char*, Kind>> names, Kind& kind) {
    const std::string name = Fields(d, where).text("kind");
    Fields f(d, where + " (" + name + ")");
    f.text("kind");
    for (const auto& [n, k] : names)
        if (name == n) {
            kind = k;
            return f;
        }
    f.fail("unknown " + std::string(what) + " kind '" + name + "'");
}

// A material or light appended to the scene's list once every key of its dictionary was read
// (else the error naming the unread one); its index in the list.
template <class Item>
int append_read(const Fields& f, std::vector<Item>& list, const Item& item) {
    f.finish();
    list.push_back(item);
    return static_cast<int>(list.size()) - 1;
}

// GGX roughness: 0 (smooth) is taken as 1e-3, a very narrow lobe the same code samples.
float roughness(Fields& f, const char* key) {
    constexpr float kSmooth = 1e-3f;
    const float a = f.real(key);
    if (!(a >= 0)) f.fail("'" + std::string(key) + "' must be >= 0");
    return std::max(a, kSmooth);
}

patina::Conductor read_conductor(Fields& f) {
    patina::Conductor c;
    c.alpha_x = roughness(f, "alpha_x");
    c.alpha_y = roughness(f, "alpha_y");
    f.vec3("eta", c.eta);
    f.vec3("k", c.k);
    f.vec3("tint", c.tint);
    return c;
}

// A table's or mixture's tint and sampling proxy.
void read_tint_and_proxy(Fields& f, float* tint, patina::ProxySampling& proxy) {
    f.vec3("tint", tint);
    proxy.diffuse = f.real("proxy_diffuse");
    if (!(proxy.diffuse >= 0 && proxy.diffuse <= 1)) f.fail("'proxy_diffuse' must be in [0, 1]");
    proxy.alpha = roughness(f, "proxy_alpha");
}

patina::TableMaterial read_table(Fields& f, SceneHandle& h) {
    patina::TableMaterial t;
    nb::object o = f.take("table");
    const TableHandle* table = nullptr;
    if (!nb::try_cast<const TableHandle*>(o, table) || table == nullptr) f.fail("'table' must be a patina._core.Table");
    if (table->table.channels != 3) f.fail("a table material needs an RGB table");
    t.table = &table->prepared.view;
    h.keep.push_back(o);
    read_tint_and_proxy(f, t.tint, t.proxy);
    return t;
}

// An RGL material: the file's arrays (a patina._core.RglBsdf, kept alive with the scene), its
// tint, the lobe roughness the cache decides by, and its sampling ("file" or "cosine").
patina::RglMaterial read_rgl(Fields& f, SceneHandle& h) {
    patina::RglMaterial r;
    nb::object o = f.take("rgl");
    const RglHandle* rgl = nullptr;
    if (!nb::try_cast<const RglHandle*>(o, rgl) || rgl == nullptr) f.fail("'rgl' must be a patina._core.RglBsdf");
    r.rgl = &rgl->view;
    h.keep.push_back(o);
    f.vec3("tint", r.tint);
    r.lobe_alpha = roughness(f, "lobe_alpha");
    const std::string sampling = f.text("sampling");
    if (sampling != "file" && sampling != "cosine") f.fail("'sampling' must be 'file' or 'cosine'");
    r.cosine_sampling = sampling == "cosine";
    return r;
}

patina::Mixture read_mixture(Fields& f) {
    patina::Mixture m;
    nb::tuple mix = f.as<nb::tuple>("mixture", "a tuple (kernel name, values, per_channel)");
    if (mix.size() != 3) f.fail("'mixture' must be a tuple (kernel name, values, per_channel)");
    try {
        m.params = mixture_params(nb::cast<std::string>(mix[0]), nb::cast<std::vector<float>>(mix[1]),
                                  nb::cast<bool>(mix[2]));
    } catch (const nb::cast_error&) {
        f.fail("'mixture' must be a tuple (kernel name, values, per_channel)");
    } catch (const std::invalid_argument& e) {
        f.fail(std::string("'mixture': ") + e.what());
    }
    read_tint_and_proxy(f, m.tint, m.proxy);
    return m;
}

patina::Dielectric read_dielectric(Fields& f) {
    patina::Dielectric d;
    d.alpha = roughness(f, "alpha_x");
    float eta[3];
    f.vec3("eta", eta);
    if (!(eta[0] > 0)) f.fail("dielectric eta must be > 0");
    d.eta = eta[0];
    return d;
}

// The keys of a material, by kind, are exactly what the renderer reads for that kind (see
// render/materials/): a Lambert's albedo, a conductor's GGX roughness, complex index and
// tint, a table's or mixture's tint and sampling proxy, an RGL file's tint, lobe roughness
// and sampling; the clear coat over any of the five
// (its three values present exactly when "coat" is true); an emitter only the light whose
// triangles it covers; a dielectric its roughness alpha_x and eta (eta[0] is read).
int add_material(SceneHandle& h, const nb::dict& d) {
    enum class Kind { Lambert, Conductor, Table, Mixture, Emitter, Dielectric, Rgl };
    Kind kind;
    Fields f = kind_fields<Kind>(d, "material " + std::to_string(h.scene.materials.size()), "material",
                                 {{"lambert", Kind::Lambert},
                                  {"conductor", Kind::Conductor},
                                  {"table", Kind::Table},
                                  {"mixture", Kind::Mixture},
                                  {"emitter", Kind::Emitter},
                                  {"dielectric", Kind::Dielectric},
                                  {"rgl", Kind::Rgl}},
                                 kind);
    patina::Material m;
    if (kind == Kind::Emitter) {
        m.model = patina::Emitter{f.integer("light")};
        return append_read(f, h.scene.materials, m);  // the light index: checked against the lights by check_materials
    }
    f.vec3("albedo", m.albedo);
    switch (kind) {
        case Kind::Lambert: {
            patina::Lambert lambert;
            std::copy(m.albedo, m.albedo + 3, lambert.reflectance);
            m.model = lambert;
            break;
        }
        case Kind::Conductor: m.model = read_conductor(f); break;
        case Kind::Table: m.model = read_table(f, h); break;
        case Kind::Mixture: m.model = read_mixture(f); break;
        case Kind::Dielectric: m.model = read_dielectric(f); break;
        case Kind::Rgl: m.model = read_rgl(f, h); break;
        case Kind::Emitter: break;
    }
    if (kind != Kind::Dielectric) {  // a dielectric refracts: it has no back face to cull, nor a coat
        m.two_sided = f.flag("two_sided");
        if (f.flag("coat")) {
            patina::ClearCoat coat;
            coat.eta = f.real("coat_eta");
            coat.alpha = roughness(f, "coat_alpha");
            f.vec3("coat_tint", coat.tint);
            m.coat = coat;
        }
    }
    return append_read(f, h.scene.materials, m);
}

using FloatVector = nb::ndarray<const float, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using FloatMatrix = nb::ndarray<const float, nb::ndim<2>, nb::c_contig, nb::device::cpu>;

// Each kind's fields after "power" (power: its RGB intensity, radiance or per-candela factor).
patina::PointLight read_point(Fields& f, const float power[3]) {
    patina::PointLight point;
    f.vec3("position", point.position);
    std::copy(power, power + 3, point.intensity);
    return point;
}

patina::QuadLight read_quad(Fields& f, const float power[3]) {
    patina::QuadLight q;
    std::copy(power, power + 3, q.radiance);
    f.vec3("position", q.center);
    f.vec3("u", q.u);
    f.vec3("v", q.v);
    f.unit3("normal", q.normal);
    return q;
}

patina::SpotLight read_spot(Fields& f, const float power[3]) {
    patina::SpotLight spot;
    std::copy(power, power + 3, spot.intensity);
    f.vec3("position", spot.position);
    f.unit3("direction", spot.direction);
    spot.cos_inner = f.real("cos_inner");
    spot.cos_outer = f.real("cos_outer");
    if (!(spot.cos_outer < spot.cos_inner)) f.fail("a spot light's cone: cos_outer < cos_inner");
    return spot;
}

patina::SunLight read_sun(Fields& f, const float power[3]) {
    patina::SunLight sun;
    std::copy(power, power + 3, sun.radiance);
    f.unit3("direction", sun.direction);
    sun.cos_sun = f.real("cos_sun");
    sun.one_minus_cos = f.real("sun_one_minus_cos");
    // a disc of angular radius below 1.5 rad, its two cosines describing the same cone
    if (!(sun.cos_sun > std::cos(1.5f) && sun.cos_sun < 1 && sun.one_minus_cos > 0 &&
          std::abs(sun.cos_sun + sun.one_minus_cos - 1) <= 1e-6f))
        f.fail("the sun's disc: cos_sun in (cos 1.5, 1) and sun_one_minus_cos = 1 - cos_sun");
    f.unit3("frame_t", sun.frame_t);
    f.unit3("frame_b", sun.frame_b);
    return sun;
}

patina::TriangleLight read_triangles(Fields& f, const float power[3], const SceneHandle& h) {
    patina::TriangleLight t;
    std::copy(power, power + 3, t.radiance);
    IntVector tris;
    FloatVector cdf;
    if (!nb::try_cast<IntVector>(f.take("triangles"), tris)) f.fail("'triangles' must be a 1-D int32 array");
    if (!nb::try_cast<FloatVector>(f.take("area_cdf"), cdf)) f.fail("'area_cdf' must be a 1-D float32 array");
    const size_t n = tris.shape(0);
    if (n == 0) f.fail("an emissive mesh needs triangles");
    if (cdf.shape(0) != n + 1) f.fail("'area_cdf' needs one value per triangle and a leading 0");
    const patina::KdTree& tree = *h.scene.tree;
    for (size_t i = 0; i < n; ++i)
        if (tris.data()[i] < 0 || static_cast<size_t>(tris.data()[i]) >= tree.triangle_count())
            f.fail("triangle id " + std::to_string(tris.data()[i]) + " is out of range");
    const float* c = cdf.data();
    for (size_t i = 1; i <= n; ++i)
        if (!(c[i] >= c[i - 1])) f.fail("'area_cdf' must not decrease (at " + std::to_string(i) + ")");
    if (c[0] != 0.0f || c[n] != 1.0f) f.fail("'area_cdf' must go from 0 to exactly 1");
    t.triangles.assign(tris.data(), tris.data() + n);
    t.area_cdf.assign(c, c + n + 1);
    return t;
}

patina::GoniometricLight read_goniometric(Fields& f, const float power[3], SceneHandle& h) {
    patina::GoniometricLight g;
    std::copy(power, power + 3, g.rgb_per_candela);
    f.vec3("position", g.position);
    f.unit3("axis_x", g.axis_x);
    f.unit3("axis_y", g.axis_y);
    f.unit3("axis_z", g.axis_z);
    g.type_b = f.flag("type_b");
    nb::object grid = f.take("candela");
    const Grid2Handle* table = nullptr;
    if (!nb::try_cast<const Grid2Handle*>(grid, table) || table == nullptr)
        f.fail("'candela' must be a patina._core.Grid2");
    g.candela = table->view();
    h.keep.push_back(grid);
    return g;
}

// An area light's area and sides, read after its shape.
template <class Area>
Area with_area(Fields& f, Area light) {
    const float area = f.real("area");
    if (!(area > 0)) f.fail("'area' must be > 0");
    light.area = area;
    light.two_sided = f.flag("two_sided");
    return light;
}

// The keys of a light, by kind, are what the renderer reads for it (render/lights/): "power"
// is a point's or spot's intensity, a quad's, triangles' or the sun's radiance, a
// goniometric light's RGB per candela. What follows from the geometry — a quad's normal and
// area, the sun's cone and frame, an emissive mesh's area cdf, unit directions — is computed
// beside the scene (python/patina/render/prepare.py) and only checked here.
int add_light(SceneHandle& h, const nb::dict& d) {
    enum class Kind { Point, Quad, Spot, Sun, Triangles, Goniometric };
    Kind kind;
    Fields f = kind_fields<Kind>(d, "light " + std::to_string(h.scene.lights.size()), "light",
                                 {{"point", Kind::Point},
                                  {"quad", Kind::Quad},
                                  {"spot", Kind::Spot},
                                  {"sun", Kind::Sun},
                                  {"triangles", Kind::Triangles},
                                  {"goniometric", Kind::Goniometric}},
                                 kind);
    float power[3];
    f.vec3("power", power);
    patina::Light l;
    switch (kind) {
        case Kind::Point: l.model = read_point(f, power); break;
        case Kind::Quad: l.model = with_area(f, read_quad(f, power)); break;
        case Kind::Spot: l.model = read_spot(f, power); break;
        case Kind::Sun: l.model = read_sun(f, power); break;
        case Kind::Triangles: l.model = with_area(f, read_triangles(f, power, h)); break;
        case Kind::Goniometric: l.model = read_goniometric(f, power, h); break;
    }
    return append_read(f, h.scene.lights, l);
}

void set_environment(SceneHandle& h, nb::object rgb, const std::vector<float>& constant, float intensity,
                     float rotation) {
    patina::Environment& e = h.scene.env;
    e = patina::Environment{};
    e.present = true;
    e.intensity = intensity;
    e.rotation = rotation;
    if (!rgb.is_none()) {
        const Image img = nb::cast<Image>(rgb);
        e.is_map = true;
        e.height = static_cast<int>(img.shape(0));
        e.width = static_cast<int>(img.shape(1));
        e.rgb = img.data();
        h.keep.push_back(rgb);
    } else {
        if (constant.size() != 3) throw std::invalid_argument("a constant environment needs 3 values");
        for (int k = 0; k < 3; ++k) e.constant[k] = constant[k];
    }
    patina::prepare_environment(e);
}

void check_materials(const SceneHandle& h) {
    const auto& s = h.scene;
    const int nm = static_cast<int>(s.materials.size());
    for (size_t i = 0; i < s.triangle_count; ++i)
        if (s.tri_material[i] < 0 || s.tri_material[i] >= nm)
            throw std::invalid_argument("triangle " + std::to_string(i) + " has no material");
    for (const auto& m : s.materials) {
        if (!m.is<patina::Emitter>()) continue;
        const int light = m.as<patina::Emitter>().light;
        if (light < 0 || light >= static_cast<int>(s.lights.size()) ||
            !patina::is_area_light(s.lights[light]))
            throw std::invalid_argument("an emitter material must name a quad or triangles light");
    }
}

void check_axis(const FloatVector& a, const char* name) {
    if (a.shape(0) < 1) throw std::invalid_argument(std::string(name) + ": needs at least one knot");
    for (size_t i = 0; i < a.shape(0); ++i) {
        if (!std::isfinite(a.data()[i])) throw std::invalid_argument(std::string(name) + ": knot " + std::to_string(i) + " is not finite");
        if (i > 0 && !(a.data()[i] > a.data()[i - 1]))
            throw std::invalid_argument(std::string(name) + ": knots must increase strictly (at " + std::to_string(i) + ")");
    }
}

// The adaptive sampler's fixed data (render/antialiasing/adaptive_pattern.h), for the drawings of
// tools/draw_antialiasing.py and the tests: positions in the canonical frame, the three
// fours of compared sample pairs, the zone tables, the weights per refined-zone set.
// The first uses of a stream's samples [first, first + n) as the sampler draws them
// (render/samplers/sample_numbers.h), for the tests of stratification and convergence: out[i][c] is
// use c of the sample's path, in the order pixel x, y, lens u, v, then seven a bounce (light
// pick, u, v, BRDF pick, u, v, roulette; bounce 0: columns 4-10, bounce 1: 11-17, ...).
// sobol with scramble=false: the plain Sobol points, out[i][d] dimension d of the table.
nb::ndarray<nb::numpy, float, nb::ndim<2>> sample_points(const std::string& sampler, size_t n, int dims, uint64_t seed,
                                                        uint32_t first, bool scramble) {
    const bool sobol = sampler == "sobol";
    if (!sobol && sampler != "independent")
        throw std::invalid_argument("sampler: '" + sampler + "' is not one of 'sobol', 'independent'");
    const bool plain = sobol && !scramble;
    if (dims < 1 || (plain && dims > patina::sobol::kDimensions))
        throw std::invalid_argument("dims: must be 1 to " + std::to_string(patina::sobol::kDimensions));
    float* out;
    const size_t shape[2] = {n, static_cast<size_t>(dims)};
    auto a = new_array<float, 2>(shape, &out);
    const uint32_t key = patina::stream_key(patina::stream_seed(seed), 0);
    const auto kind = sobol ? patina::SamplerKind::Sobol : patina::SamplerKind::Independent;
    constexpr int camera = patina::kDimLightPick, per_bounce = patina::kDimRoulette - patina::kDimLightPick + 1;
    for (size_t i = 0; i < n; ++i) {
        const uint32_t index = first + static_cast<uint32_t>(i);
        for (int c = 0; c < dims; ++c) {
            const int bounce = c < camera ? 0 : (c - camera) / per_bounce;
            const auto use = static_cast<patina::RandomDim>(c < camera ? c : camera + (c - camera) % per_bounce);
            out[i * dims + c] = plain ? patina::unit_float(patina::sobol::point_bits(index, c))
                                      : patina::sample_uniform(kind, key, index, bounce, use);
        }
    }
    return a;
}

nb::dict aa_pattern() {
    namespace aa = patina::aa;
    float *pos, *weights, *direct_weights;
    int32_t *pairs, *zones;
    const size_t sp[2] = {aa::kMaxSamples, 2}, sc[3] = {3, 4, 2}, sz[2] = {3, 16},
                 sw[2] = {aa::kPatterns, aa::kMaxSamples};
    auto a_pos = new_array<float, 2>(sp, &pos);
    auto a_pairs = new_array<int32_t, 3>(sc, &pairs);
    auto a_zones = new_array<int32_t, 2>(sz, &zones);
    auto a_weights = new_array<float, 2>(sw, &weights);
    auto a_direct_weights = new_array<float, 2>(sw, &direct_weights);
    for (int s = 0; s < aa::kMaxSamples; ++s) {
        pos[2 * s] = static_cast<float>(aa::sample_point(s).u);
        pos[2 * s + 1] = static_cast<float>(aa::sample_point(s).v);
    }
    for (int f = 0; f < 3; ++f)
        for (int l = 0; l < 4; ++l) {
            pairs[8 * f + 2 * l] = aa::kComparisons[f][l].p;
            pairs[8 * f + 2 * l + 1] = aa::kComparisons[f][l].q;
        }
    for (int f = 0; f < 3; ++f)
        for (int m = 0; m < 16; ++m) zones[16 * f + m] = aa::kZoneTable[f][m];
    for (int z = 0; z < aa::kPatterns; ++z)
        for (int s = 0; s < aa::kMaxSamples; ++s) {
            weights[aa::kMaxSamples * z + s] = aa::kWeights[z][s];
            direct_weights[aa::kMaxSamples * z + s] = aa::kDirectWeights[z][s];
        }
    nb::dict d;
    d["positions"] = a_pos;
    d["comparisons"] = a_pairs;
    d["zone_table"] = a_zones;
    d["weights"] = a_weights;
    d["direct_weights"] = a_direct_weights;  // level 2 skipped: zero where the zones are not one run
    d["default_threshold"] = patina::kDefaultAaThreshold;
    return d;
}

std::unique_ptr<Grid2Handle> make_grid2(FloatVector x, FloatVector y, FloatMatrix values) {
    check_axis(x, "x");
    check_axis(y, "y");
    if (values.shape(0) != x.shape(0) || values.shape(1) != y.shape(0))
        throw std::invalid_argument("values must have shape (len(x), len(y))");
    auto g = std::make_unique<Grid2Handle>();
    g->x.assign(x.data(), x.data() + x.shape(0));
    g->y.assign(y.data(), y.data() + y.shape(0));
    g->values.assign(values.data(), values.data() + values.size());
    for (size_t i = 0; i < g->values.size(); ++i)
        if (!std::isfinite(g->values[i])) throw std::invalid_argument("value " + std::to_string(i) + " is not finite");
    return g;
}

nb::object grid2_eval(const Grid2Handle& g, FloatVector x, FloatVector y, int width) {
    const size_t n = x.shape(0);
    if (y.shape(0) != n) throw std::invalid_argument("x and y have different lengths");
    float* out;
    auto result = new_array<float, 1>({n}, &out);
    const patina::Grid2View v = g.view();
    const patina::RenderKernels& k = patina::render_kernels_for(width);
    {
        nb::gil_scoped_release release;
        k.grid2_eval(v, x.data(), y.data(), out, n);
    }
    return nb::cast(result);
}

// A sensor entry point's scene and points, after the check both entry points make (as many
// normals as points).
struct Sensors {
    SceneHandle& handle;
    const float* points;   // (count, 3)
    const float* normals;  // (count, 3), unit
    size_t count;
};

Sensors sensors_of(nb::object scene_obj, const Rows3& points, const Rows3& normals) {
    SceneHandle& h = nb::cast<SceneHandle&>(scene_obj);
    const size_t n = points.shape(0);
    if (normals.shape(0) != n) throw std::invalid_argument("points and normals have different lengths");
    return {h, points.data(), normals.data(), n};
}

// The scene prepared, then per_block(kernels, begin, end, scratch) over the sensors in blocks
// of `block` points on `threads` threads, each block with its own scratch buffers, the GIL
// released.
template <class PerBlock>
void for_sensor_blocks(const Sensors& sensors, size_t block, int width, int threads, PerBlock per_block) {
    prepare_for_render(sensors.handle);
    const patina::RenderKernels& k = patina::render_kernels_for(width);
    nb::gil_scoped_release release;
    patina::parallel_for(sensors.count, block, threads, [&](size_t b, size_t e) {
        patina::PathScratch scratch;
        per_block(k, b, e, scratch);
    });
}

// Illuminance (lux) on sensors: points and unit normals (n, 3); split over threads. Direct
// light; with max_depth > 0 also the light reflected by the scene, by sensor paths of the
// vertices a camera path of that max_depth has (the scene file's convention, path_vertices).
nb::object sensor_illuminance(nb::object scene_obj, Rows3 points, Rows3 normals, int samples, uint64_t seed,
                              int width, int threads, int max_depth) {
    const Sensors sensors = sensors_of(scene_obj, points, normals);
    if (samples < 1) throw std::invalid_argument("samples must be at least 1");
    if (max_depth < 0) throw std::invalid_argument("max_depth must be at least 0 (0: direct light only)");
    float* out;
    auto result = new_array<float, 1>({sensors.count}, &out);
    const patina::RenderScene& scene = sensors.handle.scene;
    for_sensor_blocks(sensors, 256, width, threads, [&](const patina::RenderKernels& k, size_t b, size_t e,
                                                        patina::PathScratch& scratch) {
        k.sensor_illuminance(scene, sensors.points, sensors.normals, b, e, samples, patina::stream_seed(seed), out,
                             scratch);
        if (max_depth > 0) {
            patina::IntegratorSettings settings;
            settings.max_depth = patina::path_vertices(max_depth);
            k.sensor_illuminance_indirect(scene, settings, sensors.points, sensors.normals, b, e, samples,
                                          patina::stream_seed(seed), out, scratch);
        }
    });
    return nb::cast(result);
}

// Radiance-cache points at sensors (render/cache/sensor_cache_points_impl.h): (lux, harmonic
// mean hit distance) of an R x R hemisphere at each point, paths of the scene file's max_depth.
nb::object sensor_cache_points(nb::object scene_obj, Rows3 points, Rows3 normals, int resolution, uint64_t seed,
                               int width, int threads, int max_depth) {
    const Sensors sensors = sensors_of(scene_obj, points, normals);
    if (resolution < 1 || resolution > 64) throw std::invalid_argument("resolution must lie in [1, 64]");
    if (max_depth < 1) throw std::invalid_argument("max_depth must be at least 1");
    float *lux, *distance;
    auto lux_array = new_array<float, 1>({sensors.count}, &lux);
    auto distance_array = new_array<float, 1>({sensors.count}, &distance);
    patina::IntegratorSettings settings;
    settings.max_depth = patina::path_vertices(max_depth);
    const patina::RenderScene& scene = sensors.handle.scene;
    for_sensor_blocks(sensors, 16, width, threads, [&](const patina::RenderKernels& k, size_t b, size_t e,
                                                       patina::PathScratch& scratch) {
        k.sensor_cache_points(scene, settings, sensors.points, sensors.normals, b, e, resolution,
                              patina::stream_seed(seed), lux, distance, scratch);
    });
    return nb::make_tuple(lux_array, distance_array);
}

// A sensor entry point bound with the keywords both take: scene, points, normals, then its
// own count (samples or resolution), seed, width, threads and max_depth.
template <class Function>
void def_sensor_entry(nb::module_& m, const char* name, Function function, nb::arg_v count, int max_depth,
                      const char* doc) {
    m.def(name, function, nb::arg("scene"), nb::arg("points"), nb::arg("normals"), count, nb::arg("seed") = 0,
          nb::arg("width") = 0, nb::arg("threads") = 0, nb::arg("max_depth") = max_depth, doc);
}

}  // namespace

void prepare_for_render(SceneHandle& h) {
    check_materials(h);
    patina::prepare_light_selection(h.scene);
}

void bind_render(nb::module_& m) {
    nb::class_<Grid2Handle>(m, "Grid2", "A 2-D table on an irregular tensor grid, bilinear, clamped to its axes.")
        .def(nb::new_(&make_grid2), nb::arg("x"), nb::arg("y"), nb::arg("values"))
        .def("eval", &grid2_eval, nb::arg("x"), nb::arg("y"), nb::arg("width") = 0,
             "values at (x[i], y[i]) by the coherent search and bilinear interpolation, N points at a time");
    using C = patina::Camera;
    Record<C>(m, "Camera", "The renderer's camera (render/camera/camera.h), its frame computed beside the scene.")
        .vector3("position", &C::position, "the eye, world space")
        .vector3("forward", &C::forward, "the view direction, unit")
        .vector3("right", &C::right, "the image's x direction, unit, orthogonal to forward")
        .vector3("up", &C::up, "the image's upward direction, unit: cross(right, forward)")
        .field("tan_half_fov", &C::tan_half_fov, "tan(vertical field of view / 2)")
        .field("width", &C::width, "image width, pixels")
        .field("height", &C::height, "image height, pixels")
        .field("aperture_radius", &C::aperture_radius, "the thin lens's aperture radius (0: a pinhole)")
        .field("focus_distance", &C::focus_distance, "the distance in focus, along forward")
        .finish();
    nb::class_<SceneHandle>(m, "RenderScene", "Geometry, materials, lights, environment and camera for RenderJob.")
        .def(nb::new_(&make_scene), nb::arg("accel"), nb::arg("indices"), nb::arg("normals"),
             nb::arg("tangents").none(), nb::arg("tri_material"), nb::arg("camera"))
        .def("add_material", &add_material, nb::arg("material"))
        .def("add_light", &add_light, nb::arg("light"))
        .def("set_environment", &set_environment, nb::arg("rgb").none(), nb::arg("constant"),
             nb::arg("intensity") = 1.0f, nb::arg("rotation") = 0.0f)
        .def_prop_ro("scene_radius", [](const SceneHandle& h) { return h.scene.scene_radius; });
    m.def("sample_points", &sample_points, nb::arg("sampler"), nb::arg("n"), nb::arg("dims"), nb::arg("seed") = 0,
          nb::arg("first") = 0, nb::arg("scramble") = true,
          "The sampler's numbers of one stream: samples [first, first + n) x dimensions [0, dims).");
    m.def("aa_pattern", &aa_pattern,
          "The adaptive antialiasing's positions, comparisons, zone tables, weights (with and without level 2).");
    def_sensor_entry(
        m, "sensor_illuminance", &sensor_illuminance, nb::arg("samples") = 64, 0,
        "Illuminance in lux on sensors at points facing normals: direct by shadowed light sampling, and with "
        "max_depth > 0 the light the scene reflects, by cosine-weighted sensor paths as long as a camera path of "
        "that max_depth (the scene file's render.max_depth).");
    def_sensor_entry(
        m, "sensor_cache_points", &sensor_cache_points, nb::arg("resolution") = 16, 5,
        "Radiance-cache points at sensors: (lux, harmonic mean hit distance), the indirect illuminance of a "
        "resolution x resolution hemisphere of jittered texel rays at each point (paths as sensor_illuminance's "
        "with that max_depth) and its texels' harmonic mean first-hit distance (inf when none hit).");
}

}  // namespace patina_py
