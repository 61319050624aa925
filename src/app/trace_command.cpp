#include "app/trace_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "app/theory_gate.hpp"
#include "app/trace_load.hpp"
#include "contact/from_scene.hpp"
#include "continuation/models/fe_member.hpp"
#include "continuation/models/ritz.hpp"
#include "core/error.hpp"
#include "io/report.hpp"
#include "io/trace_writer.hpp"
#include "model/from_scene.hpp"
#include "model/member_model.hpp"
#include "post/scale.hpp"
#include "ritz/ritz_model.hpp"

namespace liftoff::app {

using continuation::TraceEvent;
using continuation::TraceOptions;
using continuation::TraceStep;
using continuation::TraceTermination;

namespace {

const scene::TraceSettings& trace_settings(const scene::Scene& scene) {
  if (!scene.trace)
    throw InputError(
        fmt::format("{}: key 'trace': missing (expected a table [trace] with lambda_max, the "
                    "largest load factor)",
                    scene.source_name));
  const scene::TraceSettings& t = *scene.trace;
  if (!t.lambda_max)
    throw InputError(fmt::format("{}{}: key 'trace.lambda_max': missing (expected a number > lambda_min = {})",
                                 scene.source_name, t.line > 0 ? fmt::format(":{}", t.line) : "", t.lambda_min));
  // A free load case (for [[combinations]]) has no place in F_dead + lambda F_live: refused, not
  // guessed (src/scene/README.md, `[[loads]]` key `case`).
  for (std::size_t i = 0; i < scene.loads.size(); ++i)
    if (scene.loads[i].case_name != "dead" && scene.loads[i].case_name != "live")
      throw InputError(fmt::format(
          "{}: key 'loads[{}].case': expected \"dead\" or \"live\" for `liftoff trace` (F = F_dead + lambda "
          "F_live), got \"{}\" (free case names are for [[combinations]] and `liftoff envelope`)",
          scene.source_name, i, scene.loads[i].case_name));
  // An axial force (second-order theory) is traced on beams (the second-order kinematics of
  // continuation/models/member_kinematics.hpp); an arch's axial force is `solve`'s only.
  for (std::size_t i = 0; i < scene.loads.size(); ++i)
    if ((scene.loads[i].kind == scene::LoadKind::axial || scene.loads[i].kind == scene::LoadKind::temperature) &&
        scene.structure.kind != scene::StructureKind::beam)
      throw InputError(fmt::format(
          "{}: key 'loads[{}].kind': expected a transverse load for `liftoff trace` of an arch, got \"{}\" (an "
          "arch's axial force is taken by `liftoff solve` only in this version)",
          scene.source_name, i, scene::to_string(scene.loads[i].kind)));
  return t;
}

scene::Method trace_method(const scene::Scene& scene, const TraceRequest& request) {
  return request.method.value_or(trace_settings(scene).method.value_or(scene.solve.method));
}

int trace_elements(const scene::Scene& scene, const TraceRequest& request) {
  return request.elements.value_or(scene.solve.elements);
}

// The monitor of the load-displacement curve: [trace] monitor, else the first live point force
// (the load being increased), else mid-member.
double monitor_point(const scene::Scene& scene) {
  if (scene.trace && scene.trace->monitor) return *scene.trace->monitor;
  for (const scene::Load& load : scene.loads)
    if (load.kind == scene::LoadKind::force && load.load_case == scene::LoadCase::live) return load.at;
  return 0.5 * (scene.begin() + scene.end());
}

// What a resumed run must share with the file's first run, beyond the scene text.
std::string options_text(const scene::Scene& scene, const TraceRequest& request, const TraceOptions& options) {
  nlohmann::json j;
  j["method"] = scene::to_string(trace_method(scene, request));
  j["elements"] = options.elements;
  j["modes"] = options.ritz.modes;
  j["samples"] = options.sample_points.size();
  j["monitor"] = options.monitor;
  if (!options.report_at.empty()) j["report_at"] = options.report_at;  // the load factors asked for
  return j.dump();
}

// The bending moment at the monitor (the crest of a buckle, the load point): the step's nodal
// moments interpolated linearly between the nodes about it (exact at a node); none where the step
// has no fields or the monitor lies outside them.
std::optional<double> monitor_moment(const TraceStep& s, double monitor) {
  const std::vector<double>&x = s.fields.coordinate, &m = s.fields.bending_moment;
  if (x.size() < 2 || m.size() != x.size() || !(monitor >= x.front() && monitor <= x.back())) return std::nullopt;
  const auto right = std::upper_bound(x.begin(), x.end(), monitor);
  if (right == x.end()) return m.back();
  const std::size_t i = static_cast<std::size_t>(right - x.begin());
  const double t = (monitor - x[i - 1]) / (x[i] - x[i - 1]);
  return t == 0.0 ? m[i - 1] : (1.0 - t) * m[i - 1] + t * m[i];
}

// A path read back from the file (without the sampled and nodal fields); its steps' physical load
// where the file has none (an older liftoff's).
PathTrace from_record(const std::string& name, const io::TracePathRecord& record,
                      const std::optional<continuation::PhysicalLoad>& load, double monitor) {
  PathTrace p;
  p.path = name;
  p.steps = record.steps;
  for (TraceStep& s : p.steps) {
    if (!s.monitor_moment) s.monitor_moment = monitor_moment(s, monitor);
    s.deflection.clear(), s.reaction.clear(), s.fields = {};
    if (load && !s.load) s.load = load->at(s.load_factor);
  }
  p.events = record.events;
  p.event_steps = record.event_steps;
  p.resumed_steps = static_cast<int>(p.steps.size());
  p.summary.path = name == "ritz" ? continuation::PathKind::ritz : continuation::PathKind::fe;
  // Read back through the one table; a path that never ended (no termination yet) failed.
  p.summary.termination = from_string<TraceTermination>(record.termination).value_or(TraceTermination::solver_failure);
  p.summary.message = record.message;
  p.summary.steps = static_cast<int>(p.steps.size());
  if (!p.steps.empty()) p.summary.final_load_factor = p.steps.back().load_factor;
  return p;
}

// An event; with its physical load where the trace has one.
nlohmann::json to_json(const TraceEvent& e, const std::optional<continuation::PhysicalLoad>& load = std::nullopt) {
  nlohmann::json j{{"lambda", e.load_factor}};
  if (load) j["load"] = load->at(e.load_factor);
  j.update({{"kind", continuation::to_string(e.kind)}, {"at", e.at}, {"description", e.description}});
  return j;
}

nlohmann::json to_json(const EventComparison& c) {
  nlohmann::json j;
  j["a"] = c.a;
  j["b"] = c.b;
  j["pairs"] = nlohmann::json::array();
  for (const EventPair& p : c.pairs)
    j["pairs"].push_back({{"kind", continuation::to_string(p.kind)},
                          {"lambda_a", p.load_factor_a},
                          {"lambda_b", p.load_factor_b},
                          {"lambda_difference", p.load_factor_b - p.load_factor_a},
                          {"at_a", p.at_a},
                          {"at_b", p.at_b}});
  j["only_a"] = nlohmann::json::array();
  for (const TraceEvent& e : c.only_a) j["only_a"].push_back(to_json(e));
  j["only_b"] = nlohmann::json::array();
  for (const TraceEvent& e : c.only_b) j["only_b"].push_back(to_json(e));
  return j;
}

// What a trace's JSON needs beside its steps: how the support reactions read
// (io::support_reactions_json) and the physical load of its events.
struct JsonStyle {
  bool arch = false, von_karman = false;
  std::optional<continuation::PhysicalLoad> load;
  bool foundation_outside = false;
};

nlohmann::json to_json(const TraceStep& s, const JsonStyle& style) {
  nlohmann::json j{{"lambda", s.load_factor}};
  if (s.load) j["load"] = *s.load;
  if (s.monitor_moment) j["monitor_moment"] = *s.monitor_moment;
  j.update({{"monitor_deflection", s.monitor_deflection},
            {"contact_regions", io::contact_regions_json(s.contact_regions)},
            {"iterations", s.iterations},
            {"axial_force", s.axial_force},
            {"amplitude", s.amplitude},
            {"lifted_length", s.lifted_length},
            {"stability", continuation::to_string(s.stability)},
            {"requested", s.requested}});
  if (s.design) j["design"] = io::design_json(*s.design);
  j["supports"] = io::support_reactions_json(s.supports, style.arch, style.von_karman, style.foundation_outside);
  return j;
}

nlohmann::json to_json(const PathTrace& p, const JsonStyle& style) {
  nlohmann::json j;
  j["path"] = p.path;
  j["termination"] = continuation::to_string(p.summary.termination);
  j["message"] = p.summary.message;
  j["final_lambda"] = p.steps.empty() ? p.summary.final_load_factor : p.steps.back().load_factor;
  j["resumed_steps"] = p.resumed_steps;
  j["rejected_steps"] = p.summary.rejected_steps;
  j["corrector_iterations"] = p.summary.corrector_iterations;
  j["pivots"] = p.summary.pivots;
  j["time_s"] = p.summary.time_s;
  j["events"] = nlohmann::json::array();
  for (const TraceEvent& e : p.events) j["events"].push_back(to_json(e, style.load));
  j["steps"] = nlohmann::json::array();
  for (const TraceStep& s : p.steps) j["steps"].push_back(to_json(s, style));
  return j;
}

std::string comparison_text(const EventComparison& c, const char* title) {
  std::string out = fmt::format("  {}: {} against {}\n", title, c.a, c.b);
  for (const EventPair& p : c.pairs)
    out += fmt::format("    {:<18} lambda {:<14.8g} {:<14.8g} difference {:.3e}   at {:.6g} / {:.6g}\n",
                       continuation::to_string(p.kind), p.load_factor_a, p.load_factor_b,
                       p.load_factor_b - p.load_factor_a, p.at_a, p.at_b);
  for (const TraceEvent& e : c.only_a)
    out += fmt::format("    {:<18} lambda {:<14.8g} only in {}\n", continuation::to_string(e.kind), e.load_factor, c.a);
  for (const TraceEvent& e : c.only_b)
    out += fmt::format("    {:<18} lambda {:<14.8g} only in {}\n", continuation::to_string(e.kind), e.load_factor, c.b);
  return out;
}

// How the summary writes positions and figures: x or theta, and the scene's unit labels.
struct SummaryUnits {
  bool arch = false;
  scene::Units units;
  std::string unit(const std::string& label) const { return label.empty() ? "" : " " + label; }
  std::string where(double at) const {
    return fmt::format("{} = {:.6g}{}", arch ? "theta" : "x", at, arch ? " deg" : unit(units.length));
  }
};

// A step's state in one indented line: the moment's extremes with their positions, w at the
// monitor, the axial force and lifted length where the member has them.
std::string state_line(const TraceStep& step, const SummaryUnits& u) {
  std::string out =
      fmt::format("                  w at the monitor {:.6g}{}", step.monitor_deflection, u.unit(u.units.length));
  if (step.monitor_moment) out += fmt::format(", M there {:.6g}{}", *step.monitor_moment, u.unit(u.units.moment()));
  if (const auto& d = step.design) {
    const auto where = [&](const post::DesignValue& v) { return v.at ? " at " + u.where(*v.at) : std::string(); };
    out += fmt::format("; moment max {:.6g}{}{}, min {:.6g}{}{}", d->moment_max.value, u.unit(u.units.moment()),
                       where(d->moment_max), d->moment_min.value, u.unit(u.units.moment()), where(d->moment_min));
  }
  if (step.axial_force != 0.0) out += fmt::format("; axial force {:.6g}{}", step.axial_force, u.unit(u.units.force));
  if (step.lifted_length > 0.0)
    out += fmt::format("; lifted length {:.6g}{}", step.lifted_length, u.arch ? " deg" : u.unit(u.units.length));
  return out + "\n";
}

// The state at an event: that of the step it follows (the step at the event, or the last step
// before it when the event lies inside a step: said so).
std::string event_state_line(const PathTrace& p, std::size_t event, const SummaryUnits& u) {
  const TraceEvent& e = p.events[event];
  const int index = event < p.event_steps.size() ? p.event_steps[event] : -1;
  if (index < 0 || index >= static_cast<int>(p.steps.size())) return "";
  const TraceStep& step = p.steps[index];
  const bool at_event = std::abs(step.load_factor - e.load_factor) <= 1e-9 * std::max(1.0, std::abs(e.load_factor));
  std::string line = state_line(step, u);
  if (!at_event) line.insert(line.size() - 1, fmt::format(" (the step before, at lambda {:.8g})", step.load_factor));
  return line;
}

}  // namespace

TracePaths default_trace_paths() {
  return {[](const model::MemberModel& m, const TraceOptions& o, const continuation::TraceSink& k) {
            return continuation::trace_fe(m, o, k);
          },
          [](const model::MemberModel& m, const TraceOptions& o, const continuation::TraceSink& k) {
            return continuation::trace_ritz(m, o, k);
          }};
}

bool TraceOutcome::usable() const {
  return std::all_of(paths.begin(), paths.end(), [](const PathTrace& p) { return p.summary.is_usable(); });
}

TraceOptions trace_options(const scene::Scene& scene, const TraceRequest& request) {
  const scene::TraceSettings& t = trace_settings(scene);
  TraceOptions o;
  continuation::ArcLengthOptions& a = o.arc_length;
  a.lambda_min = t.lambda_min;
  a.lambda_max = *t.lambda_max;
  a.control =
      t.control == scene::TraceControl::load ? continuation::PathControl::load : continuation::PathControl::arc_length;
  a.initial_step = t.initial_step;
  a.min_step = t.min_step;
  a.max_step = t.max_step;
  a.max_steps = t.max_steps;
  o.elements = trace_elements(scene, request);
  // The FE path's contact solver: the method asked for, automatic when it names no FE solver
  // ("all": the FE path beside the Ritz one; "ritz": the FE path does not run).
  const scene::Method method = trace_method(scene, request);
  o.contact_method = method == scene::Method::all || method == scene::Method::ritz ? contact::Method::automatic
                                                                                   : contact::to_contact(method);
  // The Ritz path's [ritz] table (as ritz/from_scene.hpp gives `solve` its options).
  o.ritz.modes = request.modes.value_or(scene.ritz.modes);
  o.ritz.max_modes = scene.ritz.max_modes;
  o.ritz.mode_tolerance = scene.ritz.mode_tolerance;
  o.ritz.topology = scene.ritz.topology;
  o.ritz.limits = scene.ritz.limits;
  o.monitor = monitor_point(scene);
  o.max_amplitude = t.max_amplitude;
  o.switch_branch = t.switch_branch;
  // Uniform, with both ends exact: begin + (end - begin) i / (n - 1) can round one ulp past the
  // end (L = 0.013), and the paths refuse a sample outside the member.
  o.sample_points.resize(t.samples);
  for (int i = 0; i < t.samples; ++i)
    o.sample_points[i] = std::min(scene.end(), scene.begin() + (scene.end() - scene.begin()) * i / (t.samples - 1));
  o.sample_points.back() = scene.end();
  // The live load as a physical quantity, and the loads asked for in its unit (load factors
  // without one), checked against the range before any work.
  o.physical_load = live_load(scene).load;
  if (request.report_at)
    o.report_at = report_at_load_factors(*request.report_at, o.physical_load, a.lambda_min, a.lambda_max,
                                         [](std::size_t) { return std::string("option '--at'"); });
  else
    o.report_at = report_at_load_factors(t.report_at, o.physical_load, a.lambda_min, a.lambda_max, [&](std::size_t i) {
      return fmt::format("{}{}: key 'trace.report_at[{}]'", scene.source_name,
                         t.report_at_line > 0 ? fmt::format(":{}", t.report_at_line) : "", i);
    });
  return o;
}

std::vector<std::string> trace_path_names(const scene::Scene& scene, const TraceRequest& request) {
  const scene::TraceSettings& t = trace_settings(scene);
  const scene::Method method = trace_method(scene, request);
  std::vector<std::string> names;
  if (method != scene::Method::ritz) {
    // The FE path's theory (app/theory_gate.hpp): refused for von Karman until its path exists.
    require_honoured_theory(scene, Command::trace, Solver::fe_path,
                            request.method ? std::optional<std::string>("option '--method'")
                            : t.method     ? std::optional<std::string>("key 'trace.method'")
                                           : std::optional<std::string>("key 'solve.method'"));
    names.push_back("fe");
  }
  if (method == scene::Method::ritz || method == scene::Method::all) {
    // As `solve --method ritz`: what the Ritz model cannot take is bad input for it (exit 2).
    const model::MemberModel model = model::make_member_model(scene);
    if (const auto unsupported =
            ritz::unsupported_input(model, scene.foundation.gap_key(), scene.foundation.tension_key())) {
      const std::string where = request.method ? "option '--method'"
                                : t.method     ? "key 'trace.method'"
                                               : "key 'solve.method'";
      throw InputError(
          fmt::format("{}: {}: the Ritz path cannot take this scene ({}); expected an FE method "
                      "(\"dual\", \"primal\", \"fast\" or \"auto\")",
                      scene.source_name, where, unsupported->message()));
    }
    // A bilateral foundation (or one as stiff in tension) is in contact everywhere: the Ritz
    // model has the one topology (`solve --method ritz` refuses another as well).
    const std::vector<bool>& pieces = scene.ritz.topology;
    if (!model.tensionless && (pieces.size() > 1 || (pieces.size() == 1 && !pieces.front())))
      throw InputError(fmt::format(
          "{}: key 'ritz.topology': the foundation is bilateral (in contact everywhere); expected [\"contact\"] "
          "or \"auto\", got {} piece(s) starting in {}",
          scene.source_name, pieces.size(), pieces.front() ? "contact" : "lift-off"));
    names.push_back("ritz");
  }
  if (t.refine) {
    if (method == scene::Method::ritz)
      throw InputError(
          fmt::format("{}{}: key 'trace.refine': expected false with method \"ritz\" (refine repeats "
                      "the FE path with twice the elements; use method \"all\"), got true",
                      scene.source_name, t.line > 0 ? fmt::format(":{}", t.line) : ""));
    names.push_back("fe_refined");
  }
  return names;
}

EventComparison compare_events(const PathTrace& a, const PathTrace& b) {
  EventComparison c{a.path, b.path, {}, {}, {}};
  std::vector<bool> used(b.events.size(), false);
  for (const TraceEvent& e : a.events) {
    std::size_t best = b.events.size();
    double distance = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < b.events.size(); ++j) {
      if (used[j] || b.events[j].kind != e.kind) continue;
      const double d = std::abs(b.events[j].load_factor - e.load_factor);
      if (d < distance) distance = d, best = j;
    }
    if (best == b.events.size()) {
      c.only_a.push_back(e);
      continue;
    }
    used[best] = true;
    c.pairs.push_back({e.kind, e.load_factor, b.events[best].load_factor, e.at, b.events[best].at});
  }
  for (std::size_t j = 0; j < b.events.size(); ++j)
    if (!used[j]) c.only_b.push_back(b.events[j]);
  return c;
}

TraceOutcome run_trace(const scene::Scene& scene, const TraceRequest& request, const TracePaths& paths) {
  // Everything is checked before the file is touched: bad input leaves no file behind.
  const TraceOptions options = trace_options(scene, request);
  const std::vector<std::string> names = trace_path_names(scene, request);
  const std::string options_json = options_text(scene, request, options);
  if (request.resume && request.output.empty())
    throw InputError("--resume: needs --output FILE.h5, the trace to continue");
  if (request.resume && !std::filesystem::exists(request.output))
    throw InputError(
        fmt::format("--resume: {}: no such file (run without --resume to start it)", request.output.string()));

  TraceOutcome outcome;
  outcome.scene_name = scene.source_name;
  outcome.output = request.output.string();
  outcome.monitor = options.monitor;
  outcome.sample_points = options.sample_points;
  outcome.units = scene.units;
  outcome.warnings = scene.warnings;
  outcome.physical_load = options.physical_load;
  outcome.no_physical_load = live_load(scene).why_none;
  outcome.report_at = options.report_at;
  outcome.arch = scene.structure.kind == scene::StructureKind::arch;
  outcome.von_karman = scene.structure.theory == scene::Theory::von_karman;
  const model::MemberModel member = model::make_member_model(scene);
  outcome.foundation_outside = member.foundation_outside;
  // The foundation's scale (no mesh resolution here: the paths choose their own meshes).
  for (std::string& w : post::scale_warnings(scene, member, post::scale_figures(member)))
    outcome.warnings.push_back(std::move(w));

  std::unique_ptr<io::TraceWriter> writer;
  if (request.resume) {
    writer = std::make_unique<io::TraceWriter>(io::TraceWriter::resume(request.output));
    const io::TraceFileInfo& info = writer->info();
    if (info.scene_text != scene.text || info.options != options_json || info.paths != names)
      throw InputError(
          fmt::format("--resume: {}: was written for another scene or other options ({}); resume with "
                      "the same scene and options, or start again without --resume",
                      request.output.string(), info.options));
  } else if (!request.output.empty()) {
    io::TraceFileInfo info;
    info.version = request.version;
    info.scene_name = scene.source_name;
    info.scene_text = scene.text;
    info.coordinate = scene.structure.kind == scene::StructureKind::beam ? "x" : "theta_deg";
    info.options = options_json;
    info.paths = names;
    info.sample_points = options.sample_points;
    info.units = scene::unit_labels(scene.units);
    info.units.insert(info.units.begin(), {"system", scene.units.system});
    info.physical_load = options.physical_load;
    writer = std::make_unique<io::TraceWriter>(request.output, info);
  }

  for (const std::string& name : names) {
    PathTrace trace;
    trace.path = name;
    TraceOptions path_options = options;
    if (writer) {
      if (const auto record = writer->read_path(name)) {
        if (record->complete) {  // nothing left to do on this path
          outcome.paths.push_back(from_record(name, *record, options.physical_load, options.monitor));
          continue;
        }
        trace = from_record(name, *record, options.physical_load, options.monitor);
        if (!record->steps.empty()) path_options.resume_from = record->steps.back();
      }
      writer->begin_path(name, options.monitor);
    }
    if (name == "fe_refined") path_options.elements = 2 * options.elements;

    const std::size_t resumed_events = trace.events.size();
    continuation::TraceSink sink;
    sink.on_step = [&](const TraceStep& step) {
      TraceStep kept = step;
      // The physical load, where the paths did not set it (today none does): one place for all.
      if (options.physical_load && !kept.load) kept.load = options.physical_load->at(kept.load_factor);
      if (writer) writer->append_step(name, kept);
      kept.monitor_moment = monitor_moment(kept, options.monitor);
      kept.deflection.clear();
      kept.reaction.clear();
      kept.fields = {};  // in the file; the summary, JSON and CSV take the design values
      trace.steps.push_back(std::move(kept));
      if (request.progress)
        request.progress({name, step.load_factor, options.arc_length.lambda_min, options.arc_length.lambda_max,
                          static_cast<int>(trace.steps.size()), static_cast<int>(trace.events.size())});
    };
    sink.on_event = [&](const TraceEvent& event) {
      if (writer) writer->append_event(name, event);
      trace.events.push_back(event);
      trace.event_steps.push_back(static_cast<int>(trace.steps.size()) - 1);  // the step it follows, as the file
    };
    const TracePath& path = name == "ritz" ? paths.ritz : paths.fe;
    continuation::TraceResult result;
    try {
      result = path(member, path_options, sink);
    } catch (...) {
      // Refused before its first step (a mechanism, a scene the Ritz model cannot take): no
      // half-written file is left behind. Once steps are written they are kept, to resume.
      const bool nothing_written =
          !request.resume && trace.steps.empty() &&
          std::all_of(outcome.paths.begin(), outcome.paths.end(), [](const PathTrace& p) { return p.steps.empty(); });
      if (writer && nothing_written) {
        writer.reset();
        std::error_code ignored;
        std::filesystem::remove(request.output, ignored);
        std::filesystem::remove(io::trace_backup_path(request.output), ignored);
      }
      throw;
    }
    trace.summary = result.summary;
    // A path that reports through its result only (no sink calls) is taken from the result.
    if (trace.steps.size() == static_cast<std::size_t>(trace.resumed_steps))
      for (const TraceStep& s : result.steps) sink.on_step(s);
    if (trace.events.size() == resumed_events)
      for (const TraceEvent& e : result.events) sink.on_event(e);
    if (writer) writer->end_path(name, trace.summary);
    outcome.paths.push_back(std::move(trace));
  }

  const auto find = [&](const std::string& name) -> const PathTrace* {
    for (const PathTrace& p : outcome.paths)
      if (p.path == name) return &p;
    return nullptr;
  };
  if (find("fe") && find("ritz")) outcome.comparison = compare_events(*find("fe"), *find("ritz"));
  // The FE discretisation error of every event: the same path with twice the elements. Here the
  // refined run is a path of the trace, written to the file like the others, so its events are
  // compared directly (continuation::estimate_event_errors computes the same from a run of its
  // own, for callers without a trace file: the tests).
  if (find("fe") && find("fe_refined")) outcome.discretisation_error = compare_events(*find("fe"), *find("fe_refined"));
  if (writer && outcome.usable()) writer->finish();
  return outcome;
}

nlohmann::json to_json(const TraceOutcome& outcome) {
  nlohmann::json j;
  j["scene"] = outcome.scene_name;
  if (!outcome.output.empty()) j["output"] = outcome.output;
  j["monitor"] = outcome.monitor;
  j["usable"] = outcome.usable();
  // The live load as a physical quantity (each step's and event's `load` = lambda x reference),
  // or null and why not.
  if (const auto& load = outcome.physical_load)
    j["physical_load"] = {{"quantity", load->quantity},
                          {"symbol", load->symbol},
                          {"reference", load->reference},
                          {"unit", load->unit},
                          {"definition", load->definition}};
  else
    j["physical_load"] = nullptr, j["physical_load_note"] = outcome.no_physical_load + ": lambda only";
  j["report_at"] = outcome.report_at;
  // The first path's events and steps at the top level: what a single-path trace is about.
  if (!outcome.paths.empty()) {
    const nlohmann::json first =
        to_json(outcome.paths.front(),
                JsonStyle{outcome.arch, outcome.von_karman, outcome.physical_load, outcome.foundation_outside});
    for (const char* key : {"path", "termination", "message", "final_lambda", "events", "steps"}) j[key] = first[key];
  }
  j["paths"] = nlohmann::json::array();
  const JsonStyle style{outcome.arch, outcome.von_karman, outcome.physical_load, outcome.foundation_outside};
  for (const PathTrace& p : outcome.paths) j["paths"].push_back(to_json(p, style));
  if (outcome.comparison) j["comparison"] = to_json(*outcome.comparison);
  if (outcome.discretisation_error) j["discretisation_error"] = to_json(*outcome.discretisation_error);
  j["units"] = {{"system", outcome.units.system}};
  for (const auto& [name, label] : scene::unit_labels(outcome.units)) j["units"][name] = label;
  j["warnings"] = outcome.warnings;
  return j;
}

std::string text_summary(const TraceOutcome& outcome) {
  std::string out = fmt::format("scene         {}\nmonitor       w at {:.6g}\n", outcome.scene_name, outcome.monitor);
  for (const std::string& warning : outcome.warnings) out += "WARNING       " + warning + "\n";
  if (const auto& load = outcome.physical_load)
    out += fmt::format("load          {} = lambda x {:.6g}{}: {}\n", load->symbol, load->reference,
                       load->unit.empty() ? "" : " " + load->unit, load->definition);
  else
    out += fmt::format("load          lambda only ({})\n", outcome.no_physical_load);
  const SummaryUnits units{outcome.arch, outcome.units};
  for (const PathTrace& p : outcome.paths) {
    const double final_lambda = p.steps.empty() ? p.summary.final_load_factor : p.steps.back().load_factor;
    out += fmt::format("path {:<8} {}: {} steps{}, lambda {:.8g}{}{}\n", p.path,
                       continuation::to_string(p.summary.termination), p.steps.size(),
                       p.resumed_steps > 0 ? fmt::format(" ({} resumed)", p.resumed_steps) : "", final_lambda,
                       outcome.physical_load ? " (" + load_text(outcome.physical_load, final_lambda) + ")" : "",
                       p.summary.message.empty() ? "" : " (" + p.summary.message + ")");
    for (std::size_t i = 0; i < p.events.size(); ++i) {
      const TraceEvent& e = p.events[i];
      // "lambda 5.8449045 (N = 5.8449e+06 N)": the load factor and, where there is one, the load.
      const std::string load =
          fmt::format("{:.8g}{}", e.load_factor,
                      outcome.physical_load ? " (" + load_text(outcome.physical_load, e.load_factor) + ")" : "");
      out += fmt::format("  lambda {:<{}} {:<18} at {:<10.6g} {}\n", load, outcome.physical_load ? 36 : 14,
                         continuation::to_string(e.kind), e.at, e.description);
      out += event_state_line(p, i, units);
    }
    for (const TraceStep& step : p.steps)
      if (step.requested)
        out += fmt::format("  requested     {}{}\n", load_text(outcome.physical_load, step.load_factor),
                           outcome.physical_load ? fmt::format(" (lambda {:.8g})", step.load_factor) : "") +
               state_line(step, units);
  }
  if (outcome.comparison) out += comparison_text(*outcome.comparison, "events side by side");
  if (outcome.discretisation_error) out += comparison_text(*outcome.discretisation_error, "discretisation error");
  if (!outcome.output.empty()) out += fmt::format("written       {}\n", outcome.output);
  return out;
}

std::string trace_csv(const TraceOutcome& outcome) {
  std::string out = "path,step,lambda,load,monitor_deflection,axial_force,amplitude,lifted_length," +
                    io::design_csv_header() + ",support_reactions,stability,requested,monitor_moment\n";
  for (const PathTrace& p : outcome.paths)
    for (std::size_t i = 0; i < p.steps.size(); ++i) {
      const TraceStep& s = p.steps[i];
      const std::optional<double>& m = s.monitor_moment;
      out += fmt::format("{},{},{:.17g},{},{:.17g},{:.17g},{:.17g},{:.17g},{},{},{},{},{}\n", p.path, i, s.load_factor,
                         s.load ? fmt::format("{:.17g}", *s.load) : std::string(), s.monitor_deflection, s.axial_force,
                         s.amplitude, s.lifted_length, io::design_csv_cells(s.design ? &*s.design : nullptr),
                         io::support_reactions_csv(s.supports), continuation::to_string(s.stability),
                         s.requested ? "true" : "false", m ? fmt::format("{:.17g}", *m) : std::string());
    }
  return out;
}

}  // namespace liftoff::app
