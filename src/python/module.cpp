// SPDX-License-Identifier: GPL-3.0-or-later
// python/module.cpp -- impactcert._impactcert, the compiled half of the Python module
// (impactcert/__init__.py is the other: exact numbers as fractions.Fraction, reprs, HTML).
//
// Contract: a thin binding of include/impactcert/impactcert.hpp. Exact numbers cross as text
// ("-3/4", GMP's canonical form); the Python layer makes and reads them. Every exact call runs
// with the GIL released; fuzz() takes it back only to call the Python implementation, on a batch
// of points as an (N, n) NumPy array, and expects an (N, n) array of floats back. Errors:
// impactcert.InputError (ValueError), impactcert.LimitError (RuntimeError), both
// impactcert.Error, with the command line's one-line message and exit status (.exit_status).
#include <impactcert/impactcert.hpp>

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstring>
#include <exception>
#include <tuple>

namespace py = pybind11;
namespace ic = impactcert::api;

namespace {

// Exact numbers cross the boundary as hexadecimal text ("-1f/3", GMP's base 16): Python converts
// its ints to and from base 16 without the 4,300-digit limit it puts on decimal text.
ic::Vector vector_of(const std::vector<std::string>& texts) {
    ic::Vector out;
    for (std::size_t i = 0; i < texts.size(); ++i) {
        mpq_class x;
        if (x.set_str(texts[i], 16) != 0 || sgn(x.get_den()) == 0)
            throw ic::InputError("[" + std::to_string(i) + "]: not an exact number from the impactcert package");
        x.canonicalize();
        out.push_back(x);
    }
    return out;
}

std::string text_of(const mpq_class& x) { return x.get_str(16); }

std::vector<std::string> texts_of(const ic::Vector& v) {
    std::vector<std::string> out;
    for (const auto& x : v)
        out.push_back(text_of(x));
    return out;
}

// A fuzz run of a Python implementation: run(call) without the GIL, where call takes it back to
// hand the implementation an (N, dim) array; its report's JSON, or the first exception (the
// implementation's own, or a wrong shape) raised again with the GIL held.
template <class Run>
std::string run_batches(const py::function& implementation, std::size_t dim, Run run) {
    const ic::BatchFunction call = [&implementation, dim](const double* in, double* out, std::size_t count) {
        py::gil_scoped_acquire gil;
        py::array_t<double> points({count, dim});
        std::memcpy(points.mutable_data(), in, count * dim * sizeof(double));
        py::object answer = implementation(points);
        // Real numbers only: a complex array would be cut to its real part by the conversion.
        if (py::isinstance<py::array>(answer) && py::array(answer).dtype().kind() == 'c')
            throw ic::InputError("the implementation returned complex numbers; expected an array of floats of shape (" +
                                 std::to_string(count) + ", " + std::to_string(dim) + ")");
        auto values = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(answer);
        if (!values || values.ndim() != 2 || static_cast<std::size_t>(values.shape(0)) != count ||
            static_cast<std::size_t>(values.shape(1)) != dim)
            throw ic::InputError("the implementation must return an array of shape (" + std::to_string(count) + ", " +
                                 std::to_string(dim) + ") for an input of that shape");
        std::memcpy(out, values.data(), count * dim * sizeof(double));
    };
    std::exception_ptr failure;
    ic::FuzzResult r;
    {
        py::gil_scoped_release release;
        try {
            r = run(call);
        } catch (...) {
            failure = std::current_exception();
        }
    }
    if (failure)
        std::rethrow_exception(failure);
    return r.json;
}

} // namespace

PYBIND11_MODULE(_impactcert, m) {
    m.doc() = "impactcert's C++ library (use the impactcert package, not this module)";
    m.def("version", &ic::version);
    // A number in the command line's grammar (p/q, decimals, exponents, hex floats), as hex text.
    m.def("_parse_exact", [](const std::string& text, const std::string& where) {
        return text_of(ic::parse_exact(text, where));
    });

    // The library's errors as impactcert.InputError / LimitError / Error (defined in Python, so
    // that InputError is also a ValueError and LimitError a RuntimeError), with .exit_status.
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p)
                std::rethrow_exception(p);
        } catch (const ic::Error& e) {
            const char* kind = dynamic_cast<const ic::InputError*>(&e)   ? "InputError"
                               : dynamic_cast<const ic::LimitError*>(&e) ? "LimitError"
                                                                         : "Error";
            const py::object type = py::module_::import("impactcert").attr(kind);
            const py::object err = type(e.what());
            err.attr("exit_status") = e.exit_status();
            PyErr_SetObject(type.ptr(), err.ptr());
        }
    });

    py::class_<ic::System>(m, "System")
        .def_static("chain", [](const std::vector<std::string>& masses, const std::string& walls) {
            return ic::System::chain(vector_of(masses), walls);
        }, py::arg("masses"), py::arg("walls") = "none", py::call_guard<py::gil_scoped_release>())
        .def_static("read", &ic::System::read, py::arg("path"), py::call_guard<py::gil_scoped_release>())
        .def_static("parse", &ic::System::parse, py::arg("text"), py::arg("origin") = "system",
                    py::call_guard<py::gil_scoped_release>())
        .def_property_readonly("velocities", &ic::System::velocities)
        .def_property_readonly("contacts", &ic::System::contacts)
        .def_property_readonly("friction", &ic::System::friction)
        .def("describe", &ic::System::describe);

    py::class_<ic::Law>(m, "Law")
        .def_static("read", [](const std::string& path, std::size_t max_pieces, std::size_t max_memory_mb) {
            return ic::Law::read(path, ic::LawLimits{max_pieces, max_memory_mb});
        }, py::arg("path"), py::arg("max_pieces") = ic::LawLimits{}.max_pieces,
           py::arg("max_memory_mb") = ic::LawLimits{}.max_memory_mb, py::call_guard<py::gil_scoped_release>())
        .def_static("parse", [](const std::string& text, const std::string& origin, std::size_t max_pieces,
                                std::size_t max_memory_mb) {
            return ic::Law::parse(text, origin, ic::LawLimits{max_pieces, max_memory_mb});
        }, py::arg("text"), py::arg("origin") = "law", py::arg("max_pieces") = ic::LawLimits{}.max_pieces,
           py::arg("max_memory_mb") = ic::LawLimits{}.max_memory_mb, py::call_guard<py::gil_scoped_release>())
        .def_static("paper", &ic::Law::paper)
        .def_property_readonly("name", &ic::Law::name)
        .def_property_readonly("contacts", &ic::Law::contacts)
        .def_property_readonly("velocities", &ic::Law::velocities)
        .def_property_readonly("pieces", &ic::Law::pieces)
        .def("piece_names", &ic::Law::piece_names)
        .def("figure_svg", &ic::Law::figure_svg, py::call_guard<py::gil_scoped_release>())
        .def("to_json", &ic::Law::to_json)
        .def("write", &ic::Law::write, py::arg("path"), py::call_guard<py::gil_scoped_release>())
        .def("_evaluate", [](const ic::Law& law, const std::vector<std::string>& gamma) {
            std::vector<std::vector<std::string>> out;
            for (const auto& v : law.evaluate(vector_of(gamma)))
                out.push_back(texts_of(v));
            return out;
        }, py::call_guard<py::gil_scoped_release>())
        .def("_energy", [](const ic::Law& law, const std::vector<std::string>& gamma) {
            return text_of(law.energy(vector_of(gamma)));
        }, py::call_guard<py::gil_scoped_release>())
        .def("_pieces_at", [](const ic::Law& law, const std::vector<std::string>& gamma) {
            return law.pieces_at(vector_of(gamma));
        }, py::call_guard<py::gil_scoped_release>());

    m.def("_derive", [](const ic::System& system, const std::string& kind, const std::vector<std::string>& restitution,
                        const std::string& rule, std::size_t max_impacts, std::size_t max_bits, std::size_t max_memory_mb) {
        ic::DeriveOptions o;
        if (kind == "sequential")
            o.kind = ic::LawKind::sequential;
        else if (kind == "newton")
            o.kind = ic::LawKind::newton;
        else if (kind == "poisson")
            o.kind = ic::LawKind::poisson;
        else
            throw ic::InputError("kind: expected sequential, newton or poisson, got \"" + kind + "\"");
        o.restitution = vector_of(restitution);
        o.rule = rule;
        o.max_impacts = max_impacts;
        o.max_bits = max_bits;
        o.max_memory_mb = max_memory_mb;
        const ic::Derivation d = ic::derive(system, o);
        // C++ values: cast to Python after the call, with the GIL taken back.
        return std::make_tuple(d.law, d.refutation, d.witness);
    }, py::call_guard<py::gil_scoped_release>());

    auto verify_options = [](std::size_t max_pieces, std::size_t max_memory_mb, unsigned jobs) {
        ic::VerifyOptions o;
        o.max_pieces = max_pieces;
        o.max_memory_mb = max_memory_mb;
        o.jobs = jobs;
        return o;
    };
    py::class_<ic::Obligation>(m, "Obligation")
        .def_readonly("id", &ic::Obligation::id)
        .def_readonly("claimed", &ic::Obligation::claimed)
        .def_readonly("verdict", &ic::Obligation::verdict)
        .def_readonly("checks", &ic::Obligation::checks)
        .def_readonly("method", &ic::Obligation::method)
        .def_readonly("limit", &ic::Obligation::limit)
        .def_readonly("counterexample", &ic::Obligation::counterexample);
    py::class_<ic::Report>(m, "Report")
        .def_readonly("law", &ic::Report::law)
        .def_readonly("verdict", &ic::Report::verdict)
        .def_readonly("exit_status", &ic::Report::exit_status)
        .def_readonly("obligations", &ic::Report::obligations)
        .def_readonly("json", &ic::Report::json);
    m.def("_verify", [verify_options](const ic::Law& law, std::size_t max_pieces, std::size_t max_memory_mb, unsigned jobs) {
        return ic::verify(law, verify_options(max_pieces, max_memory_mb, jobs));
    }, py::call_guard<py::gil_scoped_release>());
    m.def("_certify", [verify_options](const ic::Law& law, std::size_t max_pieces, std::size_t max_memory_mb, unsigned jobs) {
        return ic::certify(law, verify_options(max_pieces, max_memory_mb, jobs));
    }, py::call_guard<py::gil_scoped_release>());
    m.def("_check_certificate", [](const std::string& text) {
        const ic::CheckResult r = ic::check_certificate(text);
        return std::make_tuple(r.exit_status, r.message);
    }, py::call_guard<py::gil_scoped_release>());

    m.def("_fuzz", [](const ic::Law& law, py::function implementation, std::uint64_t seed, std::uint64_t samples,
                      double seconds, std::optional<std::uint64_t> max_ulps, std::optional<double> max_rel_error,
                      bool velocities, const std::string& range, bool allow_extreme, const std::string& name,
                      std::size_t batch) {
        ic::FuzzOptions o;
        o.seed = seed;
        o.samples = samples;
        o.seconds = seconds;
        o.max_ulps = max_ulps;
        o.max_rel_error = max_rel_error;
        o.velocities = velocities;
        o.range = range;
        o.allow_extreme = allow_extreme;
        o.name = name;
        o.batch = batch;
        const std::size_t dim = velocities ? law.velocities() : law.contacts();
        return run_batches(implementation, dim, [&](const ic::BatchFunction& call) { return ic::fuzz(law, call, o); });
    });
    m.def("_fuzz_consistency", [](const ic::System& system, py::function implementation, std::uint64_t seed,
                                  std::uint64_t samples, double seconds, double max_rel_error, bool velocities,
                                  std::optional<std::vector<std::string>> restitution, const std::string& reference,
                                  const std::vector<std::string>& require, const std::string& range,
                                  const std::string& name, std::size_t batch) {
        ic::ConsistencyOptions o;
        o.seed = seed;
        o.samples = samples;
        o.seconds = seconds;
        o.max_rel_error = max_rel_error;
        o.velocities = velocities;
        if (restitution)
            o.restitution = vector_of(*restitution);
        o.reference = reference;
        o.require = require;
        o.range = range;
        o.name = name;
        o.batch = batch;
        const std::size_t dim = velocities ? system.velocities() : system.contacts();
        return run_batches(implementation, dim,
                           [&](const ic::BatchFunction& call) { return ic::fuzz_consistency(system, call, o); });
    });
}
