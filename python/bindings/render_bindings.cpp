// patina._core.RenderScene and RenderJob: the preview renderer. The Python side
// (python/patina/render.py) checks the scene file and builds these; here values are
// only converted, with std::invalid_argument for what cannot be converted.
#include <nanobind/stl/string.h>
#include <nanobind/stl/unique_ptr.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "bindings.h"
#include "render/grid2.h"
#include "render/integrator.h"
#include "render/render_job.h"
#include "render/scene.h"
#include "core/parallel.h"

namespace nb = nanobind;

namespace patina_py {
namespace {

using Rows3 = nb::ndarray<const float, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;
using Tris = nb::ndarray<const int32_t, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;
using IntVector = nb::ndarray<const int32_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using Image = nb::ndarray<const float, nb::shape<-1, -1, 3>, nb::c_contig, nb::device::cpu>;

// The scene with references to everything its pointers point into.
struct SceneHandle {
    patina::RenderScene scene;
    std::vector<nb::object> keep;  // arrays, tables and the accel the pointers point into
};

// A 2-D table (a goniometric light's candela over C-plane and gamma angles), checked and
// kept; evaluated by the render kernels' grid2_eval at any width.
struct Grid2Handle {
    std::vector<float> x, y, values;
    patina::Grid2View view() const {
        return {x.data(), static_cast<int>(x.size()), y.data(), static_cast<int>(y.size()), values.data()};
    }
};

float get_float(const nb::dict& d, const char* key, float fallback) {
    return d.contains(key) ? nb::cast<float>(d[key]) : fallback;
}
bool get_bool(const nb::dict& d, const char* key, bool fallback) {
    return d.contains(key) ? nb::cast<bool>(d[key]) : fallback;
}
void get_rgb(const nb::dict& d, const char* key, float* out) {
    if (!d.contains(key)) return;
    const std::vector<float> v = nb::cast<std::vector<float>>(d[key]);
    if (v.size() != 3) throw std::invalid_argument(std::string(key) + ": expected 3 values");
    for (int k = 0; k < 3; ++k) out[k] = v[k];
}
void get_vec3(const nb::dict& d, const char* key, float* out) { get_rgb(d, key, out); }

// Arrays are taken as Python objects and kept: the scene points into their buffers.
std::unique_ptr<SceneHandle> make_scene(nb::object accel_obj, nb::object indices_obj, nb::object normals_obj,
                                        nb::object tangents, nb::object tri_material_obj, const nb::dict& camera) {
    auto h = std::make_unique<SceneHandle>();
    const Tris indices = nb::cast<Tris>(indices_obj);
    const Rows3 normals = nb::cast<Rows3>(normals_obj);
    const IntVector tri_material = nb::cast<IntVector>(tri_material_obj);
    const Accel& accel = nb::cast<const Accel&>(accel_obj);
    patina::RenderScene& s = h->scene;
    const size_t nt = indices.shape(0);
    if (accel.tree.triangle_count() != nt)
        throw std::invalid_argument("indices has " + std::to_string(nt) + " triangles, the accel " +
                                    std::to_string(accel.tree.triangle_count()));
    if (tri_material.shape(0) != nt) throw std::invalid_argument("tri_material needs one entry per triangle");
    const size_t nv = normals.shape(0);
    for (size_t i = 0; i < 3 * nt; ++i)
        if (indices.data()[i] < 0 || static_cast<size_t>(indices.data()[i]) >= nv)
            throw std::invalid_argument("triangle " + std::to_string(i / 3) + " refers to a vertex without a normal");
    s.tree = &accel.tree;
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
    patina::Camera& c = s.camera;
    get_vec3(camera, "position", c.position);
    get_vec3(camera, "forward", c.forward);
    get_vec3(camera, "right", c.right);
    get_vec3(camera, "up", c.up);
    c.tan_half_fov = get_float(camera, "tan_half_fov", c.tan_half_fov);
    c.width = nb::cast<int>(camera["width"]);
    c.height = nb::cast<int>(camera["height"]);
    c.aperture_radius = get_float(camera, "aperture_radius", 0.0f);
    c.focus_distance = get_float(camera, "focus_distance", 1.0f);
    patina::prepare_scale(s);
    return h;
}

int add_material(SceneHandle& h, const nb::dict& d) {
    patina::Material m;
    const std::string kind = nb::cast<std::string>(d["kind"]);
    if (kind == "lambert") m.kind = patina::MaterialKind::Lambert;
    else if (kind == "conductor") m.kind = patina::MaterialKind::Conductor;
    else if (kind == "table") m.kind = patina::MaterialKind::Table;
    else if (kind == "mixture") m.kind = patina::MaterialKind::Mixture;
    else if (kind == "emitter") m.kind = patina::MaterialKind::Emitter;
    else if (kind == "dielectric") m.kind = patina::MaterialKind::Dielectric;
    else throw std::invalid_argument("unknown material kind '" + kind + "'");
    get_rgb(d, "albedo", m.albedo);
    // GGX roughness: 0 (smooth) is taken as 1e-3, a very narrow lobe the same code samples
    constexpr float kSmooth = 1e-3f;
    m.alpha_x = std::max(get_float(d, "alpha_x", m.alpha_x), kSmooth);
    m.alpha_y = std::max(get_float(d, "alpha_y", m.alpha_y), kSmooth);
    get_rgb(d, "eta", m.eta);
    get_rgb(d, "k", m.k);
    get_rgb(d, "tint", m.tint);
    m.two_sided = get_bool(d, "two_sided", false);
    m.coat = get_bool(d, "coat", false);
    m.coat_eta = get_float(d, "coat_eta", m.coat_eta);
    m.coat_alpha = std::max(get_float(d, "coat_alpha", m.coat_alpha), kSmooth);
    get_rgb(d, "coat_tint", m.coat_tint);
    m.proxy_diffuse = get_float(d, "proxy_diffuse", m.proxy_diffuse);
    m.proxy_alpha = std::max(get_float(d, "proxy_alpha", m.proxy_alpha), kSmooth);
    m.light = d.contains("light") ? nb::cast<int>(d["light"]) : -1;
    if (m.kind == patina::MaterialKind::Table) {
        nb::object t = d["table"];
        const TableHandle& table = nb::cast<const TableHandle&>(t);
        if (table.table.channels != 3) throw std::invalid_argument("a table material needs an RGB table");
        m.table = &table.prepared.view;
        h.keep.push_back(t);
    }
    if (m.kind == patina::MaterialKind::Mixture) {
        nb::tuple mix = nb::cast<nb::tuple>(d["mixture"]);
        m.mixture = mixture_params(nb::cast<std::string>(mix[0]), nb::cast<std::vector<float>>(mix[1]),
                                   nb::cast<bool>(mix[2]));
    }
    if (m.kind == patina::MaterialKind::Dielectric && !(m.eta[0] > 0))
        throw std::invalid_argument("dielectric eta must be > 0");
    h.scene.materials.push_back(m);
    return static_cast<int>(h.scene.materials.size()) - 1;
}

void normalize(float* v, const char* what) {
    const float len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(len > 0) || !std::isfinite(len)) throw std::invalid_argument(std::string(what) + " must be a non-zero vector");
    for (int k = 0; k < 3; ++k) v[k] /= len;
}

int add_light(SceneHandle& h, const nb::dict& d) {
    patina::Light l;
    const std::string kind = nb::cast<std::string>(d["kind"]);
    if (kind == "point") l.kind = patina::LightKind::Point;
    else if (kind == "quad") l.kind = patina::LightKind::Quad;
    else if (kind == "spot") l.kind = patina::LightKind::Spot;
    else if (kind == "sun") l.kind = patina::LightKind::Sun;
    else if (kind == "triangles") l.kind = patina::LightKind::Triangles;
    else if (kind == "goniometric") l.kind = patina::LightKind::Goniometric;
    else throw std::invalid_argument("unknown light kind '" + kind + "'");
    get_vec3(d, "position", l.position);
    get_vec3(d, "u", l.u);
    get_vec3(d, "v", l.v);
    get_rgb(d, "power", l.power);
    l.two_sided = get_bool(d, "two_sided", false);
    l.power_estimate = get_float(d, "power_estimate", -1.0f);
    switch (l.kind) {
        case patina::LightKind::Quad: {
            const float n[3] = {l.u[1] * l.v[2] - l.u[2] * l.v[1], l.u[2] * l.v[0] - l.u[0] * l.v[2],
                                l.u[0] * l.v[1] - l.u[1] * l.v[0]};
            const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            if (!(len > 0)) throw std::invalid_argument("a quad light needs non-parallel u and v");
            for (int k = 0; k < 3; ++k) l.normal[k] = n[k] / len;
            l.area = 4 * len;
            break;
        }
        case patina::LightKind::Spot:
            get_vec3(d, "direction", l.direction);
            normalize(l.direction, "a spot light's direction");
            l.cos_inner = get_float(d, "cos_inner", 1.0f);
            l.cos_outer = get_float(d, "cos_outer", 0.0f);
            if (!(l.cos_outer < l.cos_inner)) throw std::invalid_argument("a spot light's cone: cos_outer < cos_inner");
            break;
        case patina::LightKind::Sun:
            get_vec3(d, "direction", l.direction);
            normalize(l.direction, "the sun's direction");
            {
                const double half = get_float(d, "half_angle", 0.0f);  // radians
                if (!(half > 0 && half < 1.5)) throw std::invalid_argument("the sun's disc: 0 < half_angle < 1.5 rad");
                l.cos_sun = static_cast<float>(std::cos(half));
                l.sun_one_minus_cos = static_cast<float>(2 * std::sin(half / 2) * std::sin(half / 2));
            }
            {
                patina::Vec3f t, b;
                patina::orthonormal_frame({l.direction[0], l.direction[1], l.direction[2]}, t, b);
                l.frame_t[0] = t.x, l.frame_t[1] = t.y, l.frame_t[2] = t.z;
                l.frame_b[0] = b.x, l.frame_b[1] = b.y, l.frame_b[2] = b.z;
            }
            break;
        case patina::LightKind::Triangles: {
            const std::vector<int32_t> tris = nb::cast<std::vector<int32_t>>(d["triangles"]);
            const patina::KdTree& tree = *h.scene.tree;
            double total = 0;
            l.area_cdf.push_back(0.0f);
            std::vector<double> acc;
            for (int32_t t : tris) {
                if (t < 0 || static_cast<size_t>(t) >= tree.triangle_count())
                    throw std::invalid_argument("an emissive triangle id is out of range");
                const float* v = tree.triangles.data() + 9 * static_cast<size_t>(t);
                const double e1[3] = {v[3] - v[0], v[4] - v[1], v[5] - v[2]}, e2[3] = {v[6] - v[0], v[7] - v[1], v[8] - v[2]};
                const double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
                total += 0.5 * std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
                acc.push_back(total);
            }
            if (!(total > 0)) throw std::invalid_argument("an emissive mesh needs a positive area");
            l.triangles = tris;
            for (double a : acc) l.area_cdf.push_back(static_cast<float>(a / total));
            l.area_cdf.back() = 1.0f;
            l.area = static_cast<float>(total);
            break;
        }
        case patina::LightKind::Goniometric: {
            get_vec3(d, "axis_x", l.axis_x);
            get_vec3(d, "axis_y", l.axis_y);
            get_vec3(d, "axis_z", l.axis_z);
            l.type_b = get_bool(d, "type_b", false);
            nb::object grid = d["candela"];
            l.candela = nb::cast<const Grid2Handle&>(grid).view();
            h.keep.push_back(grid);
            break;
        }
        default: break;
    }
    h.scene.lights.push_back(l);
    return static_cast<int>(h.scene.lights.size()) - 1;
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
    for (const auto& m : s.materials)
        if (m.kind == patina::MaterialKind::Emitter &&
            (m.light < 0 || m.light >= static_cast<int>(s.lights.size()) ||
             (s.lights[m.light].kind != patina::LightKind::Quad &&
              s.lights[m.light].kind != patina::LightKind::Triangles)))
            throw std::invalid_argument("an emitter material must name a quad or triangles light");
}

struct JobHandle {
    nb::object scene_ref;
    std::unique_ptr<patina::RenderJob> job;
};

// The documented seeds are 0 to 2^63 - 1; the samplers key their streams by 32 bits. Seeds
// below 2^32 are used as they are (images stay the same), higher bits are mixed into them.
uint32_t stream_seed(uint64_t seed) {
    return static_cast<uint32_t>(seed) ^ (static_cast<uint32_t>(seed >> 32) * 0x9e3779b1u);
}

std::unique_ptr<JobHandle> make_job(nb::object scene_obj, int spp, int max_depth, uint64_t seed, int threads,
                                    int width, int tile_size, int passes) {
    SceneHandle& h = nb::cast<SceneHandle&>(scene_obj);
    check_materials(h);
    patina::prepare_light_selection(h.scene);
    patina::RenderSettings st;
    st.spp = spp;
    st.max_depth = max_depth;
    st.seed = stream_seed(seed);
    st.threads = threads;
    st.width = width;
    st.tile_size = tile_size;
    st.passes = passes;
    auto j = std::make_unique<JobHandle>();
    j->scene_ref = scene_obj;
    j->job = std::make_unique<patina::RenderJob>(h.scene, st);
    return j;
}

nb::dict progress(const JobHandle& j) {
    const patina::RenderProgress p = j.job->progress();
    nb::dict d;
    d["items_done"] = p.items_done;
    d["items_total"] = p.items_total;
    d["rays"] = p.rays;
    d["samples_done"] = p.samples_done;
    d["seconds"] = p.seconds;
    d["finished"] = p.finished;
    d["cancelled"] = p.cancelled;
    return d;
}

nb::dict resolve(const JobHandle& j) {
    const auto& cam = j.job->camera();
    const size_t hgt = cam.height, wid = cam.width;
    float *rgb, *albedo, *normal, *depth, *lux, *samples;
    const size_t s3[3] = {hgt, wid, 3}, s2[2] = {hgt, wid};
    auto a_rgb = new_array<float, 3>(s3, &rgb);
    auto a_albedo = new_array<float, 3>(s3, &albedo);
    auto a_normal = new_array<float, 3>(s3, &normal);
    auto a_depth = new_array<float, 2>(s2, &depth);
    auto a_lux = new_array<float, 2>(s2, &lux);
    auto a_samples = new_array<float, 2>(s2, &samples);
    {
        nb::gil_scoped_release release;
        j.job->resolve(rgb, albedo, normal, depth, lux, samples);
    }
    nb::dict d;
    d["rgb"] = a_rgb;
    d["albedo"] = a_albedo;
    d["normal"] = a_normal;
    d["depth"] = a_depth;
    d["illuminance"] = a_lux;
    d["samples"] = a_samples;
    return d;
}

using FloatVector = nb::ndarray<const float, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using FloatMatrix = nb::ndarray<const float, nb::ndim<2>, nb::c_contig, nb::device::cpu>;

void check_axis(const FloatVector& a, const char* name) {
    if (a.shape(0) < 1) throw std::invalid_argument(std::string(name) + ": needs at least one knot");
    for (size_t i = 0; i < a.shape(0); ++i) {
        if (!std::isfinite(a.data()[i])) throw std::invalid_argument(std::string(name) + ": knot " + std::to_string(i) + " is not finite");
        if (i > 0 && !(a.data()[i] > a.data()[i - 1]))
            throw std::invalid_argument(std::string(name) + ": knots must increase strictly (at " + std::to_string(i) + ")");
    }
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

// Direct illuminance (lux) on sensors: points and unit normals (n, 3); split over threads.
nb::object sensor_illuminance(nb::object scene_obj, Rows3 points, Rows3 normals, int samples, uint64_t seed,
                              int width, int threads) {
    SceneHandle& h = nb::cast<SceneHandle&>(scene_obj);
    const size_t n = points.shape(0);
    if (normals.shape(0) != n) throw std::invalid_argument("points and normals have different lengths");
    if (samples < 1) throw std::invalid_argument("samples must be at least 1");
    check_materials(h);
    patina::prepare_light_selection(h.scene);
    float* out;
    auto result = new_array<float, 1>({n}, &out);
    const patina::RenderKernels& k = patina::render_kernels_for(width);
    {
        nb::gil_scoped_release release;
        patina::parallel_for(n, 256, threads, [&](size_t b, size_t e) {
            patina::PathScratch scratch;
            k.sensor_illuminance(h.scene, points.data(), normals.data(), b, e, samples, stream_seed(seed), out,
                                  scratch);
        });
    }
    return nb::cast(result);
}

}  // namespace

void bind_render(nb::module_& m) {
    nb::class_<Grid2Handle>(m, "Grid2", "A 2-D table on an irregular tensor grid, bilinear, clamped to its axes.")
        .def(nb::new_(&make_grid2), nb::arg("x"), nb::arg("y"), nb::arg("values"))
        .def("eval", &grid2_eval, nb::arg("x"), nb::arg("y"), nb::arg("width") = 0,
             "values at (x[i], y[i]) by the coherent search and bilinear interpolation, N points at a time");
    nb::class_<SceneHandle>(m, "RenderScene", "Geometry, materials, lights, environment and camera for RenderJob.")
        .def(nb::new_(&make_scene), nb::arg("accel"), nb::arg("indices"), nb::arg("normals"),
             nb::arg("tangents").none(), nb::arg("tri_material"), nb::arg("camera"))
        .def("add_material", &add_material, nb::arg("material"))
        .def("add_light", &add_light, nb::arg("light"))
        .def("set_environment", &set_environment, nb::arg("rgb").none(), nb::arg("constant"),
             nb::arg("intensity") = 1.0f, nb::arg("rotation") = 0.0f)
        .def_prop_ro("scene_radius", [](const SceneHandle& h) { return h.scene.scene_radius; });
    m.def("sensor_illuminance", &sensor_illuminance, nb::arg("scene"), nb::arg("points"), nb::arg("normals"),
          nb::arg("samples") = 64, nb::arg("seed") = 0, nb::arg("width") = 0, nb::arg("threads") = 0,
          "Direct illuminance in lux on sensors at points facing normals, by shadowed light sampling.");
    nb::class_<JobHandle>(m, "RenderJob", "A render running on worker threads: start, poll progress, cancel, resolve.")
        .def(nb::new_(&make_job), nb::arg("scene"), nb::arg("spp"), nb::arg("max_depth"), nb::arg("seed") = 0,
             nb::arg("threads") = 0, nb::arg("width") = 0, nb::arg("tile_size") = 16, nb::arg("passes") = 8)
        .def("start", [](JobHandle& j) { j.job->start(); })
        .def("cancel", [](JobHandle& j) { j.job->cancel(); })
        .def("wait",
             [](JobHandle& j) {
                 nb::gil_scoped_release release;
                 j.job->wait();
             })
        .def("progress", &progress)
        .def("resolve", &resolve);
}

}  // namespace patina_py
