#include "app/cli.hpp"

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <iostream>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <thread>

#include "app/solve_command.hpp"
#include "app/sweep_command.hpp"
#include "app/trace_command.hpp"
#include "core/error.hpp"
#include "default_scene.hpp"
#include "io/hdf5_writer.hpp"
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
};

void add_problem_options(CLI::App* command, ProblemArguments& args) {
  command->add_option("scene", args.scene_path, "Scene file (TOML); default: the seed paper's arch, roller ends")
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
}

struct SolveArguments {
  ProblemArguments problem;
  bool json = false;
  std::string output;
};

// `--method all`: every method side by side; exit 3 if one that applies failed. The HDF5 file,
// if asked for, holds the first usable result (primal, dual, then Ritz).
int run_all(const scene::Scene& scene, const SolveRequest& request, const SolveArguments& args, std::ostream& out,
            std::ostream& err) {
  const std::vector<io::SolveReport> reports = solve_all_methods(scene, request);
  bool failed = false;
  for (const auto& r : reports) {
    if (r.usable || r.termination == "refused") continue;
    err << "liftoff: " << scene.source_name << ": " << r.method << ": " << r.message << "\n";
    failed = true;
  }
  if (args.json) {
    nlohmann::json all;
    all["scene"] = scene.source_name;
    all["methods"] = nlohmann::json::array();
    for (const auto& r : reports) all["methods"].push_back(io::to_json(r));
    out << all.dump(2) << "\n";
  } else {
    out << io::side_by_side(reports);
  }
  if (failed) return code(ExitCode::solver_failure);
  if (!args.output.empty())
    for (const auto& r : reports)
      if (r.usable) {
        io::write_hdf5(r, args.output, LIFTOFF_VERSION);
        break;
      }
  return code(ExitCode::success);
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

SolveRequest make_request(const ProblemArguments& args) {
  SolveRequest request;
  if (!args.method.empty()) request.method = scene::parse_method(args.method);
  if (args.elements > 0) request.elements = args.elements;
  if (!args.modes.empty()) request.modes = args.modes == "auto" ? 0 : std::stoi(args.modes);
  return request;
}

// `liftoff sweep`: CSV (to --csv, or stdout), HDF5 with every case (--output), progress on
// stderr; exit 3 if a case failed (its error is in both outputs).
int run_sweep_command(const SweepArguments& args, std::ostream& out, std::ostream& err) {
  const scene::Scene scene = load_scene(args.problem.scene_path);
  std::vector<SweepParameter> parameters;
  std::vector<std::string> keys;
  for (const std::string& set : args.sets) {
    parameters.push_back(parse_sweep_parameter(set));
    keys.push_back(parameters.back().key);
  }
  const int jobs = args.jobs > 0 ? args.jobs : std::max(1u, std::thread::hardware_concurrency());
  std::mutex progress_lock;
  const auto cases = run_sweep(scene, parameters, make_request(args.problem), jobs,
                               [&](int done, int total) {
                                 const std::lock_guard<std::mutex> lock(progress_lock);
                                 const int width = 30, filled = width * done / total;
                                 err << "\rliftoff sweep [" << std::string(filled, '#') << std::string(width - filled, ' ')
                                     << "] " << done << "/" << total << (done == total ? "\n" : "") << std::flush;
                               });
  const std::string csv = io::sweep_csv(keys, cases);
  if (args.csv.empty()) {
    out << csv;
  } else {
    std::ofstream file(args.csv + ".tmp");
    file << csv;
    file.close();
    std::error_code error;
    if (!file || (std::filesystem::rename(args.csv + ".tmp", args.csv, error), error)) {
      std::filesystem::remove(args.csv + ".tmp", error);
      throw OutputError(args.csv + ": cannot write the CSV summary");
    }
  }
  if (!args.output.empty()) io::write_sweep_hdf5(keys, cases, args.output, LIFTOFF_VERSION);
  bool failed = false;
  for (const auto& c : cases) {
    if (!c.error.empty()) {
      err << "liftoff: " << c.error << "\n";
      failed = true;
    }
    for (const auto& r : c.reports)
      failed |= !r.usable && r.termination != "refused";
  }
  return code(failed ? ExitCode::solver_failure : ExitCode::success);
}

int run_solve(const SolveArguments& args, std::ostream& out, std::ostream& err) {
  const scene::Scene scene = load_scene(args.problem.scene_path);
  SolveRequest request = make_request(args.problem);
  request.fields = !args.output.empty();  // only the HDF5 file holds sampled fields

  if (request.method.value_or(scene.solve.method) == scene::Method::all) return run_all(scene, request, args, out, err);
  const io::SolveReport report = solve_scene(scene, request);
  if (!report.usable) {
    err << "liftoff: " << scene.source_name << ": " << report.message << "\n";
    return code(ExitCode::solver_failure);
  }
  if (!args.output.empty()) io::write_hdf5(report, args.output, LIFTOFF_VERSION);
  if (args.json)
    out << io::to_json(report).dump(2) << "\n";
  else
    out << io::text_summary(report) << (args.output.empty() ? "" : "  written       " + args.output + "\n");
  return code(ExitCode::success);
}

struct TraceArguments {
  ProblemArguments problem;
  bool json = false;
  bool resume = false;
  bool progress = false;
  std::string output;
};

// `liftoff trace`: the summary (or --json) on stdout; on stderr a progress line when stderr is a
// terminal, and the reason when a path stops short of lambda_max (exit 3, its steps kept).
int run_trace_command(const TraceArguments& args, std::ostream& out, std::ostream& err) {
  const scene::Scene scene = load_scene(args.problem.scene_path);
  const SolveRequest solve = make_request(args.problem);
  TraceRequest request;
  request.method = solve.method;
  request.elements = solve.elements;
  request.modes = solve.modes;
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
  if (args.json)
    out << to_json(outcome).dump(2) << "\n";
  else
    out << text_summary(outcome);
  if (outcome.usable()) return code(ExitCode::success);
  for (const PathTrace& p : outcome.paths)
    if (!p.summary.is_usable())
      err << "liftoff: " << scene.source_name << ": trace " << p.path << " stopped at lambda "
          << (p.steps.empty() ? p.summary.final_load_factor : p.steps.back().load_factor) << ": "
          << continuation::to_string(p.summary.termination) << (p.summary.message.empty() ? "" : ", ")
          << p.summary.message << "\n";
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

  SweepArguments sweep;
  CLI::App* sweep_command =
      app.add_subcommand("sweep", "Solve one scene for every combination of values of some of its keys, in parallel");
  sweep_command
      ->add_option("--set", sweep.sets,
                   "KEY=VALUES, e.g. foundation.k=10,100,1e3 or foundation.k=log:10:1e4:7 or loads[0].value=lin:0:1:5; "
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
  trace_command->get_option("--method")
      ->description("dual | primal | auto: the FE path; ritz: the Ritz path; all: both, events side by side; "
                    "overrides [trace] method");
  trace_command->add_flag("--json", trace.json, "Print one JSON object on stdout instead of the summary");
  trace_command->add_option("--output,-o", trace.output, "Write the trace to this HDF5 file as it runs");
  trace_command->add_flag("--resume", trace.resume, "Continue the --output file from its last finished step");
  trace_command->add_flag("--progress", trace.progress,
                          "Progress on stderr, a line per step, even when stderr is not a terminal");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int status = app.exit(e, out, err);
    return status == 0 ? code(ExitCode::success) : code(ExitCode::bad_input);
  }

  try {
    if (*solve_command) return run_solve(solve, out, err);
    if (*sweep_command) return run_sweep_command(sweep, out, err);
    if (*trace_command) return run_trace_command(trace, out, err);
  } catch (const InputError& e) {
    err << "liftoff: " << e.what() << "\n";
    return code(ExitCode::bad_input);
  } catch (const SolverFailure& e) {
    err << "liftoff: " << e.what() << "\n";
    return code(ExitCode::solver_failure);
  } catch (const OutputError& e) {
    err << "liftoff: " << e.what() << "\n";
    return code(ExitCode::output_error);
  } catch (const std::exception& e) {
    err << "liftoff: internal error: " << e.what() << "\n";
    return code(ExitCode::internal_error);
  }
  return code(ExitCode::internal_error);
}

}  // namespace liftoff::app
