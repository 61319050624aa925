#include "app/cli.hpp"

#include <CLI/CLI.hpp>
#include <filesystem>

#include "app/solve_command.hpp"
#include "core/error.hpp"
#include "default_scene.hpp"
#include "io/hdf5_writer.hpp"
#include "scene/scene_reader.hpp"

namespace liftoff::app {

namespace {

int code(ExitCode c) { return static_cast<int>(c); }

struct SolveArguments {
  std::string scene_path;
  std::string method;
  int elements = 0;
  bool json = false;
  std::string output;
};

int run_solve(const SolveArguments& args, std::ostream& out, std::ostream& err) {
  const scene::Scene scene = args.scene_path.empty()
                                 ? scene::parse_scene(default_scene_text, default_scene_name)
                                 : scene::read_scene_file(args.scene_path);
  SolveRequest request;
  if (!args.method.empty()) request.method = scene::parse_method(args.method);
  if (args.elements > 0) request.elements = args.elements;

  const io::SolveReport report = solve_scene(scene, request);
  if (!report.summary.is_usable()) {
    err << "liftoff: " << scene.source_name << ": " << report.summary.message << "\n";
    return code(ExitCode::solver_failure);
  }
  if (!args.output.empty()) io::write_hdf5(report, args.output, LIFTOFF_VERSION);
  if (args.json)
    out << io::to_json(report).dump(2) << "\n";
  else
    out << io::text_summary(report) << (args.output.empty() ? "" : "  written       " + args.output + "\n");
  return code(ExitCode::success);
}

}  // namespace

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  CLI::App app{"liftoff: beams and arches on a tensionless elastic foundation (FE + LCP, Lemke)", "liftoff"};
  app.set_version_flag("--version", LIFTOFF_VERSION);
  app.require_subcommand(1);

  SolveArguments solve;
  CLI::App* solve_command = app.add_subcommand(
      "solve", "Solve one scene: contact regions, deflection, forces and reactions along the member");
  solve_command->add_option("scene", solve.scene_path, "Scene file (TOML); default: the seed paper's arch, roller ends")
      ->check(CLI::ExistingFile);
  solve_command->add_option("--method", solve.method, "Contact formulation: dual | primal | auto (overrides [solve] method)")
      ->check(CLI::IsMember({"dual", "primal", "auto"}));
  solve_command->add_option("--elements", solve.elements, "Number of finite elements (overrides [solve] elements)")
      ->check(CLI::Range(1, 10'000'000));
  solve_command->add_flag("--json", solve.json, "Print one JSON object on stdout instead of the summary");
  solve_command->add_option("--output,-o", solve.output, "Write every field to this HDF5 file");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int status = app.exit(e, out, err);
    return status == 0 ? code(ExitCode::success) : code(ExitCode::bad_input);
  }

  try {
    if (*solve_command) return run_solve(solve, out, err);
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
