// patina._core.DirectSources and patina._core.direct_illuminance: the lighting calculations'
// exact direct illuminance (render/lighting/direct_illuminance.h). The Python side
// (python/patina/lighting/direct.py) places the luminaires; here values are only converted and
// checked, with std::invalid_argument (ValueError) naming the luminaire or the argument.
#include <nanobind/stl/array.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/unique_ptr.h>

#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bindings.h"
#include "render/lighting/direct_illuminance.h"

namespace nb = nanobind;

namespace patina_py {
namespace {

using Rows3 = nb::ndarray<const float, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;
using Vector3 = std::array<float, 3>;

// The luminaires of one calculation, and the candela tables their views point into.
struct SourcesHandle {
    std::vector<patina::DirectSource> sources;
    std::vector<nb::object> keep;

    // "luminaire <index>: <problem>" for the luminaire being added
    [[noreturn]] void fail(const std::string& problem) const {
        throw std::invalid_argument("luminaire " + std::to_string(sources.size()) + ": " + problem);
    }
    void copy(const char* name, const Vector3& v, float* out, bool unit) const {
        for (int a = 0; a < 3; ++a) {
            if (!std::isfinite(v[a])) fail(std::string("'") + name + "' is not finite");
            out[a] = v[a];
        }
        const float length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (unit && !(std::fabs(length - 1.0f) < 1e-4f)) fail(std::string("'") + name + "' is not a unit vector");
    }
    patina::DirectSource placed(patina::SourceKind kind, const Vector3& position, float scale) const {
        if (!(scale >= 0.0f) || !std::isfinite(scale)) fail("candela scale must be finite and >= 0");
        patina::DirectSource s;
        s.kind = kind;
        copy("position", position, s.position, false);
        s.scale = scale;
        return s;
    }
    int add(const patina::DirectSource& s) {
        sources.push_back(s);
        return static_cast<int>(sources.size()) - 1;
    }
};

int add_point(SourcesHandle& h, const Vector3& position, float candela) {
    return h.add(h.placed(patina::SourceKind::Point, position, candela));
}

int add_spot(SourcesHandle& h, const Vector3& position, float candela, const Vector3& axis, float cos_inner,
             float cos_outer) {
    patina::DirectSource s = h.placed(patina::SourceKind::Spot, position, candela);
    h.copy("axis", axis, s.spot.direction, true);
    if (!(cos_inner >= -1.0f && cos_inner <= 1.0f) || !(cos_outer >= -1.0f && cos_outer <= 1.0f))
        h.fail("the cone's cosines must lie in [-1, 1]");
    s.spot.cos_inner = cos_inner;
    s.spot.cos_outer = cos_outer;
    return h.add(s);
}

int add_goniometric(SourcesHandle& h, const Vector3& position, float scale, const Vector3& axis_x,
                    const Vector3& axis_y, const Vector3& axis_z, bool type_b, nb::object table) {
    patina::DirectSource s = h.placed(patina::SourceKind::Goniometric, position, scale);
    h.copy("axis_x", axis_x, s.goniometric.axis_x, true);
    h.copy("axis_y", axis_y, s.goniometric.axis_y, true);
    h.copy("axis_z", axis_z, s.goniometric.axis_z, true);
    s.goniometric.type_b = type_b;
    const Grid2Handle* g = nullptr;
    if (!nb::try_cast<const Grid2Handle*>(table, g) || g == nullptr) h.fail("'candela' must be a patina._core.Grid2");
    s.goniometric.candela = g->view();
    h.keep.push_back(table);
    return h.add(s);
}

patina::SensorKind sensor_kind(const std::string& name) {
    if (name == "planar") return patina::SensorKind::Planar;
    if (name == "cylindrical") return patina::SensorKind::Cylindrical;
    if (name == "semicylindrical") return patina::SensorKind::SemiCylindrical;
    throw std::invalid_argument("sensor '" + name + "': one of planar, cylindrical, semicylindrical");
}

void check_rows(const Rows3& rows, size_t n, const char* name) {
    if (rows.shape(0) != n) throw std::invalid_argument(std::string(name) + " must hold one row per point");
    for (size_t i = 0; i < 3 * n; ++i)
        if (!std::isfinite(rows.data()[i]))
            throw std::invalid_argument(std::string(name) + " row " + std::to_string(i / 3) + " is not finite");
}

nb::object direct_illuminance(const SourcesHandle& h, Rows3 points, nb::object normals, const std::string& sensor,
                              nb::object accel, float ray_offset, bool per_source, int width, int threads) {
    patina::IlluminanceSensors sensors;
    sensors.kind = sensor_kind(sensor);
    sensors.count = points.shape(0);
    check_rows(points, sensors.count, "points");
    sensors.points = points.data();
    Rows3 normal_rows;  // a converted copy lives as long as this
    if (!normals.is_none()) {
        normal_rows = nb::cast<Rows3>(normals);
        check_rows(normal_rows, sensors.count, "normals");
        sensors.normals = normal_rows.data();
    } else if (sensors.kind != patina::SensorKind::Cylindrical) {
        throw std::invalid_argument("normals are needed for " + sensor + " sensors");
    }
    if (!(ray_offset >= 0.0f) || !std::isfinite(ray_offset))
        throw std::invalid_argument("ray_offset must be finite and >= 0");
    patina::DirectLighting lighting{h.sources.data(), h.sources.size(), nullptr, ray_offset};
    if (!accel.is_none()) lighting.occluders = &bvh_of(nb::cast<Accel&>(accel));  // built once, on first use
    float *lux, *terms = nullptr;
    auto sums = new_array<float, 1>({sensors.count}, &lux);
    nb::object result = nb::cast(sums);
    if (per_source) {
        const size_t shape[2] = {h.sources.size(), sensors.count};
        result = nb::cast(new_array<float, 2>(shape, &terms));
    }
    {
        nb::gil_scoped_release release;
        patina::direct_illuminance(lighting, sensors, lux, terms, width, threads);
    }
    return result;
}

}  // namespace

void bind_lighting(nb::module_& m) {
    nb::class_<SourcesHandle>(m, "DirectSources",
                              "Point, spot and goniometric luminaires for direct_illuminance, in candela.")
        .def(nb::init<>())
        .def("add_point", &add_point, nb::arg("position"), nb::arg("candela"), "a point of constant candela")
        .def("add_spot", &add_spot, nb::arg("position"), nb::arg("candela"), nb::arg("axis"), nb::arg("cos_inner"),
             nb::arg("cos_outer"),
             "candela x the renderer's smoothstep cone about the unit axis, from 0 at cos_outer to 1 at cos_inner")
        .def("add_goniometric", &add_goniometric, nb::arg("position"), nb::arg("scale"), nb::arg("axis_x"),
             nb::arg("axis_y"), nb::arg("axis_z"), nb::arg("type_b"), nb::arg("candela"),
             "scale x the candela table (a Grid2 over (C, gamma), or (H, V) with type_b, radians) in the frame of "
             "the unit axes, as the renderer's goniometric light")
        .def("__len__", [](const SourcesHandle& h) { return h.sources.size(); });
    m.def("direct_illuminance", &direct_illuminance, nb::arg("sources"), nb::arg("points"),
          nb::arg("normals").none(), nb::arg("sensor") = "planar", nb::arg("accel").none() = nb::none(),
          nb::arg("ray_offset") = 1e-4f, nb::arg("per_source") = false, nb::arg("width") = 0, nb::arg("threads") = 0,
          "Exact direct illuminance in lux at float32 points (n, 3): the sum over the sources of candela x the "
          "sensor's response / d^2, each term kept if one shadow ray through accel (None: no shadows) from "
          "ray_offset to just short of the source is clear. sensor: planar (normals), cylindrical (normals "
          "unread, may be None) or semicylindrical (normals: the horizontal facings). (n,), or (sources, n) "
          "with per_source. The same bits at every width and thread count.");
}

}  // namespace patina_py
