// `liftoff trace`: options from [trace], the HDF5 trace written as the path runs, resume after
// an interruption (in-process and by SIGKILL), the comparisons of `method = "all"` and `refine`,
// and the command line. Most tests drive run_trace with a synthetic path, so they test this
// command's logic whatever the paths do; the tests tagged [real_paths] run trace_fe and
// trace_ritz end to end.
#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <thread>

#include "app/cli.hpp"
#include "app/trace_command.hpp"
#include "app/trace_load.hpp"
#include "core/error.hpp"
#include "io/trace_writer.hpp"
#include "model/member_model.hpp"
#include "scene/scene_reader.hpp"
#include "support/cli.hpp"
#include "support/scenes.hpp"
#include "support/scratch.hpp"

using namespace liftoff;
using continuation::EventKind;
using continuation::TraceEvent;
using continuation::TraceOptions;
using continuation::TraceStep;
namespace fs = std::filesystem;

using namespace liftoff::test;  // support/: the CLI runner, the scratch directory

namespace {

// A free-free beam, dead uniform load, live upward central force (continuation/scenes has the
// physics); `trace` is the [trace] table's body.
std::string beam_with_trace(const std::string& trace) {
  return "[structure]\nkind = \"beam\"\nlength = 10.0\nEI = 1.0e4\n[supports]\nleft = \"free\"\nright = \"free\"\n"
         "[foundation]\nk = 500.0\n[[loads]]\nkind = \"uniform\"\nvalue = 1.0\ncase = \"dead\"\n"
         "[[loads]]\nkind = \"force\"\nat = 4.0\nvalue = -1.0\n[solve]\nmethod = \"auto\"\nelements = 50\n" +
         (trace.empty() ? std::string() : "[trace]\n" + trace);
}

scene::Scene scene_with_trace(const std::string& trace) {
  return scene::parse_scene(beam_with_trace(trace), "beam.toml");
}

struct Interrupted : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A path with a known answer: steps of max_step in lambda from lambda_min (the first step is
// the dead load alone), one contact region [0, c] with c falling linearly from L to L/2, and two
// events (at 30% and 70% of the range) reported after the step that passes them. The state is
// (lambda, c), so a resumed run can check what it was given. Throws Interrupted after
// `stop_after` new steps, as a run that is stopped.
struct SyntheticPath {
  int stop_after = -1;
  std::chrono::milliseconds delay{0};
  std::vector<TraceOptions> calls;  // the options of every call, resume_from included

  app::TracePath path() {
    return [this](const model::MemberModel& member, const TraceOptions& o, const continuation::TraceSink& sink) {
      calls.push_back(o);
      const double begin = member.user_from_s(member.s_begin);
      const double range = o.arc_length.lambda_max - o.arc_length.lambda_min,
                   length = member.user_from_s(member.s_end) - begin;
      const int n = static_cast<int>(std::ceil(range / o.arc_length.max_step - 1e-9));
      int first = 0;
      if (o.resume_from)
        first = static_cast<int>(
                    std::lround((o.resume_from->load_factor - o.arc_length.lambda_min) / o.arc_length.max_step)) +
                1;
      continuation::TraceResult result;
      result.summary.path = continuation::PathKind::fe;  // a synthetic stand-in for either path
      const double event_at[2] = {o.arc_length.lambda_min + 0.3 * range, o.arc_length.lambda_min + 0.7 * range};
      for (int i = first; i <= n; ++i) {
        if (stop_after >= 0 && i - first == stop_after) throw Interrupted("stopped");
        std::this_thread::sleep_for(delay);
        const double lambda = std::min(o.arc_length.lambda_max, o.arc_length.lambda_min + i * o.arc_length.max_step);
        const double c = length * (1 - 0.5 * (lambda - o.arc_length.lambda_min) / range);
        TraceStep s;
        s.load_factor = lambda;
        s.contact_regions = {{begin, begin + c}};
        for (const double x : o.sample_points) {
          s.deflection.push_back(1e-3 * (1 + lambda * (x - o.monitor)));
          s.reaction.push_back(500 * s.deflection.back());
        }
        s.monitor_deflection = 1e-3;
        s.iterations = i;
        s.state_topology = continuation::RitzTopology{true, 1, 4, continuation::RitzOpening{-1.0, 0.125}};
        s.state = {lambda, c};
        sink.on_step(s);
        result.steps.push_back(s);
        const double previous = o.arc_length.lambda_min + (i - 1) * o.arc_length.max_step;
        for (int e = 0; e < 2; ++e) {
          if (i == 0 || !(previous < event_at[e] && event_at[e] <= lambda)) continue;
          const TraceEvent event{event_at[e], e == 0 ? EventKind::lift_off_opens : EventKind::limit_at_load,
                                 begin + length * (1 - 0.5 * (event_at[e] - o.arc_length.lambda_min) / range),
                                 "synthetic event " + std::to_string(e)};
          sink.on_event(event);
          result.events.push_back(event);
        }
      }
      result.summary.termination = continuation::TraceTermination::completed;
      result.summary.steps = static_cast<int>(result.steps.size());
      return result;
    };
  }
  app::TracePaths paths() { return {path(), path()}; }
};

app::TraceRequest to_file(const fs::path& output, bool resume = false) {
  app::TraceRequest r;
  r.output = output;
  r.resume = resume;
  r.version = "test";
  return r;
}

std::vector<double> lambdas(const io::TracePathRecord& p) {
  std::vector<double> l;
  for (const auto& s : p.steps) l.push_back(s.load_factor);
  return l;
}

void check_same_events(const std::vector<TraceEvent>& a, const std::vector<TraceEvent>& b) {
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i].load_factor == b[i].load_factor);
    CHECK(a[i].kind == b[i].kind);
    CHECK(a[i].at == b[i].at);
  }
}

// Runs `child` in a forked process whose stderr is a pipe; reads the pipe's lines until
// `enough(line)` says so, then kills the child with SIGKILL. Returns false if the child ended
// first (then there was nothing to interrupt).
template <class Child, class Enough>
bool kill_midway(Child child, Enough enough) {
  int pipe_fds[2];
  REQUIRE(::pipe(pipe_fds) == 0);
  std::cout.flush();
  std::cerr.flush();
  const pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    ::close(pipe_fds[0]);
    ::dup2(pipe_fds[1], STDERR_FILENO);
    ::close(pipe_fds[1]);
    const int devnull = ::open("/dev/null", O_WRONLY);
    ::dup2(devnull, STDOUT_FILENO);
    child();
    ::_exit(0);
  }
  ::close(pipe_fds[1]);
  std::string line;
  bool killed = false;
  char c;
  while (::read(pipe_fds[0], &c, 1) == 1) {
    if (c != '\n') {
      line += c;
      continue;
    }
    if (enough(line)) {
      ::kill(pid, SIGKILL);
      killed = true;
      break;
    }
    line.clear();
  }
  ::close(pipe_fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return killed && WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
}

// "liftoff trace ritz: lambda 0.5 of [0, 8], 12 steps, 0 events" -> 12
int steps_in(const std::string& progress_line) {
  const auto comma = progress_line.find("], ");
  return comma == std::string::npos ? 0 : std::stoi(progress_line.substr(comma + 3));
}

}  // namespace

TEST_CASE("trace: options come from [trace], [solve] and [ritz], with the request's overrides", "[app][trace]") {
  const scene::Scene s = scene_with_trace(
      "lambda_min = 1\nlambda_max = 3\ncontrol = \"load\"\ninitial_step = 0.02\n"
      "min_step = 1e-4\nmax_step = 0.1\nmax_steps = 77\nsamples = 5\n");
  const TraceOptions o = app::trace_options(s, {});
  CHECK(o.arc_length.lambda_min == 1);
  CHECK(o.arc_length.lambda_max == 3);
  CHECK(o.arc_length.control == continuation::PathControl::load);
  CHECK(o.arc_length.initial_step == 0.02);
  CHECK(o.arc_length.min_step == 1e-4);
  CHECK(o.arc_length.max_step == 0.1);
  CHECK(o.arc_length.max_steps == 77);
  CHECK(o.elements == 50);
  CHECK(o.ritz.modes == 0);
  CHECK(o.monitor == 4.0);  // the first live point force
  CHECK(o.sample_points == std::vector<double>{0, 2.5, 5, 7.5, 10});
  CHECK_FALSE(o.resume_from.has_value());

  app::TraceRequest request;
  request.elements = 80;
  request.modes = 12;
  const TraceOptions overridden = app::trace_options(s, request);
  CHECK(overridden.elements == 80);
  CHECK(overridden.ritz.modes == 12);
  CHECK(app::trace_options(scene_with_trace("lambda_max = 1\nmonitor = 2.5\n"), {}).monitor == 2.5);

  // The method: [trace], else [solve]; the request overrides both.
  CHECK(app::trace_path_names(s, {}) == std::vector<std::string>{"fe"});
  CHECK(app::trace_path_names(scene_with_trace("lambda_max = 1\nmethod = \"ritz\"\n"), {}) ==
        std::vector<std::string>{"ritz"});
  request.method = scene::Method::all;
  CHECK(app::trace_path_names(s, request) == std::vector<std::string>{"fe", "ritz"});
  CHECK(app::trace_path_names(scene_with_trace("lambda_max = 1\nrefine = true\n"), request) ==
        std::vector<std::string>{"fe", "ritz", "fe_refined"});
}

TEST_CASE("trace: [trace] method reaches the FE path as its contact solver", "[app][trace]") {
  const auto contact_method = [](const char* trace, const app::TraceRequest& request = {}) {
    return app::trace_options(scene_with_trace(trace), request).contact_method;
  };
  CHECK(contact_method("lambda_max = 1\nmethod = \"dual\"\n") == contact::Method::dual);
  CHECK(contact_method("lambda_max = 1\nmethod = \"primal\"\n") == contact::Method::primal);
  CHECK(contact_method("lambda_max = 1\nmethod = \"fast\"\n") == contact::Method::fast);
  // "all" runs the FE path beside the Ritz one: automatic for it.
  CHECK(contact_method("lambda_max = 1\nmethod = \"all\"\n") == contact::Method::automatic);
  app::TraceRequest request;
  request.method = scene::Method::primal;
  CHECK(contact_method("lambda_max = 1\nmethod = \"dual\"\n", request) == contact::Method::primal);

  // Run through the app, the FE path reports the formulation it solved with: a simply supported
  // beam (dual needs a stable structure) whose live end moments have lifted its left end off by
  // lambda_min = 5, so the start is not full contact and needs a contact solve.
  const auto run = [](const char* method) {
    const std::string text = fmt::format(
        "[structure]\nkind = \"beam\"\nlength = 1.0\nEI = 1.0\n[supports]\nleft = \"pinned\"\nright = \"pinned\"\n"
        "[foundation]\nnondimensional_k = 1.0e4\n[[loads]]\nkind = \"uniform\"\nvalue = 100.0\ncase = \"dead\"\n"
        "[[loads]]\nkind = \"moment\"\nat = 0.0\nvalue = 1.0\n[[loads]]\nkind = \"moment\"\nat = 1.0\nvalue = 1.0\n"
        "[solve]\nelements = 80\n[trace]\nlambda_min = 5\nlambda_max = 6\nmethod = \"{}\"\n",
        method);
    return app::run_trace(scene::parse_scene(text, "pinned.toml"), {});
  };
  const app::TraceOutcome dual = run("dual"), primal = run("primal"), fast = run("fast");
  for (const app::TraceOutcome* o : {&dual, &primal, &fast}) {
    REQUIRE(o->paths.size() == 1);
    INFO(o->paths[0].summary.message);
    CHECK(o->paths[0].summary.contact_solves >= 1);
  }
  CHECK(dual.paths[0].summary.contact_method == contact::Method::dual);
  CHECK(primal.paths[0].summary.contact_method == contact::Method::primal);
  CHECK(fast.paths[0].summary.contact_method == contact::Method::fast);
  // Same answer whichever solver found the start.
  REQUIRE(dual.paths[0].events.size() == fast.paths[0].events.size());
  REQUIRE(primal.paths[0].events.size() == fast.paths[0].events.size());
  for (std::size_t i = 0; i < fast.paths[0].events.size(); ++i) {
    CHECK(dual.paths[0].events[i].load_factor == Approx(fast.paths[0].events[i].load_factor).epsilon(1e-9));
    CHECK(primal.paths[0].events[i].load_factor == Approx(fast.paths[0].events[i].load_factor).epsilon(1e-9));
  }
}

TEST_CASE("trace: no [trace] or no lambda_max is a one-line error naming the key", "[app][trace][errors]") {
  const auto message = [](const scene::Scene& s) {
    try {
      app::trace_options(s, {});
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  CHECK(message(scene_with_trace("")) ==
        "beam.toml: key 'trace': missing (expected a table [trace] with lambda_max, the largest load factor)");
  CHECK(message(scene_with_trace("lambda_min = 0.5\n")) ==
        "beam.toml:21: key 'trace.lambda_max': missing (expected a number > lambda_min = 0.5)");
  CHECK_THROWS_WITH(
      app::trace_path_names(scene_with_trace("lambda_max = 1\nmethod = \"ritz\"\nrefine = true\n"), {}),
      Catch::Matchers::StartsWith("beam.toml:21: key 'trace.refine': expected false with method \"ritz\""));
}

TEST_CASE("trace: every step and event goes to the file, and to the JSON", "[app][trace]") {
  Scratch scratch;
  const scene::Scene s = scene_with_trace("lambda_max = 2\nmax_step = 0.25\nsamples = 11\n");
  SyntheticPath synthetic;
  const app::TraceOutcome outcome = app::run_trace(s, to_file(scratch.dir / "t.h5"), synthetic.paths());
  REQUIRE(outcome.usable());
  REQUIRE(outcome.paths.size() == 1);
  const app::PathTrace& fe = outcome.paths[0];
  CHECK(fe.steps.size() == 9);  // lambda = 0, 0.25, ..., 2
  CHECK(fe.events.size() == 2);

  const io::TraceFileRecord file = io::read_trace_file(scratch.dir / "t.h5");
  CHECK(file.complete);
  CHECK(file.info.scene_text == s.text);
  CHECK(file.info.sample_points.size() == 11);
  REQUIRE(file.paths.size() == 1);
  const io::TracePathRecord& written = file.paths[0].second;
  CHECK(written.complete);
  CHECK(written.termination == "completed");
  CHECK(written.monitor == 4.0);
  REQUIRE(written.steps.size() == 9);
  for (std::size_t i = 0; i < 9; ++i) {
    CHECK(written.steps[i].load_factor == fe.steps[i].load_factor);
    CHECK(written.steps[i].contact_regions == fe.steps[i].contact_regions);
    CHECK(written.steps[i].deflection.size() == 11);
  }
  check_same_events(written.events, fe.events);

  const nlohmann::json j = app::to_json(outcome);
  REQUIRE(j["events"].size() == 2);
  for (const auto& e : j["events"]) {
    CHECK(e.contains("lambda"));
    CHECK(e.contains("kind"));
    CHECK(e.contains("at"));
  }
  CHECK(j["events"][0]["kind"] == "lift_off_opens");
  CHECK(j["events"][0]["lambda"] == Approx(0.6).epsilon(1e-14));
  CHECK(j["steps"].size() == 9);
  CHECK(j["steps"][8]["lambda"] == 2.0);
  CHECK(j["termination"] == "completed");
  CHECK_THAT(app::text_summary(outcome), Catch::Matchers::Contains("lift_off_opens"));
}

TEST_CASE("trace: an interrupted trace keeps its steps and resumes to the uninterrupted result", "[app][trace]") {
  Scratch scratch;
  const scene::Scene s = scene_with_trace("lambda_max = 3\nmax_step = 0.25\nsamples = 7\n");
  SyntheticPath whole;
  app::run_trace(s, to_file(scratch.dir / "whole.h5"), whole.paths());
  const io::TracePathRecord expected = io::read_trace_file(scratch.dir / "whole.h5").paths[0].second;

  SyntheticPath stopped;
  stopped.stop_after = 5;
  CHECK_THROWS_AS(app::run_trace(s, to_file(scratch.dir / "t.h5"), stopped.paths()), Interrupted);
  const io::TraceFileRecord partial = io::read_trace_file(scratch.dir / "t.h5");
  CHECK_FALSE(partial.complete);
  REQUIRE(partial.paths[0].second.steps.size() == 5);
  CHECK_FALSE(partial.paths[0].second.complete);

  SyntheticPath resumed;
  const app::TraceOutcome outcome = app::run_trace(s, to_file(scratch.dir / "t.h5", true), resumed.paths());
  REQUIRE(resumed.calls.size() == 1);
  REQUIRE(resumed.calls[0].resume_from.has_value());
  CHECK(resumed.calls[0].resume_from->load_factor == 1.0);  // the fifth step, lambda = 4 x 0.25
  CHECK(resumed.calls[0].resume_from->state == partial.paths[0].second.steps.back().state);
  CHECK(resumed.calls[0].resume_from->state_topology ==
        continuation::StateTopology{continuation::RitzTopology{true, 1, 4, continuation::RitzOpening{-1.0, 0.125}}});
  CHECK(outcome.paths[0].resumed_steps == 5);
  CHECK(outcome.paths[0].steps.size() == expected.steps.size());

  const io::TraceFileRecord done = io::read_trace_file(scratch.dir / "t.h5");
  CHECK(done.complete);
  CHECK(lambdas(done.paths[0].second) == lambdas(expected));
  check_same_events(done.paths[0].second.events, expected.events);

  // A complete file resumes to itself without running the path again.
  SyntheticPath again;
  const app::TraceOutcome repeat = app::run_trace(s, to_file(scratch.dir / "t.h5", true), again.paths());
  CHECK(again.calls.empty());
  CHECK(repeat.paths[0].steps.size() == expected.steps.size());
  check_same_events(repeat.paths[0].events, expected.events);
}

TEST_CASE("trace: a path that refuses the scene before its first step leaves no file", "[app][trace][errors]") {
  Scratch scratch;
  const scene::Scene s = scene_with_trace("lambda_max = 1\n");
  const app::TracePath refuses = [](const model::MemberModel&, const TraceOptions&,
                                    const continuation::TraceSink&) -> continuation::TraceResult {
    throw InputError("beam.toml: a mechanism");
  };
  CHECK_THROWS_AS(app::run_trace(s, to_file(scratch.dir / "t.h5"), {refuses, refuses}), InputError);
  CHECK_FALSE(fs::exists(scratch.dir / "t.h5"));
  CHECK_FALSE(fs::exists(io::trace_backup_path(scratch.dir / "t.h5")));
}

TEST_CASE("trace: resume refuses another scene, other options, or no file", "[app][trace][errors]") {
  Scratch scratch;
  const scene::Scene s = scene_with_trace("lambda_max = 1\nmax_step = 0.25\nsamples = 5\n");
  SyntheticPath synthetic;
  synthetic.stop_after = 2;
  CHECK_THROWS_AS(app::run_trace(s, to_file(scratch.dir / "t.h5"), synthetic.paths()), Interrupted);
  synthetic.stop_after = -1;
  const scene::Scene other = scene_with_trace("lambda_max = 1.5\nmax_step = 0.25\nsamples = 5\n");
  CHECK_THROWS_AS(app::run_trace(other, to_file(scratch.dir / "t.h5", true), synthetic.paths()), InputError);
  app::TraceRequest finer = to_file(scratch.dir / "t.h5", true);
  finer.elements = 100;
  CHECK_THROWS_AS(app::run_trace(s, finer, synthetic.paths()), InputError);
  CHECK_THROWS_AS(app::run_trace(s, to_file(scratch.dir / "none.h5", true), synthetic.paths()), InputError);
  CHECK_FALSE(fs::exists(scratch.dir / "none.h5"));
  app::TraceRequest no_output;
  no_output.resume = true;
  CHECK_THROWS_AS(app::run_trace(s, no_output, synthetic.paths()), InputError);
  CHECK(synthetic.calls.size() == 1);  // none of the refused runs reached a path
}

TEST_CASE("trace: method all pairs the paths' events; refine runs the FE path with twice the elements",
          "[app][trace]") {
  const scene::Scene s = scene_with_trace(
      "lambda_max = 2\nmax_step = 0.25\nsamples = 5\nmethod = \"all\"\n"
      "refine = true\n");
  SyntheticPath fe, ritz;
  app::TracePaths paths{fe.path(), ritz.path()};
  const app::TraceOutcome outcome = app::run_trace(s, {}, paths);
  REQUIRE(outcome.paths.size() == 3);
  CHECK(outcome.paths[0].path == "fe");
  CHECK(outcome.paths[1].path == "ritz");
  CHECK(outcome.paths[2].path == "fe_refined");
  REQUIRE(fe.calls.size() == 2);
  CHECK(fe.calls[0].elements == 50);
  CHECK(fe.calls[1].elements == 100);
  REQUIRE(outcome.comparison.has_value());
  CHECK(outcome.comparison->pairs.size() == 2);
  CHECK(outcome.comparison->only_a.empty());
  REQUIRE(outcome.discretisation_error.has_value());
  CHECK(outcome.discretisation_error->pairs.size() == 2);
  const nlohmann::json j = app::to_json(outcome);
  CHECK(j["paths"].size() == 3);
  CHECK(j["comparison"]["pairs"][0]["lambda_difference"] == 0.0);
  CHECK(j["discretisation_error"]["pairs"].size() == 2);
}

TEST_CASE("trace: plot_trace.py draws both figures from a trace file", "[app][trace][plot]") {
  Scratch scratch;
  const scene::Scene s = scene_with_trace("lambda_max = 2\nmax_step = 0.1\nsamples = 11\nmethod = \"all\"\n");
  SyntheticPath synthetic;
  app::run_trace(s, to_file(scratch.dir / "t.h5"), synthetic.paths());
  const std::string prefix = (scratch.dir / "t").string();
  const std::string plot = "/usr/bin/python3 " + std::string(LIFTOFF_SOURCE_DIR) +
                           "/verification/plots/plot_trace.py " + prefix + ".h5 --out " + prefix + " > /dev/null";
  REQUIRE(std::system(plot.c_str()) == 0);
  CHECK(fs::file_size(prefix + "_load_displacement.png") > 0);
  CHECK(fs::file_size(prefix + "_lift_off_map.png") > 0);
}

TEST_CASE("trace: events are paired by kind and nearest load factor", "[app][trace]") {
  app::PathTrace a, b;
  a.path = "fe";
  b.path = "ritz";
  a.events = {{1.0, EventKind::lift_off_opens, 5, ""}, {2.0, EventKind::limit_at_end, 0, ""}};
  b.events = {{2.1, EventKind::limit_at_end, 0, ""},
              {1.01, EventKind::lift_off_opens, 5, ""},
              {3.0, EventKind::region_vanishes, 1, ""}};
  const app::EventComparison c = app::compare_events(a, b);
  REQUIRE(c.pairs.size() == 2);
  CHECK(c.pairs[0].load_factor_b == 1.01);
  CHECK(c.pairs[1].load_factor_b == 2.1);
  CHECK(c.only_a.empty());
  REQUIRE(c.only_b.size() == 1);
  CHECK(c.only_b[0].kind == EventKind::region_vanishes);
}

TEST_CASE("trace: a run killed with SIGKILL leaves a readable file of finished steps, and resumes",
          "[app][trace][kill]") {
  Scratch scratch;
  const scene::Scene s = scene_with_trace("lambda_max = 4\nmax_step = 0.02\nsamples = 201\n");
  SyntheticPath whole;
  app::run_trace(s, to_file(scratch.dir / "whole.h5"), whole.paths());
  const io::TracePathRecord expected = io::read_trace_file(scratch.dir / "whole.h5").paths[0].second;
  REQUIRE(expected.steps.size() == 201);

  const fs::path killed = scratch.dir / "killed.h5";
  const bool interrupted = kill_midway(
      [&] {
        SyntheticPath slow;
        slow.delay = std::chrono::milliseconds(5);
        app::TraceRequest request = to_file(killed);
        request.progress = [](const app::TraceProgress& p) { std::cerr << p.steps << "\n" << std::flush; };
        app::run_trace(s, request, slow.paths());
      },
      [](const std::string& line) { return std::stoi(line) >= 20; });
  REQUIRE(interrupted);

  const io::TraceFileRecord partial = io::read_trace_file(killed);
  CHECK_FALSE(partial.complete);
  const std::vector<double> finished = lambdas(partial.paths[0].second);
  REQUIRE(finished.size() >= 20);
  REQUIRE(finished.size() < expected.steps.size());
  CHECK(std::equal(finished.begin(), finished.end(), lambdas(expected).begin()));

  SyntheticPath resumed;
  app::run_trace(s, to_file(killed, true), resumed.paths());
  REQUIRE(resumed.calls[0].resume_from.has_value());
  CHECK(resumed.calls[0].resume_from->load_factor == finished.back());
  const io::TraceFileRecord done = io::read_trace_file(killed);
  CHECK(done.complete);
  CHECK_FALSE(fs::exists(io::trace_backup_path(killed)));  // kept only while the trace runs
  CHECK(lambdas(done.paths[0].second) == lambdas(expected));
  check_same_events(done.paths[0].second.events, expected.events);
}

TEST_CASE("trace: the test scenes read, with a [trace] table", "[app][trace]") {
  for (const char* name : {"free_free_uplift", "simply_supported_end_moments", "region_split"}) {
    CAPTURE(name);
    const scene::Scene s = test::continuation_scene(name);
    const TraceOptions o = app::trace_options(s, {});
    CHECK(o.arc_length.lambda_max > o.arc_length.lambda_min);
    CHECK(app::trace_path_names(s, {}) == std::vector<std::string>{"fe"});
  }
}

TEST_CASE("trace CLI: bad input exits 2 with one line and writes no file", "[app][trace][errors]") {
  Scratch scratch;
  const std::string h5 = (scratch.dir / "t.h5").string();
  const std::string no_table = scratch.write("no_table.toml", beam_with_trace("")).string();
  Run r = run_cli({"trace", no_table, "-o", h5});
  CHECK(r.status == 2);
  CHECK(one_line(r.err));
  CHECK_THAT(r.err, Catch::Matchers::Contains("key 'trace': missing"));
  const std::string no_max = scratch.write("no_max.toml", beam_with_trace("samples = 11\n")).string();
  r = run_cli({"trace", no_max, "--json", "-o", h5});
  CHECK(r.status == 2);
  CHECK(one_line(r.err));
  CHECK_THAT(r.err, Catch::Matchers::Contains("no_max.toml:21: key 'trace.lambda_max': missing"));
  // --json: one failure object on stdout, the message as on stderr.
  const nlohmann::json failure = nlohmann::json::parse(r.out);
  CHECK(failure["termination"] == "bad_input");
  CHECK(failure["exit_code"] == 2);
  CHECK(failure["scene"] == no_max);
  CHECK(failure["method_requested"] == "auto");  // [solve] method of beam_with_trace
  CHECK("liftoff: " + failure["message"].get<std::string>() + "\n" == r.err);
  const std::string bad = scratch.write("bad.toml", beam_with_trace("lambda_max = 1\nsamples = 1\n")).string();
  r = run_cli({"trace", bad, "-o", h5});
  CHECK(r.status == 2);
  CHECK_THAT(r.err, Catch::Matchers::Contains("key 'trace.samples'"));
  const std::string good = scratch.write("good.toml", beam_with_trace("lambda_max = 1\n")).string();
  r = run_cli({"trace", good, "--resume"});
  CHECK(r.status == 2);
  CHECK_THAT(r.err, Catch::Matchers::Contains("--resume: needs --output"));
  r = run_cli({"trace", good, "--resume", "-o", h5});
  CHECK(r.status == 2);
  CHECK(run_cli({"trace", good, "--method", "fastest"}).status == 2);
  CHECK_FALSE(fs::exists(h5));
  // `solve` ignores [trace]: a scene without lambda_max still solves.
  CHECK(run_cli({"solve", no_max}).status == 0);
  CHECK(run_cli({"trace", "--help"}).status == 0);
}

TEST_CASE("trace: the Ritz path refuses interior supports as bad input, before any file", "[app][trace][errors]") {
  // `solve --method ritz` refuses this scene with exit 2; the trace once ended in exit 1.
  std::string text = beam_with_trace("lambda_max = 1\nmethod = \"ritz\"\n");
  text.replace(text.find("right = \"free\""), 14, "right = \"free\"\ninterior = [5.0]");
  const scene::Scene s = scene::parse_scene(text, "beam.toml");
  CHECK_THROWS_WITH(app::trace_path_names(s, {}),
                    "beam.toml: key 'trace.method': the Ritz path cannot take this scene (key 'supports.interior': "
                    "the moving-boundary model takes no interior point supports); expected an FE method (\"dual\", "
                    "\"primal\", \"fast\" or \"auto\")");
  app::TraceRequest all;
  all.method = scene::Method::all;
  CHECK_THROWS_WITH(app::trace_path_names(s, all), Catch::Matchers::StartsWith("beam.toml: option '--method':"));
  app::TraceRequest fe;
  fe.method = scene::Method::fast;
  CHECK(app::trace_path_names(s, fe) == std::vector<std::string>{"fe"});

  Scratch scratch;
  const std::string scene_file = scratch.write("interior.toml", text).string();
  const std::string h5 = (scratch.dir / "t.h5").string();
  const Run r = run_cli({"trace", scene_file, "-o", h5, "--json"});
  CHECK(r.status == 2);
  CHECK(one_line(r.err));
  CHECK(nlohmann::json::parse(r.out)["exit_code"] == 2);
  CHECK_FALSE(fs::exists(h5));
}

TEST_CASE("trace: the sample points lie on the member, both ends exact", "[app][trace]") {
  // (L / 100) * 100 rounds one ulp above L = 0.013; the Ritz path refused its own sample (exit 1).
  for (const double length : {0.013, 1.0, 0.1, 3.3, 7e-5, 123.456}) {
    std::string text = beam_with_trace("lambda_max = 1\nsamples = 101\n");
    text.replace(text.find("length = 10.0"), 13, fmt::format("length = {}", length));
    text.replace(text.find("at = 4.0"), 8, fmt::format("at = {}", length / 2));
    const scene::Scene s = scene::parse_scene(text, "beam.toml");
    const TraceOptions o = app::trace_options(s, {});
    REQUIRE(o.sample_points.size() == 101);
    CHECK(o.sample_points.front() == 0.0);
    CHECK(o.sample_points.back() == length);
    for (std::size_t i = 1; i < o.sample_points.size(); ++i) {
      CHECK(o.sample_points[i] > o.sample_points[i - 1]);
      CHECK(o.sample_points[i] <= length);
    }
  }
  // An arch: theta from -gamma to gamma.
  const scene::Scene arch = scene::parse_scene(
      "[structure]\nkind = \"arch\"\nradius = 3.0\nhalf_angle_deg = 13.7\nEI = 1.0\nEA = 100.0\n[supports]\n"
      "left = \"pinned\"\nright = \"pinned\"\n[foundation]\nk = 10.0\n[trace]\nlambda_max = 1\nsamples = 37\n",
      "arch.toml");
  const TraceOptions a = app::trace_options(arch, {});
  CHECK(a.sample_points.front() == -13.7);
  CHECK(a.sample_points.back() == 13.7);
  for (double x : a.sample_points) CHECK((x >= -13.7 && x <= 13.7));

  // End to end: the Ritz path of a 0.013 m beam traces (exit 0).
  Scratch scratch;
  const std::string text =
      "[structure]\nkind = \"beam\"\nlength = 0.013\nEI = 1.0\n[supports]\nleft = \"pinned\"\nright = \"pinned\"\n"
      "[foundation]\nk = 1.0e4\n[[loads]]\nkind = \"force\"\nat = 0.0065\nvalue = 1.0\n"
      "[trace]\nlambda_max = 2.0\nmethod = \"ritz\"\n";
  const Run r = run_cli({"trace", scratch.write("short.toml", text).string(), "--modes", "8"});
  CHECK(r.status == 0);
  CHECK(r.err.empty());
}

// ---------------------------------------------------------------------------------------------
// End to end with the real paths (continuation/fe_path, ritz_path): these pass once the paths
// are merged.

namespace {
std::string shipped(const std::string& name) {
  return std::string(LIFTOFF_SOURCE_DIR) + "/continuation/scenes/" + name + ".toml";
}
}  // namespace

TEST_CASE("trace CLI: every test scene traces, with --json events and steps, and an HDF5 file that plots",
          "[app][trace][real_paths]") {
  Scratch scratch;
  for (const char* name : {"free_free_uplift", "simply_supported_end_moments", "region_split"}) {
    CAPTURE(name);
    const std::string h5 = (scratch.dir / (std::string(name) + ".h5")).string();
    const Run r = run_cli({"trace", shipped(name), "--json", "-o", h5});
    INFO(r.err);
    REQUIRE(r.status == 0);
    const nlohmann::json j = nlohmann::json::parse(r.out);
    REQUIRE(j["events"].size() >= 1);
    for (const auto& e : j["events"]) {
      CHECK(e["lambda"].is_number());
      CHECK(e["kind"].is_string());
      CHECK(e["at"].is_number());
    }
    CHECK(j["steps"].size() >= 2);
    const io::TraceFileRecord file = io::read_trace_file(h5);
    CHECK(file.complete);
    const std::string prefix = (scratch.dir / name).string();
    const std::string plot = "/usr/bin/python3 " + std::string(LIFTOFF_SOURCE_DIR) +
                             "/verification/plots/plot_trace.py " + h5 + " --out " + prefix + " > /dev/null";
    REQUIRE(std::system(plot.c_str()) == 0);
    CHECK(fs::file_size(prefix + "_load_displacement.png") > 0);
    CHECK(fs::file_size(prefix + "_lift_off_map.png") > 0);
  }
}

namespace {
// The first event of `path` (fe or ritz) within [lambda_lo, lambda_hi] near `at`, if any.
std::optional<nlohmann::json> event_between(const nlohmann::json& path, double lambda_lo, double lambda_hi, double at,
                                            double margin) {
  for (const auto& e : path["events"])
    if (e["lambda"] >= lambda_lo && e["lambda"] <= lambda_hi && std::abs(e["at"].get<double>() - at) <= margin)
      return e;
  return std::nullopt;
}
}  // namespace

// The brackets are `liftoff solve` at fixed load factors with the scene's own elements (see the
// scenes' comments): the FE path on the same mesh must put each event inside them.
TEST_CASE("trace CLI: the FE path puts the test scenes' events between the fixed-load solutions",
          "[app][trace][real_paths]") {
  {
    const Run r = run_cli({"trace", shipped("free_free_uplift"), "--json"});
    REQUIRE(r.status == 0);
    const nlohmann::json j = nlohmann::json::parse(r.out);
    CHECK(j["events"][0]["kind"] == "lift_off_opens");
    CHECK(j["events"][0]["at"].get<double>() == Approx(5.0).margin(10.0 / 200));
    CHECK(j["events"][0]["lambda"].get<double>() > 5.0);
    CHECK(j["events"][0]["lambda"].get<double>() < 6.0);
  }
  {
    const Run r = run_cli({"trace", shipped("region_split"), "--json"});
    REQUIRE(r.status == 0);
    const nlohmann::json j = nlohmann::json::parse(r.out);
    const auto split = event_between(j, 6.7, 7.0, 5.0, 10.0 / 200);
    REQUIRE(split.has_value());
    CHECK((*split)["kind"] == "lift_off_opens");
    CHECK(event_between(j, 8.6, 8.8, 0.0, 1e-9).has_value());
    CHECK(event_between(j, 8.6, 8.8, 10.0, 1e-9).has_value());
  }
  {
    const Run r = run_cli({"trace", shipped("simply_supported_end_moments"), "--json"});
    REQUIRE(r.status == 0);
    const nlohmann::json j = nlohmann::json::parse(r.out);
    CHECK(event_between(j, 0.20, 0.21, 0.0, 6.0 / 400).has_value());
    CHECK(event_between(j, 0.40, 0.44, 6.0, 6.0 / 400).has_value());
    const auto vanishes = event_between(j, 0.846, 0.848, 3.85, 0.15);
    REQUIRE(vanishes.has_value());
    CHECK((*vanishes)["kind"] == "region_vanishes");
  }
}

TEST_CASE("trace CLI: the Ritz path killed with SIGKILL keeps its steps and resumes to the uninterrupted run",
          "[app][trace][kill][real_paths]") {
  Scratch scratch;
  // Load control with a fixed step, so the uninterrupted and the resumed runs take the same
  // steps; many small steps so that the run is still going when it is killed.
  std::string text;
  {
    std::ifstream in(shipped("free_free_uplift"));
    text.assign(std::istreambuf_iterator<char>(in), {});
  }
  text = text.substr(0, text.find("[trace]")) +
         "[trace]\nlambda_max = 8.0\nmethod = \"ritz\"\ncontrol = \"load\"\ninitial_step = 0.01\nmax_step = 0.01\n"
         "samples = 1001\n";
  const std::string scene = scratch.write("uplift.toml", text).string();
  const std::string whole = (scratch.dir / "whole.h5").string(), killed = (scratch.dir / "killed.h5").string();
  REQUIRE(run_cli({"trace", scene, "-o", whole}).status == 0);
  const io::TracePathRecord expected = io::read_trace_file(whole).paths[0].second;

  const bool interrupted = kill_midway(
      [&] {  // the real stderr (a pipe here): --progress writes a line per finished step
        const char* argv[] = {"liftoff", "trace", scene.c_str(), "-o", killed.c_str(), "--progress"};
        ::_exit(app::run_cli(6, argv, std::cout, std::cerr));
      },
      [](const std::string& line) { return steps_in(line) >= 20; });
  REQUIRE(interrupted);
  const io::TraceFileRecord partial = io::read_trace_file(killed);
  CHECK_FALSE(partial.complete);
  const std::vector<double> finished = lambdas(partial.paths[0].second);
  REQUIRE(finished.size() >= 20);
  REQUIRE(run_cli({"trace", scene, "-o", killed, "--resume"}).status == 0);
  const io::TracePathRecord done = io::read_trace_file(killed).paths[0].second;
  const std::vector<double> all = lambdas(done), reference = lambdas(expected);
  REQUIRE(all.size() == reference.size());
  for (std::size_t i = 0; i < all.size(); ++i) CHECK(all[i] == Approx(reference[i]).margin(1e-9));
  REQUIRE(done.events.size() == expected.events.size());
  for (std::size_t i = 0; i < done.events.size(); ++i) {
    CHECK(done.events[i].kind == expected.events[i].kind);
    CHECK(done.events[i].load_factor == Approx(expected.events[i].load_factor).margin(1e-8));
  }
}

TEST_CASE("trace CLI: a von Karman beam is traced by the FE path through its snap-through",
          "[app][trace][von_karman]") {
  // Issue 16's shallow arch (verification/dolfinx/scenes/issue16/), the theory gate open for trace:
  // the FE path from the unloaded state through the limit point (models/fe_member_von_karman_test.cpp has
  // the figures: 21.13167 on 64 elements) and back up, thrust and stability per step.
  std::ifstream in(std::string(LIFTOFF_SOURCE_DIR) +
                   "/verification/dolfinx/scenes/issue16/shallow_arch_tensionless.toml");
  REQUIRE(in);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Scratch scratch;
  const fs::path scene = scratch.dir / "arch.toml";
  {
    std::ofstream out(scene);
    out << text << "\n[trace]\nlambda_max = 25.0\n";
  }
  const std::string h5 = (scratch.dir / "arch.h5").string();
  const Run r = run_cli({"trace", scene.string(), "--json", "-o", h5});
  INFO(r.err);
  REQUIRE(r.status == 0);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  const nlohmann::json& fe = j.contains("paths") ? j["paths"][0] : j;
  INFO(fe.dump().substr(0, 2000));
  bool maximum = false;
  for (const auto& e : fe["events"])
    if (e["kind"] == "limit_point" && std::abs(e["lambda"].get<double>() - 21.13167) < 1e-4) maximum = true;
  CHECK(maximum);
  const io::TraceFileRecord file = io::read_trace_file(h5);
  CHECK(file.complete);
}

// ---------------------------------------------------------------------------------------------
// Issue 37: the live load as a physical quantity, the loads asked for, the whole state per step
// in the JSON, CSV and summary.

namespace {
scene::Scene scene_file(const std::string& relative) {
  return scene::read_scene_file(std::string(LIFTOFF_SOURCE_DIR) + "/" + relative);
}

// A beam heated by two temperature rises (`alpha` of the second), nothing else live.
scene::Scene heated(double alpha) {
  return scene::parse_scene(
      "[structure]\nkind = \"beam\"\nlength = 10.0\nEI = 1.0e4\nEA = 1.0e8\n[supports]\nleft = \"clamped\"\n"
      "right = \"clamped\"\n[foundation]\nmodulus = 1.0e5\n[[loads]]\nkind = \"uniform\"\nvalue = 10.0\n"
      "case = \"dead\"\n[[loads]]\nkind = \"temperature\"\nvalue = 30.0\nalpha = 1.2e-5\n[[loads]]\n"
      "kind = \"temperature\"\nvalue = 10.0\nalpha = " +
          fmt::format("{}", alpha) + "\n[units]\nsystem = \"N-m\"\n[trace]\nlambda_max = 2.0\n",
      "heated.toml");
}
}  // namespace

TEST_CASE("trace: the live load of the shipped scenes as a physical quantity", "[app][trace][load]") {
  struct Expected {
    const char* scene;
    const char* quantity;
    const char* symbol;
    double reference;
    const char* unit;
  };
  for (const Expected& e : {
           Expected{"continuation/scenes/pipeline_upheaval.toml", "axial force", "N", 1e6, "N"},
           Expected{"continuation/scenes/footing_trace.toml", "moment", "M", -100e3, ""},  // no [units]
           Expected{"continuation/scenes/arch_culvert.toml", "point force", "P", 100e3, ""},
           Expected{"continuation/scenes/simply_supported_end_moments.toml", "moment", "M", 60.0, ""},  // the largest
           Expected{"verification/scenes/engineering/pipeline_500m_uplift.toml", "point force", "P", -50e3, "N"},
           Expected{"verification/scenes/von_karman/shallow_arch_bifurcation.toml", "distributed force", "q", 1000.0,
                    "N/m"},
       }) {
    CAPTURE(e.scene);
    const app::LiveLoad live = app::live_load(scene_file(e.scene));
    REQUIRE(live.load.has_value());
    CHECK(live.load->quantity == e.quantity);
    CHECK(live.load->symbol == e.symbol);
    CHECK(live.load->reference == e.reference);
    CHECK(live.load->unit == e.unit);
    CHECK(live.why_none.empty());
  }
  // Temperature rises of one alpha add up (their forces EA alpha dT do); with two alphas, none.
  const app::LiveLoad heat = app::live_load(heated(1.2e-5));
  REQUIRE(heat.load.has_value());
  CHECK(heat.load->quantity == "temperature rise");
  CHECK(heat.load->reference == 40.0);
  CHECK(heat.load->unit == "deg");
  CHECK(heat.load->definition == "the sum of the 2 live temperature rises (loads[1], loads[2])");
  CHECK_FALSE(app::live_load(heated(2.4e-5)).load.has_value());
  // Mixed kinds: lambda only, and why.
  const app::LiveLoad mixed = app::live_load(scene::parse_scene(
      beam_with_trace("lambda_max = 1\n") + "[[loads]]\nkind = \"moment\"\nat = 2.0\nvalue = 1.0\n", "mixed.toml"));
  CHECK_FALSE(mixed.load.has_value());
  CHECK(mixed.why_none == "the live case mixes point forces and moments");
}

TEST_CASE("trace: report_at and --at are loads in the live load's unit, refused outside the range",
          "[app][trace][load][errors]") {
  std::ifstream in(std::string(LIFTOFF_SOURCE_DIR) + "/continuation/scenes/pipeline_upheaval.toml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string anchor = "max_amplitude = 1.0\n";
  REQUIRE(text.find(anchor) != std::string::npos);
  const auto with = [&](const std::string& line) {
    std::string t = text;
    t.insert(t.find(anchor) + anchor.size(), line);
    return scene::parse_scene(t, "upheaval.toml");
  };
  const int line = static_cast<int>(std::count(text.begin(), text.begin() + text.find(anchor), '\n')) + 2;
  // 5 MN and 3.2 MN: lambda 5 and 3.2 (the live axial force is 1 MN).
  CHECK(app::trace_options(with("report_at = [5.0e6, 3.2e6]\n"), {}).report_at == std::vector<double>{5.0, 3.2});
  CHECK(app::trace_options(with("report_at = [1.2e7]\n"), {}).report_at == std::vector<double>{12.0});  // the end
  CHECK_THROWS_WITH(app::trace_options(with("report_at = [5.0e6, 2.0e7]\n"), {}),
                    fmt::format("upheaval.toml:{}: key 'trace.report_at[1]': expected an axial force N in [0, "
                                "1.2e+07] N (lambda in [0, 12] x the live axial force (loads[1]), 1e+06 N), got 2e+07",
                                line));
  // --at overrides the key, in the same unit.
  app::TraceRequest request;
  request.report_at = std::vector<double>{4.0e6};
  CHECK(app::trace_options(with("report_at = [5.0e6]\n"), request).report_at == std::vector<double>{4.0});
  request.report_at = std::vector<double>{-1.0e6};
  CHECK_THROWS_WITH(app::trace_options(with(""), request),
                    Catch::Matchers::StartsWith("option '--at': expected an axial force N in [0, 1.2e+07] N"));
  // No physical load (the live case mixes a force and a moment): load factors.
  const std::string mixed = beam_with_trace("lambda_max = 1\nreport_at = [0.25, 1]\n") +
                            "[[loads]]\nkind = \"moment\"\nat = 2.0\nvalue = 1.0\n";
  CHECK(app::trace_options(scene::parse_scene(mixed, "mixed.toml"), {}).report_at == std::vector<double>{0.25, 1.0});
  request.report_at = std::vector<double>{2.0};
  CHECK_THROWS_WITH(app::trace_options(scene::parse_scene(mixed, "mixed.toml"), request),
                    "option '--at': expected a load factor in [0, 1] ([trace] lambda_min, lambda_max), got 2");
  // The command line: --at splits at commas; a word that is no number is refused naming the option.
  Scratch scratch;
  const std::string scene = scratch.write("upheaval.toml", text).string();
  const Run bad = run_cli({"trace", scene, "--at", "5e6,big"});
  CHECK(bad.status == 2);
  CHECK_THAT(bad.err, Catch::Matchers::Contains("option '--at': expected finite numbers separated by commas"));
  const Run outside = run_cli({"trace", scene, "--at", "5e6,2e7"});
  CHECK(outside.status == 2);
  CHECK_THAT(outside.err, Catch::Matchers::Contains("option '--at': expected an axial force N in [0, 1.2e+07] N"));
}

namespace {
// The synthetic path's steps with a record (design values, supports) and one requested step (at
// lambda 1, as the engine records a load asked for): what the outputs of a requested step look like.
app::TracePath recording(SyntheticPath& synthetic) {
  return [&synthetic](const model::MemberModel& member, const TraceOptions& o, const continuation::TraceSink& sink) {
    continuation::TraceSink decorated;
    decorated.on_event = sink.on_event;
    decorated.on_step = [&](const TraceStep& step) {
      TraceStep s = step;
      s.requested = s.load_factor == 1.0;
      post::DesignTable d;
      d.moment_max = {2.0 * s.load_factor, 4.0};
      d.moment_min = {-s.load_factor, 1.0};
      d.uplift_max = {0.0, std::nullopt};
      d.from_statics = true;
      s.design = d;
      s.supports = {{10.0, 0.5 * s.load_factor, 0.0, 0.0, false, 0.0}};
      // Nodal moments 3 lambda all along, so that M at the monitor is 3 lambda wherever it is.
      const double begin = member.user_from_s(member.s_begin), end = member.user_from_s(member.s_end);
      s.fields.coordinate = {begin, 0.5 * (begin + end), end};
      s.fields.bending_moment.assign(3, 3.0 * s.load_factor);
      sink.on_step(s);
    };
    return synthetic.path()(member, o, decorated);
  };
}
}  // namespace

TEST_CASE("trace: JSON, CSV and summary carry each step's load, design values, supports and requested",
          "[app][trace][load]") {
  Scratch scratch;
  const scene::Scene s = scene_with_trace("lambda_max = 2\nmax_step = 0.25\nsamples = 5\n");  // P = lambda x -1
  SyntheticPath synthetic;
  const app::TracePath path = recording(synthetic);
  const app::TraceOutcome outcome = app::run_trace(s, to_file(scratch.dir / "t.h5"), {path, path});
  REQUIRE(outcome.usable());
  REQUIRE(outcome.physical_load.has_value());

  const nlohmann::json j = app::to_json(outcome);
  CHECK(j["physical_load"]["quantity"] == "point force");
  CHECK(j["physical_load"]["reference"] == -1.0);
  REQUIRE(j["steps"].size() == 9);
  const nlohmann::json& fifth = j["steps"][4];  // lambda 1: the requested one
  CHECK(fifth["lambda"] == 1.0);
  CHECK(fifth["load"] == -1.0);
  CHECK(fifth["requested"] == true);
  CHECK(j["steps"][3]["requested"] == false);
  CHECK(fifth["design"]["moment_max"]["value"] == 2.0);  // solve's object, key for key
  CHECK(fifth["design"]["moment_max"]["at"] == 4.0);
  CHECK(fifth["design"]["uplift_max"]["at"].is_null());
  CHECK(fifth["design"]["from_statics"] == true);
  REQUIRE(fifth["supports"].size() == 1);
  CHECK(fifth["supports"][0]["force"] == 0.5);
  for (const char* key : {"axial_force", "lifted_length", "amplitude", "stability"}) CHECK(fifth.contains(key));
  CHECK(fifth["monitor_moment"] == 3.0);  // read off the fields before they are let go
  REQUIRE(j["events"].size() == 2);
  CHECK(j["events"][0]["load"] == Approx(-0.6).epsilon(1e-14));  // lambda 0.6

  const std::string csv = app::trace_csv(outcome);
  std::istringstream lines(csv);
  std::string header, row;
  std::getline(lines, header);
  CHECK(header ==
        "path,step,lambda,load,monitor_deflection,axial_force,amplitude,lifted_length,moment_max,at_moment_max,"
        "moment_min,at_moment_min,shear_max_abs,at_shear_max_abs,pressure_max,at_pressure_max,uplift_max,"
        "at_uplift_max,support_reactions,stability,requested,monitor_moment");
  std::vector<std::string> rows;
  while (std::getline(lines, row)) rows.push_back(row);
  REQUIRE(rows.size() == 9);
  CHECK(rows[4] == "fe,4,1,-1,0.001,0,0,0,2,4,-1,1,0,,0,,0,,10:0.5:0,unknown,true,3");
  CHECK(rows[3].substr(rows[3].size() - 11) == ",false,2.25");

  const std::string summary = app::text_summary(outcome);
  CHECK_THAT(summary, Catch::Matchers::Contains("load          P = lambda x -1: the live point force (loads[1])"));
  CHECK_THAT(summary, Catch::Matchers::Contains("lambda 0.6 (P = -0.6)"));
  CHECK_THAT(summary, Catch::Matchers::Contains("9 steps, lambda 2 (P = -2)"));  // where the path ended
  CHECK_THAT(summary, Catch::Matchers::Contains("requested     P = -1 (lambda 1)"));
  CHECK_THAT(summary, Catch::Matchers::Contains("moment max 2 at x = 4, min -1 at x = 1"));
  CHECK_THAT(summary, Catch::Matchers::Contains("M there 3;"));

  // The file: the load and the requested flag per step.
  const io::TracePathRecord written = io::read_trace_file(scratch.dir / "t.h5").paths.at(0).second;
  REQUIRE(written.steps.size() == 9);
  CHECK(written.steps[4].requested);
  CHECK(written.steps[4].load == -1.0);
  CHECK(written.steps[4].design->moment_max.value == 2.0);
}

TEST_CASE("trace CLI: --csv writes one row per step; --json has each step's design values and supports",
          "[app][trace][load][real_paths]") {
  Scratch scratch;
  const std::string csv = (scratch.dir / "steps.csv").string();
  const Run r =
      run_cli({"trace", shipped("simply_supported_end_moments"), "--elements", "100", "--json", "--csv", csv});
  INFO(r.err);
  REQUIRE(r.status == 0);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  CHECK(j["physical_load"]["symbol"] == "M");
  std::ifstream in(csv);
  std::string line;
  std::size_t rows = 0;
  while (std::getline(in, line)) ++rows;
  CHECK(rows == j["steps"].size() + 1);
  for (const auto& step : j["steps"]) {
    CHECK(step["load"] == Approx(60.0 * step["lambda"].get<double>()).epsilon(1e-15));
    CHECK(step["design"]["from_statics"] == true);  // a beam: solve's statics
    CHECK(step["supports"].size() == 2);            // the two pins
  }
  // The summary: each event with its load and the moment's extremes at it.
  const Run text = run_cli({"trace", shipped("simply_supported_end_moments"), "--elements", "100"});
  REQUIRE(text.status == 0);
  CHECK_THAT(text.out, Catch::Matchers::Contains("(M = "));
  CHECK_THAT(text.out, Catch::Matchers::Contains("; moment max "));
}
