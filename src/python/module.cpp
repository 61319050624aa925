// The Python module `liftoff._liftoff` (pybind11): solve, trace and sweep as the CLI runs them.
//
// Thin on purpose: a scene is read by the scene reader (a file, TOML text, or a dict written out
// as TOML text), checked by the theory gate, and solved by app::solve_scene / run_trace /
// run_sweep, the functions `liftoff solve|trace|sweep` call; the results' keys are io::to_json's
// (the CLI's --json), their arrays views of the report's vectors. The GIL is released while the
// library works. Every library error becomes the Python exception of its kind (liftoff.InputError,
// MechanismError, SolverFailure, UnstableEquilibrium, OutputError) with the CLI's one-line message.

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <toml++/toml.h>

#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "app/solve_command.hpp"
#include "app/sweep_command.hpp"
#include "app/theory_gate.hpp"
#include "app/trace_command.hpp"
#include "core/error.hpp"
#include "io/hdf5_writer.hpp"
#include "io/report.hpp"
#include "model/from_scene.hpp"
#include "scene/scene_reader.hpp"

namespace py = pybind11;

namespace liftoff::python {

namespace {

py::object to_python(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

// ---- the scene ------------------------------------------------------------------------------

// A dict's value as TOML, handed to `put` (its concrete toml++ type); `key` (dotted) names it in
// the error. Tables and arrays recurse through the plain functions below, so that `put` has two
// types only.
toml::table toml_table(const py::dict& dict, const std::string& prefix);
toml::array toml_array(py::handle list, const std::string& key);

template <class Put>
void toml_value(py::handle value, const std::string& key, Put&& put) {
  if (py::isinstance<py::bool_>(value)) return put(value.cast<bool>());
  if (py::isinstance<py::int_>(value)) return put(value.cast<int64_t>());
  if (py::isinstance<py::float_>(value)) return put(value.cast<double>());
  if (py::isinstance<py::str>(value)) return put(value.cast<std::string>());
  if (py::isinstance<py::dict>(value)) return put(toml_table(value.cast<py::dict>(), key + "."));
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) return put(toml_array(value, key));
  // numpy scalars: integers have __index__, reals __float__
  if (py::hasattr(value, "__index__")) return put(value.attr("__index__")().cast<int64_t>());
  if (py::hasattr(value, "__float__")) return put(value.attr("__float__")().cast<double>());
  throw InputError(fmt::format("scene dict: key '{}': expected a number, string, bool, dict or list, got {}", key,
                               py::str(py::type::of(value)).cast<std::string>()));
}

toml::table toml_table(const py::dict& dict, const std::string& prefix) {
  toml::table table;
  for (const auto& [k, v] : dict) {
    if (!py::isinstance<py::str>(k))
      throw InputError(fmt::format("scene dict: key '{}{}': expected a string key, got {}", prefix,
                                   py::str(k).cast<std::string>(), py::str(py::type::of(k)).cast<std::string>()));
    const std::string name = k.cast<std::string>();
    toml_value(v, prefix + name, [&](auto&& node) { table.insert(name, std::forward<decltype(node)>(node)); });
  }
  return table;
}

toml::array toml_array(py::handle list, const std::string& key) {
  toml::array array;
  int i = 0;
  for (py::handle item : list)
    toml_value(item, fmt::format("{}[{}]", key, i++),
               [&](auto&& node) { array.push_back(std::forward<decltype(node)>(node)); });
  return array;
}

// A TOML file path (str or os.PathLike), TOML text (a str with a newline or '='), or a dict with
// the keys of a scene file.
scene::Scene read_scene(py::handle source) {
  if (py::isinstance<py::dict>(source)) {
    std::ostringstream text;
    text << toml_table(source.cast<py::dict>(), "");
    return scene::parse_scene(text.str(), "scene dict");
  }
  const bool path_like = !py::isinstance<py::str>(source) && py::hasattr(source, "__fspath__");
  if (!path_like && !py::isinstance<py::str>(source))
    throw InputError(fmt::format("scene: expected a TOML file path, TOML text or a dict, got {}",
                                 py::str(py::type::of(source)).cast<std::string>()));
  const std::string text = py::module_::import("os").attr("fspath")(source).cast<std::string>();
  if (!path_like && text.find_first_of("\n=") != std::string::npos) return scene::parse_scene(text, "scene string");
  return scene::read_scene_file(text);
}

// ---- the options: what the CLI's options give, checked as CLI11 and make_request check them --

std::optional<scene::Method> method_option(const std::optional<std::string>& method) {
  if (!method) return std::nullopt;
  const auto m = scene::parse_method(*method);
  if (!m) throw InputError(fmt::format("method: expected dual, primal, fast, auto, ritz or all, got '{}'", *method));
  return m;
}

std::optional<int> elements_option(const std::optional<int>& elements) {
  if (elements && (*elements < 1 || *elements > 10'000'000))
    throw InputError(fmt::format("elements: expected an integer in [1, 10000000], got {}", *elements));
  return elements;
}

std::optional<int> modes_option(const py::object& modes) {
  if (modes.is_none()) return std::nullopt;
  if (py::isinstance<py::str>(modes) && modes.cast<std::string>() == "auto") return 0;
  if (py::isinstance<py::int_>(modes) && !py::isinstance<py::bool_>(modes)) {
    const long n = modes.cast<long>();
    if (n >= 1 && n <= 1000) return static_cast<int>(n);
  }
  throw InputError(
      fmt::format("modes: expected \"auto\" or an integer in [1, 1000], got {}", py::repr(modes).cast<std::string>()));
}

app::SolveRequest solve_request(const std::optional<std::string>& method, const std::optional<double>& tolerance,
                                const std::optional<int>& elements, const py::object& modes, bool fields) {
  app::SolveRequest request;
  request.method = method_option(method);
  request.elements = elements_option(elements);
  request.modes = modes_option(modes);
  if (tolerance && !(*tolerance >= scene::min_tolerance && *tolerance <= scene::max_tolerance))
    throw InputError(fmt::format(
        "tolerance: expected a number in [{:g}, {:g}] (the contact limits' accuracy relative to the length; below "
        "{:g} double precision cannot honour it), got {}",
        scene::min_tolerance, scene::max_tolerance, scene::min_tolerance, *tolerance));
  request.tolerance = tolerance;
  request.fields = fields;
  return request;
}

// ---- results --------------------------------------------------------------------------------

// A read-only array over `count` doubles from `first`, `stride` bytes apart, kept alive by `owner`.
py::array view(const double* first, std::size_t count, std::size_t stride, py::handle owner) {
  if (count == 0) return py::array_t<double>(0);
  py::array a(py::dtype::of<double>(), {count}, {stride}, first, owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}
py::array view(const std::vector<double>& v, py::handle owner) {
  return view(v.data(), v.size(), sizeof(double), owner);
}

struct SolveResult {
  std::shared_ptr<const io::SolveReport> report;
  py::object json;  // io::to_json(report) as Python objects, made on first use
  const io::SolveReport& r() const { return *report; }
  py::object keys() {
    if (json.is_none() || !json) json = to_python(io::to_json(*report));
    return json;
  }
};

// The field table's arrays, by the names of the HDF5 file's columns (io/hdf5_writer.cpp).
py::dict field_arrays(const io::FieldTable& t, py::handle owner) {
  using T = io::FieldTable;
  static constexpr const char* names[] = {
      "coordinate",   "w",        "u",         "rotation",     "bending_moment", "shear_force",
      "normal_force", "reaction", "w_initial", "buckling_mode"};
  static constexpr std::vector<double> T::*members[] = {
      &T::coordinate,   &T::w,        &T::u,         &T::rotation,     &T::bending_moment, &T::shear_force,
      &T::normal_force, &T::reaction, &T::w_initial, &T::buckling_mode};
  py::dict d;
  for (std::size_t i = 0; i < std::size(names); ++i)
    if (!(t.*members[i]).empty()) d[names[i]] = view(t.*members[i], owner);
  return d;
}

struct TraceResult {
  std::shared_ptr<const app::TraceOutcome> outcome;
  py::object json;
};

struct SweepResult {
  std::vector<std::string> keys;
  std::shared_ptr<const std::vector<io::SweepCase>> cases;
};

// ---- errors ---------------------------------------------------------------------------------

// The CLI's exit code of a solve report (cli.cpp run_solve).
ExitCode exit_code(const io::SolveReport& r) {
  return r.usable                                                                    ? ExitCode::success
         : r.termination == "unstable_equilibrium" || r.termination == "limit_point" ? ExitCode::unstable_equilibrium
                                                                                     : ExitCode::solver_failure;
}

// The exception types (made by the module's init, kept for the interpreter's life).
PyObject* input_type = nullptr;
PyObject* mechanism_type = nullptr;
PyObject* solver_failure_type = nullptr;
PyObject* unstable_type = nullptr;
PyObject* output_type = nullptr;

[[noreturn]] void raise_unsolved(ExitCode code, const std::string& message, py::object result) {
  PyObject* type = code == ExitCode::unstable_equilibrium ? unstable_type : solver_failure_type;
  py::object error = py::reinterpret_borrow<py::object>(type)(message);
  error.attr("result") = std::move(result);
  PyErr_SetObject(type, error.ptr());
  throw py::error_already_set();
}

py::object solve(py::handle scene_source, const std::optional<std::string>& method,
                 const std::optional<double>& tolerance, const std::optional<int>& elements, const py::object& modes,
                 bool fields, bool check) {
  const app::SolveRequest request = solve_request(method, tolerance, elements, modes, fields);
  const scene::Scene scene = read_scene(scene_source);
  const bool all = request.method.value_or(scene.solve.method) == scene::Method::all;
  std::vector<io::SolveReport> reports;
  {
    py::gil_scoped_release unlocked;
    app::require_honoured_theory(scene, app::Command::solve);
    if (all)
      reports = app::solve_all_methods(scene, request);
    else
      reports.push_back(app::solve_scene(scene, request));
  }
  if (all) {  // a refused method's report knows nothing of the scene: its k as `--method all` gives it
    const model::MemberModel model = model::make_member_model(scene);
    for (io::SolveReport& r : reports)
      if (r.outcome == io::SolveOutcome::refused) r.k = model.k, r.tensionless = model.tensionless;
  }
  py::list results;
  std::string failures;
  ExitCode worst = ExitCode::success;
  for (io::SolveReport& r : reports) {
    if (!r.usable && r.outcome != io::SolveOutcome::refused) {
      failures += fmt::format("{}{}{}", failures.empty() ? "" : "; ", all ? r.method + ": " : "", r.message);
      if (worst == ExitCode::success) worst = exit_code(r);
    }
    results.append(py::cast(SolveResult{std::make_shared<const io::SolveReport>(std::move(r)), py::none()}));
  }
  py::object result = all ? py::object(results) : results[0];
  if (check && worst != ExitCode::success)
    raise_unsolved(all ? ExitCode::solver_failure : worst, scene.source_name + ": " + failures, result);
  return result;
}

py::object trace(py::handle scene_source, const std::optional<std::string>& method, const std::optional<int>& elements,
                 const py::object& modes, const std::optional<std::string>& output, bool resume, bool check) {
  const scene::Scene scene = read_scene(scene_source);
  app::TraceRequest request;
  request.method = method_option(method);
  request.elements = elements_option(elements);
  request.modes = modes_option(modes);
  if (output) request.output = *output;
  request.resume = resume;
  request.version = LIFTOFF_VERSION;
  auto outcome = std::make_shared<app::TraceOutcome>();
  {
    py::gil_scoped_release unlocked;
    app::require_honoured_theory(scene, app::Command::trace);
    *outcome = app::run_trace(scene, request);
  }
  // The top level's termination and message are the run's, and method_requested the method asked
  // for, as `liftoff trace --json` has them.
  nlohmann::json j = app::to_json(*outcome);
  if (method)
    j["method_requested"] = *method;
  else if (scene.trace)
    j["method_requested"] = scene::to_string(scene.trace->method.value_or(scene.solve.method));
  std::string failure;
  for (const app::PathTrace& p : outcome->paths)
    if (!p.summary.is_usable()) {
      j["termination"] = continuation::to_string(p.summary.termination);
      j["message"] = fmt::format("path {}: {}", p.path, p.summary.message);
      failure = fmt::format("{}: trace {}: {}, {}", scene.source_name, p.path,
                            continuation::to_string(p.summary.termination), p.summary.message);
      break;
    }
  py::object result = py::cast(TraceResult{outcome, to_python(j)});
  if (check && !outcome->usable()) raise_unsolved(ExitCode::solver_failure, failure, result);
  return result;
}

py::object sweep(py::handle scene_source, const py::dict& parameters, const std::optional<std::string>& method,
                 const std::optional<double>& tolerance, const std::optional<int>& elements, const py::object& modes,
                 std::optional<int> jobs, const std::optional<std::string>& output, bool fields, bool check) {
  const app::SolveRequest request = solve_request(method, tolerance, elements, modes, fields || output.has_value());
  if (jobs && (*jobs < 1 || *jobs > 1024))
    throw InputError(fmt::format("jobs: expected an integer in [1, 1024], got {}", *jobs));
  // Each parameter: a list of numbers, or the CLI's "a,b,c" / "lin:a:b:n" / "log:a:b:n".
  std::vector<app::SweepParameter> swept;
  SweepResult result;
  for (const auto& [k, v] : parameters) {
    const std::string key = py::str(k).cast<std::string>();
    if (py::isinstance<py::str>(v)) {
      swept.push_back(app::parse_sweep_parameter(key + "=" + v.cast<std::string>()));
    } else {
      app::SweepParameter p{key, {}};
      for (py::handle value : v) p.values.push_back(value.cast<double>());
      if (p.values.empty()) throw InputError(fmt::format("parameters: key '{}': expected at least one value", key));
      swept.push_back(std::move(p));
    }
    result.keys.push_back(swept.back().key);
  }
  if (swept.empty()) throw InputError("parameters: expected at least one key to sweep, got none");
  const scene::Scene scene = read_scene(scene_source);
  auto cases = std::make_shared<std::vector<io::SweepCase>>();
  {
    py::gil_scoped_release unlocked;
    app::require_honoured_theory(scene, app::Command::sweep);
    *cases = app::run_sweep(scene, swept, request,
                            jobs.value_or(static_cast<int>(std::max(1u, std::thread::hardware_concurrency()))));
    if (output) io::write_sweep_hdf5(result.keys, *cases, *output, LIFTOFF_VERSION);
  }
  result.cases = cases;
  int unsolved = 0;
  std::string first;
  for (const auto& c : *cases) {
    if (!c.error.empty() && first.empty()) first = c.error;
    for (const auto& r : c.reports)
      if (!r.usable && r.outcome != io::SolveOutcome::refused && ++unsolved == 1 && first.empty())
        first = r.scene_name + ": " + r.message;
  }
  py::object object = py::cast(std::move(result));
  if (check && !first.empty())
    raise_unsolved(ExitCode::solver_failure, fmt::format("sweep: a case failed (the first: {})", first), object);
  return object;
}

}  // namespace

}  // namespace liftoff::python

PYBIND11_MODULE(_liftoff, m) {
  using namespace liftoff;
  using namespace liftoff::python;
  m.doc() = "liftoff: beams and arches on a tensionless elastic foundation (the C++ library's entry points)";
  m.attr("__version__") = LIFTOFF_VERSION;

  // The exceptions, one per kind of library error, each with the CLI's exit code; created once and
  // kept for the interpreter's life.
  const py::module_ builtins = py::module_::import("builtins");
  const auto make = [&](const char* name, py::tuple bases, std::optional<ExitCode> code) {
    py::object type = py::reinterpret_steal<py::object>(
        PyErr_NewException(("liftoff." + std::string(name)).c_str(), bases.ptr(), nullptr));
    if (code) type.attr("exit_code") = static_cast<int>(*code);
    m.attr(name) = type;
    return type.release().ptr();
  };
  PyObject* base = make("Error", py::make_tuple(builtins.attr("Exception")), std::nullopt);
  input_type = make("InputError", py::make_tuple(py::handle(base), builtins.attr("ValueError")), ExitCode::bad_input);
  mechanism_type = make("MechanismError", py::make_tuple(py::handle(input_type)), ExitCode::bad_input);
  solver_failure_type =
      make("SolverFailure", py::make_tuple(py::handle(base), builtins.attr("RuntimeError")), ExitCode::solver_failure);
  unstable_type =
      make("UnstableEquilibrium", py::make_tuple(py::handle(solver_failure_type)), ExitCode::unstable_equilibrium);
  output_type = make("OutputError", py::make_tuple(py::handle(base), builtins.attr("OSError")), ExitCode::output_error);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const MechanismError& e) {
      PyErr_SetString(mechanism_type, e.what());
    } catch (const InputError& e) {
      PyErr_SetString(input_type, e.what());
    } catch (const UnstableEquilibrium& e) {
      PyErr_SetString(unstable_type, e.what());
    } catch (const SolverFailure& e) {
      PyErr_SetString(solver_failure_type, e.what());
    } catch (const OutputError& e) {
      PyErr_SetString(output_type, e.what());
    }
  });

  py::class_<SolveResult>(m, "SolveResult",
                          "One solve's answer. Every key of `liftoff solve --json` is an attribute (contact_regions, "
                          "design, support_reactions, certificate, termination, message, ...); the fields are "
                          "read-only numpy views: positions, w, u, rotation, M, V, N, reaction (`fields`, `nodes`: "
                          "every column by its HDF5 name).")
      .def_property_readonly("json", &SolveResult::keys, "the answer as `liftoff solve --json` prints it (a dict)")
      .def_property_readonly("usable", [](const SolveResult& s) { return s.r().usable; })
      .def_property_readonly("certified", [](const SolveResult& s) { return s.r().certified(); })
      .def_property_readonly("exit_code", [](const SolveResult& s) { return static_cast<int>(exit_code(s.r())); })
      .def_property_readonly("scene_text", [](const SolveResult& s) { return s.r().scene_text; })
      .def_property_readonly(
          "positions", [](py::object self) { return view(self.cast<SolveResult&>().r().fields.coordinate, self); })
      .def_property_readonly("w", [](py::object self) { return view(self.cast<SolveResult&>().r().fields.w, self); })
      .def_property_readonly("u", [](py::object self) { return view(self.cast<SolveResult&>().r().fields.u, self); })
      .def_property_readonly("rotation",
                             [](py::object self) { return view(self.cast<SolveResult&>().r().fields.rotation, self); })
      .def_property_readonly(
          "M", [](py::object self) { return view(self.cast<SolveResult&>().r().fields.bending_moment, self); })
      .def_property_readonly(
          "V", [](py::object self) { return view(self.cast<SolveResult&>().r().fields.shear_force, self); })
      .def_property_readonly(
          "N", [](py::object self) { return view(self.cast<SolveResult&>().r().fields.normal_force, self); })
      .def_property_readonly("reaction",
                             [](py::object self) { return view(self.cast<SolveResult&>().r().fields.reaction, self); })
      .def_property_readonly("fields",
                             [](py::object self) { return field_arrays(self.cast<SolveResult&>().r().fields, self); })
      .def_property_readonly("nodes",
                             [](py::object self) { return field_arrays(self.cast<SolveResult&>().r().nodes, self); })
      .def("__getattr__",
           [](SolveResult& s, const std::string& name) -> py::object {
             py::dict keys = s.keys();
             if (keys.contains(name)) return keys[py::str(name)];
             throw py::attribute_error(fmt::format("SolveResult has no key '{}' (see dir(result))", name));
           })
      .def("__dir__",
           [](py::object self) {
             py::list names = py::module_::import("builtins").attr("object").attr("__dir__")(self);
             for (const auto& key : self.cast<SolveResult&>().keys().cast<py::dict>()) names.append(key.first);
             return names;
           })
      .def("__repr__", [](const SolveResult& s) {
        return fmt::format("<liftoff.SolveResult {} {}: {}>", s.r().scene_name, s.r().method, s.r().termination);
      });

  py::class_<TraceResult>(m, "TraceResult",
                          "One trace. Every key of `liftoff trace --json` is an attribute (paths, events, steps, "
                          "termination, ...); steps(path) gives a path's columns as read-only numpy views.")
      .def_property_readonly("json", [](const TraceResult& t) { return t.json; })
      .def_property_readonly("usable", [](const TraceResult& t) { return t.outcome->usable(); })
      .def(
          "steps",
          [](py::object self, std::optional<std::string> path) {
            const app::TraceOutcome& o = *self.cast<TraceResult&>().outcome;
            for (const app::PathTrace& p : o.paths) {
              if (path && p.path != *path) continue;
              const auto& s = p.steps;
              const auto column = [&](const double continuation::TraceStep::*member) {
                return s.empty() ? py::array(py::array_t<double>(0))
                                 : view(&(s.front().*member), s.size(), sizeof(continuation::TraceStep), self);
              };
              py::dict d;
              d["lambda"] = column(&continuation::TraceStep::load_factor);
              d["monitor_deflection"] = column(&continuation::TraceStep::monitor_deflection);
              d["axial_force"] = column(&continuation::TraceStep::axial_force);
              d["amplitude"] = column(&continuation::TraceStep::amplitude);
              d["lifted_length"] = column(&continuation::TraceStep::lifted_length);
              return d;
            }
            throw py::key_error(fmt::format("no path '{}' in this trace", path.value_or("")));
          },
          py::arg("path") = py::none(),
          "a path's steps (default: the first path): lambda, monitor_deflection, axial_force, amplitude, lifted_length "
          "(the JSON step keys) as read-only numpy views")
      .def("__getattr__",
           [](TraceResult& t, const std::string& name) -> py::object {
             py::dict keys = t.json;
             if (keys.contains(name)) return keys[py::str(name)];
             throw py::attribute_error(fmt::format("TraceResult has no key '{}'", name));
           })
      .def("__repr__", [](const TraceResult& t) {
        return fmt::format("<liftoff.TraceResult {}: {} paths>", t.outcome->scene_name, t.outcome->paths.size());
      });

  py::class_<SweepResult>(m, "SweepResult",
                          "One sweep: keys (the swept scene keys), values (cases x keys), cases (each a dict of "
                          "values, error and reports, a SolveResult per method), csv (`liftoff sweep`'s CSV).")
      .def_property_readonly("keys", [](const SweepResult& s) { return s.keys; })
      .def_property_readonly("values",
                             [](const SweepResult& s) {
                               py::array_t<double> a({s.cases->size(), s.keys.size()});
                               auto v = a.mutable_unchecked<2>();
                               for (std::size_t i = 0; i < s.cases->size(); ++i)
                                 for (std::size_t k = 0; k < s.keys.size(); ++k) v(i, k) = (*s.cases)[i].values[k];
                               return a;
                             })
      .def_property_readonly(
          "cases",
          [](const SweepResult& s) {
            py::list cases;
            for (const io::SweepCase& c : *s.cases) {
              py::list reports;
              for (const io::SolveReport& r : c.reports)
                reports.append(SolveResult{std::shared_ptr<const io::SolveReport>(s.cases, &r), py::none()});
              cases.append(
                  py::dict(py::arg("values") = c.values, py::arg("error") = c.error, py::arg("reports") = reports));
            }
            return cases;
          })
      .def_property_readonly("csv", [](const SweepResult& s) { return io::sweep_csv(s.keys, *s.cases); })
      .def("__len__", [](const SweepResult& s) { return s.cases->size(); })
      .def("__repr__",
           [](const SweepResult& s) { return fmt::format("<liftoff.SweepResult {} cases>", s.cases->size()); });

  m.def("solve", &solve, py::arg("scene"), py::kw_only(), py::arg("method") = py::none(),
        py::arg("tolerance") = py::none(), py::arg("elements") = py::none(), py::arg("modes") = py::none(),
        py::arg("fields") = true, py::arg("check") = true,
        "Solve one scene (a TOML file path, TOML text, or a dict with a scene file's keys) as `liftoff solve` does; "
        "method, tolerance, elements and modes override the scene's [solve] and [ritz] keys. Returns a SolveResult "
        "(method='all': a list, one per method). check: an answer that is not solved raises SolverFailure (or "
        "UnstableEquilibrium) with the CLI's message, the result in the exception's `result`.");
  m.def("trace", &trace, py::arg("scene"), py::kw_only(), py::arg("method") = py::none(),
        py::arg("elements") = py::none(), py::arg("modes") = py::none(), py::arg("output") = py::none(),
        py::arg("resume") = false, py::arg("check") = true,
        "Follow the scene's load history ([trace]) as `liftoff trace` does; output: the HDF5 trace file.");
  m.def("sweep", &sweep, py::arg("scene"), py::arg("parameters"), py::kw_only(), py::arg("method") = py::none(),
        py::arg("tolerance") = py::none(), py::arg("elements") = py::none(), py::arg("modes") = py::none(),
        py::arg("jobs") = py::none(), py::arg("output") = py::none(), py::arg("fields") = false,
        py::arg("check") = true,
        "Solve the scene for every combination of values of some of its keys as `liftoff sweep` does: parameters "
        "maps a key ('foundation.modulus', 'loads[0].value') to a list of values or to the CLI's 'a,b,c', "
        "'lin:a:b:n', 'log:a:b:n' (the last key varies fastest). jobs: cases at once (default: the cores); output: "
        "the HDF5 file; fields: keep each case's sampled fields.");
}
