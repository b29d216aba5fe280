// patina._core.Table: a tabulated BRDF, its readers/writers and its batch evaluator.
#include <nanobind/stl/string.h>
#include <nanobind/stl/unique_ptr.h>
#include <nanobind/stl/vector.h>

#include <memory>
#include <stdexcept>
#include <string>

#include "bindings.h"
#include "brdf/kernels.h"
#include "brdf/merl.h"
#include "brdf/ptab.h"
#include "brdf/table.h"

namespace nb = nanobind;

namespace patina_py {
namespace {

template <class E>
E parse_enum(const std::string& s, std::initializer_list<const char*> names, const char* what) {
    int i = 0;
    for (const char* n : names) {
        if (s == n) return static_cast<E>(i);
        ++i;
    }
    throw std::invalid_argument(std::string("unknown ") + what + " '" + s + "'");
}

using FloatVector = nb::ndarray<const float, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using FloatAny = nb::ndarray<const float, nb::c_contig, nb::device::cpu>;
using ByteAny = nb::ndarray<const uint8_t, nb::c_contig, nb::device::cpu>;
using Directions = nb::ndarray<const float, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;

std::unique_ptr<TableHandle> from_arrays(const std::string& parametrization, const std::vector<FloatVector>& axes,
                                         FloatAny values, int channels, const std::string& channel_kind,
                                         nb::object wavelengths, nb::object valid, uint32_t symmetry,
                                         const std::string& units, const std::string& provenance) {
    patina::Table t;
    t.parametrization =
        parse_enum<patina::Parametrization>(parametrization, {"isotropic", "anisotropic", "halfdiff"}, "parametrization");
    t.channel_kind = parse_enum<patina::ChannelKind>(channel_kind, {"mono", "rgb", "xyz", "spectral"}, "channel kind");
    t.symmetry = symmetry;
    t.channels = channels;
    for (const auto& a : axes) t.axes.emplace_back(a.data(), a.data() + a.shape(0));
    t.values.assign(values.data(), values.data() + values.size());
    if (!wavelengths.is_none()) {
        auto w = nb::cast<FloatVector>(wavelengths);
        t.wavelengths.assign(w.data(), w.data() + w.shape(0));
    }
    if (!valid.is_none()) {
        auto v = nb::cast<ByteAny>(valid);
        t.valid.assign(v.data(), v.data() + v.size());
        for (size_t j = 0; j < t.valid.size(); ++j)
            if (!t.valid[j]) {
                for (int c = 0; c < channels && j * channels + c < t.values.size(); ++c) t.values[j * channels + c] = 0.0f;
            }
        if (t.missing_count() == 0) t.valid.clear();
    }
    t.units = units;
    t.provenance = provenance;
    return std::make_unique<TableHandle>(std::move(t));
}

using Output = nb::ndarray<float, nb::ndim<2>, nb::c_contig, nb::device::cpu>;

// Writes into `out` when given (no allocation: what benchmarks and renderers want).
nb::object eval(const TableHandle& h, Directions wi, Directions wo, int width, int threads, nb::object out_obj,
                bool libm_trig) {
    const size_t n = wi.shape(0);
    if (wo.shape(0) != n) throw std::invalid_argument("wi and wo have different numbers of rows");
    const size_t shape[2] = {n, static_cast<size_t>(h.table.channels)};
    float* out;
    nb::object result;
    if (out_obj.is_none()) {
        result = nb::cast(new_array<float, 2>(shape, &out));
    } else {
        auto o = nb::cast<Output>(out_obj);
        if (o.shape(0) != shape[0] || o.shape(1) != shape[1])
            throw std::invalid_argument("out must be a C-contiguous float32 array of shape (n, channels)");
        out = o.data();
        result = out_obj;
    }
    const patina::TableView& view = h.prepared.view;
    {
        nb::gil_scoped_release release;
        patina::eval_batch(view, wi.data(), wo.data(), out, n, width, threads, libm_trig);
    }
    return result;
}

nb::object values_array(const TableHandle& h) {
    const patina::Table& t = h.table;
    std::vector<size_t> shape;
    for (const auto& a : t.axes) shape.push_back(a.size());
    shape.push_back(static_cast<size_t>(t.channels));
    float* copy = new float[t.values.size()];
    std::copy(t.values.begin(), t.values.end(), copy);
    nb::capsule owner(copy, [](void* p) noexcept { delete[] static_cast<float*>(p); });
    return nb::cast(nb::ndarray<nb::numpy, float>(copy, shape.size(), shape.data(), owner));
}

nb::object valid_array(const TableHandle& h) {
    const patina::Table& t = h.table;
    if (t.valid.empty()) return nb::none();
    std::vector<size_t> shape;
    for (const auto& a : t.axes) shape.push_back(a.size());
    uint8_t* copy = new uint8_t[t.valid.size()];
    std::copy(t.valid.begin(), t.valid.end(), copy);
    nb::capsule owner(copy, [](void* p) noexcept { delete[] static_cast<uint8_t*>(p); });
    return nb::cast(nb::ndarray<nb::numpy, uint8_t>(copy, shape.size(), shape.data(), owner));
}

}  // namespace

void bind_table(nb::module_& m) {
    m.attr("SYM_RECIPROCITY") = static_cast<uint32_t>(patina::kSymReciprocity);
    m.attr("SYM_PHI_MIRROR") = static_cast<uint32_t>(patina::kSymPhiMirror);

    nb::class_<TableHandle>(m, "Table", "A tabulated BRDF on an irregular tensor grid (immutable).")
        .def_static("from_arrays", &from_arrays, nb::arg("parametrization"), nb::arg("axes"), nb::arg("values"),
                    nb::arg("channels"), nb::arg("channel_kind"), nb::arg("wavelengths") = nb::none(),
                    nb::arg("valid") = nb::none(), nb::arg("symmetry") = 0, nb::arg("units") = "1/sr",
                    nb::arg("provenance") = "",
                    "Builds a table from float32 arrays (values: grid points x channels, C order); "
                    "raises ValueError naming the first problem.")
        .def_prop_ro("parametrization",
                     [](const TableHandle& h) { return std::string(patina::parametrization_name(h.table.parametrization)); })
        .def_prop_ro("channel_kind",
                     [](const TableHandle& h) { return std::string(patina::channel_kind_name(h.table.channel_kind)); })
        .def_prop_ro("symmetry", [](const TableHandle& h) { return h.table.symmetry; })
        .def_prop_ro("channels", [](const TableHandle& h) { return h.table.channels; })
        .def_prop_ro("axis_names",
                     [](const TableHandle& h) {
                         std::vector<std::string> names;
                         for (int a = 0; a < patina::axis_count(h.table.parametrization); ++a)
                             names.emplace_back(patina::axis_name(h.table.parametrization, a));
                         return names;
                     })
        .def_prop_ro("axes",
                     [](const TableHandle& h) {
                         nb::list out;
                         for (const auto& a : h.table.axes) out.append(copy_vector(a.data(), a.size()));
                         return out;
                     })
        .def_prop_ro("wavelengths",
                     [](const TableHandle& h) -> nb::object {
                         if (h.table.wavelengths.empty()) return nb::none();
                         return nb::cast(copy_vector(h.table.wavelengths.data(), h.table.wavelengths.size()));
                     })
        .def_prop_ro("values", &values_array, "A copy of the values, shape (*axis lengths, channels).")
        .def_prop_ro("valid", &valid_array, "Per grid point, 1 where measured and 0 where missing; None if complete.")
        .def_prop_ro("units", [](const TableHandle& h) { return h.table.units; })
        .def_prop_ro("provenance", [](const TableHandle& h) { return h.table.provenance; })
        .def_prop_ro("point_count", [](const TableHandle& h) { return h.table.point_count(); })
        .def_prop_ro("missing_count", [](const TableHandle& h) { return h.table.missing_count(); })
        .def("eval", &eval, nb::arg("wi"), nb::arg("wo"), nb::arg("width") = 0, nb::arg("threads") = 0,
             nb::arg("out") = nb::none(), nb::arg("libm_trig") = false,
             "Evaluates (n, 3) float32 local-frame directions; returns (n, channels) float32. "
             "libm_trig=True runs the scalar evaluator with the C library's acos/atan2 (a benchmark baseline).");

    m.def("read_ptab", [](const std::string& path) { return std::make_unique<TableHandle>(patina::read_ptab(path)); },
          nb::arg("path"));
    m.def("write_ptab", [](const TableHandle& h, const std::string& path) { patina::write_ptab(h.table, path); },
          nb::arg("table"), nb::arg("path"));
    m.def("read_merl", [](const std::string& path) { return std::make_unique<TableHandle>(patina::read_merl(path)); },
          nb::arg("path"));
}

}  // namespace patina_py
