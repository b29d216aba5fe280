// patina._core: the C++ engine as seen from Python. Arrays cross without copies
// where the layout allows; long computations release the GIL.
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <stdexcept>
#include <string>

#include "bindings.h"
#include "brdf/kernels.h"
#include "core/cpu.h"
#include "core/errors.h"

namespace nb = nanobind;
using namespace patina_py;

namespace {

using FloatVector = nb::ndarray<const float, nb::ndim<1>, nb::c_contig, nb::device::cpu>;

patina::MathOp math_op(const std::string& name) {
    using patina::MathOp;
    if (name == "acos") return MathOp::Acos;
    if (name == "asin") return MathOp::Asin;
    if (name == "atan") return MathOp::Atan;
    if (name == "atan2") return MathOp::Atan2;
    if (name == "sqrt") return MathOp::Sqrt;
    if (name == "rcp") return MathOp::Rcp;
    if (name == "rsqrt") return MathOp::Rsqrt;
    if (name == "libc_acos") return MathOp::LibcAcos;
    if (name == "libc_atan2") return MathOp::LibcAtan2;
    throw std::invalid_argument("unknown math op '" + name + "'");
}

using FloatOut = nb::ndarray<float, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using IntOut = nb::ndarray<int32_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;

// `out`, when given, receives the results (no allocation, for benchmarks).
template <class Out, class T>
nb::object output(nb::object out_obj, size_t n, T** data) {
    if (out_obj.is_none()) return nb::cast(new_array<T, 1>({n}, data));
    auto o = nb::cast<Out>(out_obj);
    if (o.shape(0) != n) throw std::invalid_argument("out has the wrong length");
    *data = o.data();
    return out_obj;
}

nb::object math(const std::string& op_name, FloatVector a, nb::object b_obj, int width, nb::object out_obj) {
    const patina::MathOp op = math_op(op_name);
    const bool binary = op == patina::MathOp::Atan2 || op == patina::MathOp::LibcAtan2;
    const float* b = nullptr;
    FloatVector b_arr;
    if (binary) {
        if (b_obj.is_none()) throw std::invalid_argument(op_name + " needs two arguments");
        b_arr = nb::cast<FloatVector>(b_obj);
        if (b_arr.shape(0) != a.shape(0)) throw std::invalid_argument("arguments have different lengths");
        b = b_arr.data();
    }
    const patina::Kernels& k = patina::kernels_for(width);
    const size_t n = a.shape(0);
    float* out;
    nb::object result = output<FloatOut>(out_obj, n, &out);
    {
        nb::gil_scoped_release release;
        k.math(op, a.data(), b, out, n);
    }
    return result;
}

nb::object search(FloatVector knots, FloatVector x, int width, nb::object out_obj, const std::string& split) {
    if (split != "masked" && split != "sequential")
        throw std::invalid_argument("split='" + split + "': expected 'masked' or 'sequential'");
    const size_t count = knots.shape(0);
    if (count < 2) throw std::invalid_argument("an axis needs at least 2 knots");
    for (size_t j = 1; j < count; ++j)
        if (!(knots.data()[j] > knots.data()[j - 1]))
            throw std::invalid_argument("knots are not strictly increasing at " + std::to_string(j));
    const patina::Kernels& k = patina::kernels_for(width);
    const size_t n = x.shape(0);
    int32_t* out;
    nb::object result = output<IntOut>(out_obj, n, &out);
    {
        nb::gil_scoped_release release;
        (split == "masked" ? k.search : k.search_thesis)(knots.data(), static_cast<int>(count), x.data(), out, n);
    }
    return result;
}

}  // namespace

NB_MODULE(_core, m) {
    m.doc() = "Patina's C++ engine: SIMD kernels, tabulated BRDFs, native formats";
    m.attr("__version__") = PATINA_VERSION;

    nb::register_exception_translator([](const std::exception_ptr& p, void*) {
        try {
            std::rethrow_exception(p);
        } catch (const patina::FormatError& e) {
            nb::object cls = nb::module_::import_("patina.errors").attr("FormatError");
            nb::object instance = cls(e.path, e.where, e.problem);
            PyErr_SetObject(cls.ptr(), instance.ptr());
        }
    });

    m.def("width_supported", &patina::width_supported, nb::arg("width"),
          "True if kernels of this SIMD width (1, 4, 8, 16) can run on this CPU.");
    m.def("default_width", &patina::default_width,
          "The SIMD width used when none is asked for (PATINA_SIMD or the widest supported).");
    m.def("math", &math, nb::arg("op"), nb::arg("a"), nb::arg("b") = nb::none(), nb::arg("width") = 0, nb::arg("out") = nb::none(),
          "Applies a fast-math op (acos, asin, atan, atan2, sqrt, rcp, rsqrt; libc_acos, libc_atan2 "
          "for the C library baseline) to float32 arrays at the given SIMD width (0 = default).");
    m.def("search", &search, nb::arg("knots"), nb::arg("x"), nb::arg("width") = 0, nb::arg("out") = nb::none(),
          nb::arg("split") = "masked",
          "Coherent binary search: the cell index of each x on the knot axis. split='sequential' walks "
          "diverging lanes one branch after the other, as the thesis does; 'masked' (default) all at once.");

    bind_table(m);
    bind_rgl(m);
    bind_accel(m);
    bind_fit(m);
    bind_render(m);
    bind_lighting(m);
    bind_render_job(m);
    bind_cache_probe(m);
}
