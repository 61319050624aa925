#include "app/cli.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iostream>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string_view>
#include <thread>
#include <utility>

#include "app/distributed_sweep.hpp"
#include "app/envelope_command.hpp"
#include "app/plot_command.hpp"
#include "app/solve_command.hpp"
#include "app/sweep_command.hpp"
#include "app/theory_gate.hpp"
#include "app/trace_command.hpp"
#include "core/error.hpp"
#include "default_scene.hpp"
#include "io/csv_writer.hpp"
#include "io/envelope_report.hpp"
#include "io/hdf5_writer.hpp"
#include "io/trace_writer.hpp"
#include "model/from_scene.hpp"
#include "model/member_model.hpp"
#include "scene/scene_reader.hpp"

namespace liftoff::app {

namespace {

int code(ExitCode c) { return static_cast<int>(c); }

// What `solve` and `sweep` share: the scene and how to solve it.
struct ProblemArguments {
  std::string scene_path;
  std::string method;
  int elements = 0;
  std::string modes;
  std::string tolerance;
};

void add_problem_options(CLI::App* command, ProblemArguments& args) {
  command->add_option("scene", args.scene_path, fmt::format("Scene file (TOML); default: {}", default_scene_name))
      ->check(CLI::ExistingFile);
  command
      ->add_option(
          "--method", args.method,
          "auto (the default: fast for FE scenes, ritz when [ritz] topology is given) | fast (FE, sparse active set) | "
          "dual | primal (FE + LCP by dense Lemke) | ritz (moving contact limits) | all (side by side); "
          "overrides [solve] method")
      ->check(CLI::IsMember({"dual", "primal", "fast", "auto", "ritz", "all"}));
  command->add_option("--elements", args.elements, "Number of finite elements (overrides [solve] elements)")
      ->check(CLI::Range(1, 10'000'000));
  command->add_option("--modes", args.modes, "Ritz modes: a number, or auto (overrides [ritz] modes)")
      ->check(CLI::IsMember({"auto"}) | CLI::Range(1, 1000));
  command->add_option(
      "--tolerance", args.tolerance,
      "Accuracy wanted for the contact limits, relative to the length (arches: the angular span), in "
      "[1e-13, 0.1]: liftoff chooses the mesh (or Ritz modes) itself (overrides [solve] tolerance; wins "
      "over --elements)");
}

// What a --json failure object says about the run, filled in as it becomes known.
struct RunContext {
  std::string scene;                            // the scene's name, as in every message (empty: unknown)
  std::optional<std::string> method_requested;  // --method, else the scene's; unknown before the scene is read
  bool solve = false;                           // `liftoff solve`: the object carries the answer's keys, null
};

// The failure object of --json: one on stdout for every run that gives no answer, whatever the
// cause (CERTIFICATE.md), with the one-line message also printed on stderr.
nlohmann::json failure_json(const RunContext& context, const std::string& termination, const std::string& message,
                            ExitCode exit_code) {
  nlohmann::json j;
  j["scene"] = context.scene.empty() ? nlohmann::json() : nlohmann::json(context.scene);
  j["method_requested"] = context.method_requested ? nlohmann::json(*context.method_requested) : nlohmann::json();
  j["termination"] = termination;
  j["message"] = message;
  j["exit_code"] = code(exit_code);
  if (context.solve) {  // no answer: its keys null, as in a report without one (io/report.hpp)
    for (const char* key : io::answer_keys) j[key] = nullptr;
    // Bad input: no solver ran. An error thrown later may come after one (the Ritz start's FE
    // solve, an answer whose file could not be written): which ran is not known, so not said.
    if (termination == "bad_input") {
      j["method"] = nullptr;
      j["methods_run"] = nlohmann::json::array();
    }
  }
  return j;
}

// What every --json object carries besides its own keys.
void add_run_keys(nlohmann::json& j, const RunContext& context, ExitCode exit_code) {
  if (!j.contains("method_requested") && context.method_requested) j["method_requested"] = *context.method_requested;
  j["exit_code"] = code(exit_code);
}

// A file the run reads or writes: as named by the user (`option` 'named'), or a file the run
// keeps beside it (`what`: "temporary file", "backup file").
struct RunFile {
  std::string option;  // "--output", "the scene"
  std::filesystem::path named;
  std::filesystem::path path;
  std::string what;  // empty: the named file itself

  std::string description() const {
    return what.empty() ? fmt::format("{} '{}'", option, named.string())
                        : fmt::format("the {} '{}' of {} '{}'", what, path.string(), option, named.string());
  }
};

// Whether two names are one file: the same inode if both exist (hard and symbolic links
// included), else the same canonical path.
bool same_file(const std::filesystem::path& a, const std::filesystem::path& b) {
  std::error_code error;
  if (std::filesystem::exists(a, error) && std::filesystem::exists(b, error)) {
    const bool same = std::filesystem::equivalent(a, b, error);
    if (!error) return same;
  }
  const auto normal = [](const std::filesystem::path& p) {
    std::error_code e;
    const std::filesystem::path canonical = std::filesystem::weakly_canonical(p, e);
    return e ? std::filesystem::absolute(p, e).lexically_normal() : canonical;
  };
  return normal(a) == normal(b);
}

// No output (nor the temporary or backup beside it) may replace an input or another output of
// the same run: checked before any work, so a refused run writes nothing (InputError, exit 2).
// Nor may it replace what is not a regular file: the rename that finishes an output would put
// a file in place of a directory's name or a device (as root, --output /dev/null replaced
// /dev/null).
void check_files(const std::vector<RunFile>& inputs, const std::vector<RunFile>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const RunFile& o = outputs[i];
    std::error_code error;
    const std::filesystem::file_status status = std::filesystem::status(o.path, error);
    if (!error && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
      const char* kind = std::filesystem::is_directory(status)        ? "a directory"
                         : std::filesystem::is_character_file(status) ? "a character device"
                         : std::filesystem::is_block_file(status)     ? "a block device"
                         : std::filesystem::is_fifo(status)           ? "a named pipe"
                         : std::filesystem::is_socket(status)         ? "a socket"
                                                                      : "something other than a regular file";
      throw InputError(
          fmt::format("{} '{}': {}is {}; expected the name of a regular file, new or to be replaced "
                      "(nothing was written)",
                      o.option, o.named.string(),
                      o.what.empty() ? "" : fmt::format("its {} '{}' ", o.what, o.path.string()), kind));
    }
    const auto clash = [&](const RunFile& other) {
      if (!same_file(o.path, other.path)) return;
      throw InputError(fmt::format(
          "{} '{}': {}the same file as {}; expected an output that is neither an input nor "
          "another output of this run (nothing was written)",
          o.option, o.named.string(), o.what.empty() ? "" : fmt::format("its {} '{}' is ", o.what, o.path.string()),
          other.description()));
    };
    for (const RunFile& input : inputs) clash(input);
    for (std::size_t j = 0; j < i; ++j) clash(outputs[j]);
  }
}

std::vector<RunFile> scene_input(const std::string& scene_path) {
  if (scene_path.empty()) return {};
  return {{"the scene", scene_path, scene_path, ""}};
}

// Outputs written under a temporary name and renamed (io/hdf5_writer.hpp): both names of each
// (option, path); an empty path (the option not given) is none.
std::vector<RunFile> atomic_outputs(std::initializer_list<std::pair<std::string_view, std::string_view>> options) {
  std::vector<RunFile> outputs;
  for (const auto& [option, path] : options) {
    if (path.empty()) continue;
    outputs.push_back({std::string(option), std::string(path), std::string(path), ""});
    outputs.push_back(
        {std::string(option), std::string(path), io::temporary_path(std::string(path)), "temporary file"});
  }
  return outputs;
}

struct SolveArguments {
  ProblemArguments problem;
  bool json = false;
  std::string output;
  std::string csv_fields;  // --csv-fields
};

// The HDF5 file, then the fields CSV, of one usable report: a failure to write the CSV removes
// the HDF5 file too, so a failed run leaves neither.
void write_solve_outputs(const io::SolveReport& r, const SolveArguments& args) {
  if (!args.output.empty()) io::write_hdf5(r, args.output, LIFTOFF_VERSION);
  if (args.csv_fields.empty()) return;
  try {
    io::write_fields_csv(r, args.csv_fields);
  } catch (const OutputError&) {
    std::error_code ignored;
    if (!args.output.empty()) std::filesystem::remove(args.output, ignored);
    throw;
  }
}

// `--method all`: every method side by side; exit 3 if one that applies failed. The HDF5 file,
// if asked for, holds the first usable result (primal, dual, then Ritz); it is written before
// anything is printed, so a failure to write it leaves one JSON object (the failure's).
int run_all(const scene::Scene& scene, const SolveRequest& request, const SolveArguments& args,
            const RunContext& context, std::ostream& out, std::ostream& err) {
  std::vector<io::SolveReport> reports = solve_all_methods(scene, request);
  // A refused method's report knows nothing of the scene; the header and JSON need its k.
  const model::MemberModel model = model::make_member_model(scene);
  for (io::SolveReport& r : reports)
    if (r.outcome == io::SolveOutcome::refused) r.k = model.k, r.tensionless = model.tensionless;
  std::string failures;
  for (const auto& r : reports) {
    if (r.usable || r.outcome == io::SolveOutcome::refused) continue;
    err << "liftoff: " << scene.source_name << ": " << r.method << ": " << r.message << "\n";
    failures += fmt::format("{}{}: {}", failures.empty() ? "" : "; ", r.method, r.message);
  }
  if (failures.empty() && (!args.output.empty() || !args.csv_fields.empty()))
    for (const auto& r : reports)
      if (r.usable) {
        write_solve_outputs(r, args);
        break;
      }
  const ExitCode status = failures.empty() ? ExitCode::success : ExitCode::solver_failure;
  if (args.json) {
    nlohmann::json all;
    all["scene"] = scene.source_name;
    all["termination"] = failures.empty() ? "solved" : "failed";
    all["message"] = failures.empty() ? "every method that applies gave an answer" : failures;
    add_run_keys(all, context, status);
    all["methods"] = nlohmann::json::array();
    for (const auto& r : reports) all["methods"].push_back(io::to_json(r));
    out << all.dump(2) << "\n";
  } else {
    out << io::side_by_side(reports);
  }
  return code(status);
}

struct SweepArguments {
  ProblemArguments problem;
  std::vector<std::string> sets;
  std::string output;
  std::string csv;
  int jobs = 0;
};

scene::Scene load_scene(const std::string& path) {
  return path.empty() ? scene::parse_scene(default_scene_text, default_scene_name) : scene::read_scene_file(path);
}

// The text file a command writes last (io::write_text_file); when that fails, the output written
// before it (`written_before`, an HDF5 file; empty: none) is removed too, so a failure leaves
// neither. `what` names the file in the error.
void write_text_last(const std::string& path, const std::string& text, const std::string& written_before,
                     const std::string& what) {
  try {
    io::write_text_file(path, text, what);
  } catch (const OutputError&) {
    std::error_code error;
    if (!written_before.empty()) std::filesystem::remove(written_before, error);
    throw;
  }
}

// A command's start: the scene and every output checked before any work, then the scene read and
// its theory checked against the command's solvers (app/theory_gate.hpp).
scene::Scene checked_scene(const ProblemArguments& problem, const std::vector<RunFile>& outputs, Command command) {
  check_files(scene_input(problem.scene_path), outputs);
  scene::Scene scene = load_scene(problem.scene_path);
  require_honoured_theory(scene, command);
  return scene;
}

SolveRequest make_request(const ProblemArguments& args) {
  SolveRequest request;
  if (!args.method.empty()) request.method = scene::parse_method(args.method);
  if (args.elements > 0) request.elements = args.elements;
  if (!args.modes.empty() && args.modes != "auto") {  // CLI11 has checked an integer in [1, 1000]
    int modes = 0;
    const auto [end, error] = std::from_chars(args.modes.data(), args.modes.data() + args.modes.size(), modes);
    if (error != std::errc() || end != args.modes.data() + args.modes.size() || modes < 1 || modes > 1000)
      throw InputError(fmt::format("--modes: expected \"auto\" or an integer in [1, 1000], got '{}'", args.modes));
    request.modes = modes;
  } else if (args.modes == "auto") {
    request.modes = 0;
  }
  if (!args.tolerance.empty()) {
    double tolerance = NAN;
    const auto [end, error] =
        std::from_chars(args.tolerance.data(), args.tolerance.data() + args.tolerance.size(), tolerance);
    if (error != std::errc() || end != args.tolerance.data() + args.tolerance.size() || !std::isfinite(tolerance) ||
        !(tolerance >= scene::min_tolerance && tolerance <= scene::max_tolerance))
      throw InputError(fmt::format(
          "--tolerance: expected a number in [{:g}, {:g}] (the contact limits' accuracy relative to the length; below "
          "{:g} double precision cannot honour it), got '{}'",
          scene::min_tolerance, scene::max_tolerance, scene::min_tolerance, args.tolerance));
    request.tolerance = tolerance;
  }
  return request;
}

// A sweep's warnings on stderr (the CSV has no room for them): each distinct one once, with the
// first case that gave it, at most `shown` lines.
void print_sweep_warnings(const std::vector<io::SweepCase>& cases, std::ostream& err) {
  constexpr std::size_t shown = 20;
  std::set<std::string> seen;
  std::size_t more = 0;
  for (const auto& c : cases) {
    if (c.reports.empty()) continue;
    for (const std::string& warning : c.reports.front().warnings) {
      if (!seen.insert(warning).second) continue;
      if (seen.size() > shown)
        ++more;
      else
        err << "liftoff: warning: " << c.reports.front().scene_name << ": " << warning << "\n";
    }
  }
  if (more > 0) err << fmt::format("liftoff: warning: {} more warnings (each case's are in its JSON and HDF5)\n", more);
}

// `liftoff sweep`: CSV (to --csv, or stdout), HDF5 with every case (--output), progress on
// stderr; exit 3 if a case failed (its error is in both outputs).
int run_sweep_command(const SweepArguments& args, std::ostream& out, std::ostream& err) {
  const std::vector<RunFile> outputs = atomic_outputs({{"--output", args.output}, {"--csv", args.csv}});
  // Under MPI (app/distributed_sweep.hpp) every rank reads the scene and builds the grid; a rank
  // that cannot stops every rank before the shared work.
  std::optional<scene::Scene> scene;
  std::vector<SweepParameter> parameters;
  std::vector<std::string> keys;
  std::optional<SweepGrid> grid;
  try {
    scene = checked_scene(args.problem, outputs, Command::sweep);
    for (const std::string& set : args.sets) {
      parameters.push_back(parse_sweep_parameter(set));
      keys.push_back(parameters.back().key);
    }
    if (mpi::active()) grid = make_sweep_grid(*scene, parameters);
  } catch (const std::exception&) {
    mpi::all_ready(false);
    throw;
  }
  if (!mpi::all_ready(true))
    throw InputError(
        fmt::format("{}: sweep: another MPI rank could not read the scene or the --set values (a file "
                    "system that differs between nodes?); expected every rank to read the same scene",
                    args.problem.scene_path.empty() ? std::string(default_scene_name) : args.problem.scene_path));
  // Under MPI one thread per rank unless --jobs says otherwise: the ranks are the parallelism.
  const int jobs = args.jobs > 0 ? args.jobs : mpi::active() ? 1 : std::max(1u, std::thread::hardware_concurrency());
  std::mutex progress_lock;
  SolveRequest request = make_request(args.problem);
  request.fields = !args.output.empty();  // only the HDF5 file holds sampled fields
  const auto progress = [&](int done, int total) {
    const std::lock_guard<std::mutex> lock(progress_lock);
    const int width = 30, filled = width * done / total;
    err << "\rliftoff sweep [" << std::string(filled, '#') << std::string(width - filled, ' ') << "] " << done << "/"
        << total << (done == total ? "\n" : "") << std::flush;
  };
  std::vector<io::SweepCase> cases;
  std::string csv;
  if (mpi::active()) {
    mpi::DistributedSweep d = mpi::run_distributed_sweep(
        std::move(*grid), keys, request, solves_every_method(*scene, request), jobs, !args.output.empty(), progress);
    if (mpi::rank() != 0) return code(ExitCode::success);  // rank 0 writes, prints and decides the exit code
    cases = std::move(d.cases);
    csv = std::move(d.csv);
    if (!args.output.empty()) io::write_sweep_hdf5(keys, cases, d.images, args.output, LIFTOFF_VERSION);
  } else {
    cases = run_sweep(*scene, parameters, request, jobs, progress);
    csv = io::sweep_csv(keys, cases);
    // The HDF5 file first, then the CSV: a failure to write either leaves neither.
    if (!args.output.empty()) io::write_sweep_hdf5(keys, cases, args.output, LIFTOFF_VERSION);
  }
  if (args.csv.empty()) {
    out << csv;
  } else {
    write_text_last(args.csv, csv, args.output, "the CSV summary");
  }
  print_sweep_warnings(cases, err);
  bool failed = false;
  int unsolved = 0, answers = 0;
  std::map<std::string, int> terminations;
  for (const auto& c : cases) {
    if (!c.error.empty()) {
      err << "liftoff: " << c.error << "\n";
      failed = true;
    }
    for (const auto& r : c.reports) {
      ++answers;
      if (r.usable || r.outcome == io::SolveOutcome::refused) continue;
      failed = true;
      ++unsolved;
      ++terminations[r.termination];
    }
  }
  // One line saying why the exit code is 3, when the cases' own errors have not (a case without
  // an answer is a row of the CSV, its termination in its column).
  if (unsolved > 0) {
    std::string counts;
    for (const auto& [termination, count] : terminations)
      counts += fmt::format("{}{} x {}", counts.empty() ? "" : ", ", count, termination);
    err << fmt::format("liftoff: {}: sweep: {} of {} answers not solved ({}); see the termination column\n",
                       args.problem.scene_path.empty() ? std::string(default_scene_name) : args.problem.scene_path,
                       unsolved, answers, counts);
  }
  return code(failed ? ExitCode::solver_failure : ExitCode::success);
}

int run_solve(const SolveArguments& args, RunContext& context, std::ostream& out, std::ostream& err) {
  const std::vector<RunFile> outputs = atomic_outputs({{"--output", args.output}, {"--csv-fields", args.csv_fields}});
  const scene::Scene scene = checked_scene(args.problem, outputs, Command::solve);
  if (!context.method_requested) context.method_requested = scene::to_string(scene.solve.method);
  SolveRequest request = make_request(args.problem);
  request.fields = !args.output.empty() || !args.csv_fields.empty();  // only these files hold sampled fields

  if (request.method.value_or(scene.solve.method) == scene::Method::all)
    return run_all(scene, request, args, context, out, err);
  const io::SolveReport report = solve_scene(scene, request);
  const ExitCode status = report.usable ? ExitCode::success
                          // a von Karman load path's limit point is a loss of stability too
                          : report.termination == "unstable_equilibrium" || report.termination == "limit_point"
                              ? ExitCode::unstable_equilibrium
                              : ExitCode::solver_failure;
  if (!report.usable) err << "liftoff: " << scene.source_name << ": " << report.message << "\n";
  if (report.usable) write_solve_outputs(report, args);
  if (args.json) {
    nlohmann::json j = io::to_json(report);
    add_run_keys(j, context, status);
    out << j.dump(2) << "\n";
  } else if (report.usable) {
    out << io::text_summary(report) << (args.output.empty() ? "" : "  written       " + args.output + "\n")
        << (args.csv_fields.empty() ? "" : "  written       " + args.csv_fields + "\n");
  }
  return code(status);
}

struct TraceArguments {
  ProblemArguments problem;
  bool json = false;
  bool resume = false;
  bool progress = false;
  std::string output;
  std::string csv;              // --csv
  std::vector<std::string> at;  // --at, split at commas
};

// --at V[,V...]: the numbers, or InputError naming the option and the text that is none.
std::optional<std::vector<double>> report_at_option(const std::vector<std::string>& texts) {
  if (texts.empty()) return std::nullopt;
  std::vector<double> values;
  for (const std::string& text : texts) {
    double value = NAN;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
      throw InputError(fmt::format(
          "option '--at': expected finite numbers separated by commas (loads in the live load's unit, or load factors "
          "where the live case mixes kinds), got '{}'",
          text));
    values.push_back(value);
  }
  return values;
}

// `liftoff trace`: the summary (or --json) on stdout; on stderr a progress line when stderr is a
// terminal, and the reason when a path stops short of lambda_max (exit 3, its steps kept).
int run_trace_command(const TraceArguments& args, RunContext& context, std::ostream& out, std::ostream& err) {
  std::vector<RunFile> outputs = atomic_outputs({{"--csv", args.csv}});
  if (!args.output.empty()) {
    outputs.push_back({"--output", args.output, args.output, ""});
    outputs.push_back({"--output", args.output, io::trace_backup_path(args.output), "backup file"});
  }
  const scene::Scene scene = checked_scene(args.problem, outputs, Command::trace);
  if (!context.method_requested && scene.trace)
    context.method_requested = scene::to_string(scene.trace->method.value_or(scene.solve.method));
  const SolveRequest solve = make_request(args.problem);
  if (solve.tolerance)
    throw InputError(
        "--tolerance: not taken by trace (it follows the load path on the mesh of --elements, or Ritz's modes); "
        "expected it with solve or sweep");
  TraceRequest request;
  request.method = solve.method;
  request.elements = solve.elements;
  request.modes = solve.modes;
  request.report_at = report_at_option(args.at);
  request.output = args.output;
  request.resume = args.resume;
  request.version = LIFTOFF_VERSION;
  // On a terminal, one line rewritten at most ten times a second; with --progress elsewhere, a
  // line per step (a step counted there is already in the file).
  const bool terminal = &err == &std::cerr && ::isatty(STDERR_FILENO) == 1;
  bool progress_shown = false;
  if (terminal || args.progress) {
    auto last = std::chrono::steady_clock::now() - std::chrono::seconds(1);
    request.progress = [&err, &progress_shown, last, terminal](const TraceProgress& p) mutable {
      const auto now = std::chrono::steady_clock::now();
      if (terminal && now - last < std::chrono::milliseconds(100)) return;
      last = now;
      progress_shown = terminal;
      err << fmt::format("{}liftoff trace {}: lambda {:.6g} of [{:.6g}, {:.6g}], {} steps, {} events{}",
                         terminal ? "\r" : "", p.path, p.load_factor, p.lambda_min, p.lambda_max, p.steps, p.events,
                         terminal ? "   " : "\n")
          << std::flush;
    };
  }
  const TraceOutcome outcome = run_trace(scene, request);
  if (progress_shown) err << "\n";
  // The CSV of the steps, whole or not at all (the HDF5 file, written as the trace ran, stays: it
  // resumes); also of a trace that stopped short, whose steps hold.
  if (!args.csv.empty()) write_text_last(args.csv, trace_csv(outcome), "", "the trace CSV");
  const ExitCode status = outcome.usable() ? ExitCode::success : ExitCode::solver_failure;
  if (args.json) {
    nlohmann::json j = to_json(outcome);
    // The top-level termination and message are the run's: those of the first path that
    // stopped short of lambda_max, if one did.
    for (const PathTrace& p : outcome.paths)
      if (!p.summary.is_usable()) {
        j["termination"] = continuation::to_string(p.summary.termination);
        j["message"] = fmt::format("path {}: {}", p.path, p.summary.message);
        break;
      }
    add_run_keys(j, context, status);
    out << j.dump(2) << "\n";
  } else {
    out << text_summary(outcome) << (args.csv.empty() ? "" : "written       " + args.csv + "\n");
  }
  if (outcome.usable()) return code(ExitCode::success);
  for (const PathTrace& p : outcome.paths)
    if (!p.summary.is_usable())
      err << "liftoff: " << scene.source_name << ": trace " << p.path << " stopped at lambda "
          << (p.steps.empty() ? p.summary.final_load_factor : p.steps.back().load_factor) << ": "
          << continuation::to_string(p.summary.termination) << (p.summary.message.empty() ? "" : ", ")
          << p.summary.message << "\n";
  return code(ExitCode::solver_failure);
}

struct EnvelopeArguments {
  ProblemArguments problem;
  std::string json;
  std::string hdf5;
  int samples = 401;
  bool cold = false;
};

// `liftoff envelope`: the summary on stdout, the JSON (--json FILE) and HDF5 (--hdf5 FILE) files;
// exit 3 if a case failed (the envelope is then incomplete, and says so in every output).
int run_envelope_command(const EnvelopeArguments& args, std::ostream& out, std::ostream& err) {
  const std::vector<RunFile> outputs = atomic_outputs({{"--hdf5", args.hdf5}, {"--json", args.json}});
  const scene::Scene scene = checked_scene(args.problem, outputs, Command::envelope);
  EnvelopeRequest request;
  request.solve = make_request(args.problem);
  if (request.solve.method == scene::Method::all)
    throw InputError("--method: expected one method for envelope (dual, primal, fast, auto or ritz), got all");
  request.samples = args.samples;
  request.warm_start = !args.cold;
  const io::EnvelopeReport report = run_envelope(scene, request);
  // The HDF5 file first, then the JSON: a failure to write either leaves neither.
  if (!args.hdf5.empty()) io::write_envelope_hdf5(report, args.hdf5, LIFTOFF_VERSION);
  if (!args.json.empty()) {
    nlohmann::json j = io::to_json(report);
    j["exit_code"] = code(report.complete() ? ExitCode::success : ExitCode::solver_failure);
    write_text_last(args.json, j.dump(2) + "\n", args.hdf5, "the JSON file");
  }
  out << io::text_summary(report);
  if (report.complete()) return code(ExitCode::success);
  err << fmt::format("liftoff: {}: envelope: {} of {} cases not certified; the envelope is incomplete\n",
                     scene.source_name, report.failed_cases(), report.cases.size());
  return code(ExitCode::solver_failure);
}

}  // namespace

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  CLI::App app{"liftoff: beams and arches on a tensionless elastic foundation (FE + LCP by Lemke, Ritz by Newton)",
               "liftoff"};
  app.set_version_flag("--version", LIFTOFF_VERSION);
  app.require_subcommand(1);

  SolveArguments solve;
  CLI::App* solve_command = app.add_subcommand(
      "solve", "Solve one scene: contact regions, deflection, forces and reactions along the member");
  add_problem_options(solve_command, solve.problem);
  solve_command->add_flag("--json", solve.json, "Print one JSON object on stdout instead of the summary");
  solve_command->add_option("--output,-o", solve.output, "Write every field to this HDF5 file");
  solve_command->add_option(
      "--csv-fields", solve.csv_fields,
      "Write the sampled fields to this CSV file (position, w, rotation, moment, shear, reaction)");

  SweepArguments sweep;
  CLI::App* sweep_command =
      app.add_subcommand("sweep", "Solve one scene for every combination of values of some of its keys, in parallel");
  sweep_command
      ->add_option("--set", sweep.sets,
                   "KEY=VALUES, e.g. foundation.nondimensional_k=10,100,1e3 or foundation.modulus=log:1e6:1e8:7 or "
                   "loads[0].value=lin:0:1:5; "
                   "repeat for a grid")
      ->required();
  add_problem_options(sweep_command, sweep.problem);
  sweep_command->add_option("--output,-o", sweep.output, "Write every case to this HDF5 file");
  sweep_command->add_option("--csv", sweep.csv, "Write the CSV summary here (default: stdout)");
  sweep_command->add_option("--jobs,-j", sweep.jobs, "Cases solved at once (default: the machine's cores)")
      ->check(CLI::Range(1, 1024));

  TraceArguments trace;
  CLI::App* trace_command = app.add_subcommand(
      "trace", "Follow the load history F = F_dead + lambda F_live ([trace] table): contact regions and events");
  add_problem_options(trace_command, trace.problem);
  trace_command->get_option("scene")->required()->description(
      "Scene file (TOML) with a [trace] table (lambda_max); required (the default scene of `solve` has none)");
  trace_command->get_option("--method")
      ->description(
          "dual | primal | auto: the FE path; ritz: the Ritz path; all: both, events side by side; "
          "overrides [trace] method");
  trace_command->add_flag("--json", trace.json, "Print one JSON object on stdout instead of the summary");
  trace_command->add_option("--output,-o", trace.output, "Write the trace to this HDF5 file as it runs");
  trace_command->add_flag("--resume", trace.resume, "Continue the --output file from its last finished step");
  trace_command->add_option("--csv", trace.csv, "Write one CSV row per step here (lambda, load, design values, ...)");
  trace_command
      ->add_option("--at", trace.at,
                   "Record the state at these loads, V[,V...] (in the live load's unit where it is of one kind, "
                   "else load factors); overrides [trace] report_at")
      ->delimiter(',');
  trace_command->add_flag("--progress", trace.progress,
                          "Progress on stderr, a line per step, even when stderr is not a terminal");

  PlotRequest plot;
  CLI::App* plot_command = app.add_subcommand(
      "plot", "Draw the pictures of a result file (solve, trace or sweep --output; envelope --hdf5) as PNG files");
  plot_command->add_option("file", plot.file, "HDF5 file written by liftoff solve, trace, sweep or envelope")
      ->required()
      ->check(CLI::ExistingFile);
  plot_command->add_option("--out", plot.out, "Prefix of the PNG files (default: the file's name without .h5)");
  plot_command->add_flag("--normalise", plot.normalise,
                         "Sweeps only: each case's curves divided by their own largest magnitude");
  EnvelopeArguments envelope;
  CLI::App* envelope_command = app.add_subcommand(
      "envelope",
      "Solve every load combination ([[combinations]]) and moving-load position ([moving]): envelopes, governing "
      "cases, lift-off map");
  add_problem_options(envelope_command, envelope.problem);
  envelope_command->get_option("scene")->required()->description(
      "Scene file (TOML) with [[combinations]] and/or a [moving] table; required");
  envelope_command->add_option("--json", envelope.json, "Write the envelope as JSON to this file");
  envelope_command->add_option("--hdf5", envelope.hdf5, "Write the envelope to this HDF5 file");
  envelope_command->add_option("--samples", envelope.samples, "Points of the envelope grid along the member")
      ->check(CLI::Range(2, 1'000'000));
  envelope_command->add_flag("--no-warm-start", envelope.cold,
                             "Start every position from the solver's default contact set (to measure the warm start)");

  const bool json_asked =
      std::any_of(argv + 1, argv + argc, [](const char* a) { return std::string_view(a) == "--json"; });
  RunContext context;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) {  // --help, --version
      app.exit(e, out, err);
      return code(ExitCode::success);
    }
    // One line, as every other error (CLI11's own adds a second).
    std::string message = e.what();
    std::replace(message.begin(), message.end(), '\n', ' ');
    const CLI::App* command = *solve_command      ? solve_command
                              : *sweep_command    ? sweep_command
                              : *trace_command    ? trace_command
                              : *plot_command     ? plot_command
                              : *envelope_command ? envelope_command
                                                  : &app;
    err << "liftoff: " << message << " (see liftoff" << (command == &app ? "" : " " + command->get_name())
        << " --help)\n";
    // --json asked for and the command line refused: still one object on stdout.
    if (json_asked) {
      const ProblemArguments* problem = *solve_command   ? &solve.problem
                                        : *trace_command ? &trace.problem
                                        : *sweep_command ? &sweep.problem
                                                         : nullptr;
      context.solve = static_cast<bool>(*solve_command);
      if (problem != nullptr) {
        context.scene = problem->scene_path;
        if (!problem->method.empty()) context.method_requested = problem->method;
      }
      out << failure_json(context, "bad_input", message, ExitCode::bad_input).dump(2) << "\n";
    }
    return code(ExitCode::bad_input);
  }

  const ProblemArguments& problem = *solve_command      ? solve.problem
                                    : *sweep_command    ? sweep.problem
                                    : *envelope_command ? envelope.problem
                                                        : trace.problem;
  context.scene = problem.scene_path.empty() ? std::string(default_scene_name) : problem.scene_path;
  if (!problem.method.empty()) context.method_requested = problem.method;
  context.solve = static_cast<bool>(*solve_command);
  const bool json = (*solve_command && solve.json) || (*trace_command && trace.json);
  const auto fail = [&](const std::string& termination, const std::string& message, ExitCode status) {
    err << "liftoff: " << message << "\n";
    if (json) out << failure_json(context, termination, message, status).dump(2) << "\n";
    return code(status);
  };
  // Under MPI only sweeps are shared out; any other command runs on rank 0 alone (the other ranks'
  // exit code is rank 0's: app/distributed_sweep.hpp).
  if (!*sweep_command && mpi::rank() != 0) return code(ExitCode::success);
  try {
    if (*plot_command) return run_plot(plot);
    if (*solve_command) return run_solve(solve, context, out, err);
    if (*sweep_command) return run_sweep_command(sweep, out, err);
    if (*trace_command) return run_trace_command(trace, context, out, err);
    if (*envelope_command) return run_envelope_command(envelope, out, err);
  } catch (const InputError& e) {
    return fail("bad_input", e.what(), ExitCode::bad_input);
  } catch (const UnstableEquilibrium& e) {
    return fail("unstable_equilibrium", e.what(), ExitCode::unstable_equilibrium);
  } catch (const SolverFailure& e) {
    return fail("refused", e.what(), ExitCode::solver_failure);
  } catch (const OutputError& e) {
    return fail("output_error", e.what(), ExitCode::output_error);
  } catch (const std::exception& e) {
    return fail("internal_error", std::string("internal error: ") + e.what(), ExitCode::internal_error);
  }
  return code(ExitCode::internal_error);
}

}  // namespace liftoff::app
