// The command line as a user meets it: exit codes, one-line errors naming file and key, no
// output file after a failure, JSON on stdout, and an HDF5 file that describes itself.
#include "app/cli.hpp"

#include <fmt/format.h>
#include <sys/stat.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "io/report.hpp"
#include "support/cli.hpp"
#include "support/scene_text.hpp"
#include "support/scenes.hpp"
#include "support/scratch.hpp"

namespace fs = std::filesystem;

using namespace liftoff::test;  // support/: the CLI runner, the scratch directory

namespace {

std::string scene_path(const std::string& name) {
  return std::string(LIFTOFF_SOURCE_DIR) + "/verification/scenes/" + name + ".toml";
}

const std::string valid_beam = std::string("\n") + beam_text("2.0", "3.0") + R"(nondimensional_k = 1.0e4
[[loads]]
kind = "force"
at = 1.0
value = 1.0
[solve]
elements = 40
)";

// A free-free unit beam on a foundation k with a central force.
std::string free_beam(double k, double force) {
  return "[structure]\nkind = \"beam\"\nlength = 1.0\nEI = 1.0\n[supports]\nleft = \"free\"\nright = \"free\"\n"
         "[foundation]\nnondimensional_k = " +
         std::to_string(k) + "\n[[loads]]\nkind = \"force\"\nat = 0.5\nvalue = " + std::to_string(force) + "\n";
}

}  // namespace

TEST_CASE("cli: help and version exit 0", "[app]") {
  CHECK(run_cli({"--help"}).status == 0);
  CHECK(run_cli({"solve", "--help"}).status == 0);
  CHECK_THAT(run_cli({"solve", "--help"}).out, Catch::Matchers::Contains("--method"));
}

TEST_CASE("cli: solve with no scene runs the seed arch", "[app]") {
  const Run r = run_cli({"solve", "--json"});
  REQUIRE(r.status == 0);
  const auto j = nlohmann::json::parse(r.out);  // stdout is exactly one JSON object
  CHECK(j["structure"] == "arch");
  CHECK(j["contact_regions"].size() == 1);
  for (const char* key : {"method", "contact_regions", "w_max", "at_w_max", "w_min", "at_w_min", "max_reaction",
                          "pivots", "residual", "elements", "time_s"})
    CHECK(j.contains(key));
  // The summary sets the seed paper's contact half-angle (the scene's [compare]) beside ours.
  const double half_angle = (j["contact_regions"][0][1].get<double>() - j["contact_regions"][0][0].get<double>()) / 2;
  CHECK_THAT(run_cli({"solve"}).out,
             Catch::Matchers::Contains(fmt::format("compare       contact half-angle {:.4g} deg; "
                                                   "Silveira, Pereira & Goncalves (2008), sec. 5 "
                                                   "gives 3.73 deg",
                                                   half_angle)));
}

TEST_CASE("cli: a malformed scene is one line naming file and key, exit 2, no output", "[app]") {
  Scratch scratch;
  std::string bad = valid_beam;
  bad.replace(bad.find("EI = 3.0"), 8, "EI = -3.0");
  const fs::path scene = scratch.write("bad.toml", bad);
  const fs::path output = scratch.dir / "out.h5";
  const Run r = run_cli({"solve", scene.string(), "--output", output.string()});
  CHECK(r.status == 2);
  CHECK(one_line(r.err));
  CHECK_THAT(r.err, Catch::Matchers::Contains(scene.string()) && Catch::Matchers::Contains("structure.EI"));
  CHECK_FALSE(fs::exists(output));
  CHECK_FALSE(fs::exists(output.string() + ".tmp"));
}

TEST_CASE("cli: bad command-line values exit 2", "[app]") {
  CHECK(run_cli({"solve", scene_path("seed_arch_pinned"), "--method", "fastest"}).status == 2);
  CHECK(run_cli({"solve", scene_path("seed_arch_pinned"), "--elements", "0"}).status == 2);
  CHECK(run_cli({"solve", "/no/such/scene.toml"}).status == 2);
  CHECK(run_cli({"frobnicate"}).status == 2);
}

TEST_CASE("cli: a solver failure has its own exit code and a reason, no output", "[app]") {
  Scratch scratch;
  // A free beam pulled away from the foundation: no equilibrium.
  const fs::path scene =
      scratch.write("lift.toml", free_beam(100.0, -1.0) + "[solve]\nmethod = \"primal\"\nelements = 10\n");
  const fs::path output = scratch.dir / "out.h5";
  const Run r = run_cli({"solve", scene.string(), "--output", output.string()});
  CHECK(r.status == 3);
  CHECK(one_line(r.err));
  CHECK_THAT(r.err, Catch::Matchers::Contains("no equilibrium"));
  CHECK_FALSE(fs::exists(output));
  // The dual form is refused for a free beam with a pointer to auto and fast.
  const fs::path pressed = scratch.write("press.toml", free_beam(100.0, 1.0));
  const Run dual = run_cli({"solve", pressed.string(), "--method", "dual"});
  CHECK(dual.status == 3);
  CHECK_THAT(dual.err, Catch::Matchers::Contains("\"auto\"") && Catch::Matchers::Contains("\"fast\""));
}

TEST_CASE("cli: an unwritable output is exit 4 and leaves nothing", "[app]") {
  Scratch scratch;
  const fs::path scene = scratch.write("ok.toml", valid_beam);
  const Run r = run_cli({"solve", scene.string(), "--output", "/no/such/dir/out.h5"});
  CHECK(r.status == 4);
  CHECK(one_line(r.err));
}

TEST_CASE("cli: the HDF5 file is complete and readable by h5py and h5dump", "[app][hdf5]") {
  Scratch scratch;
  const fs::path scene = scratch.write("ok.toml", valid_beam);
  const fs::path output = scratch.dir / "out.h5";
  const Run r = run_cli({"solve", scene.string(), "--json", "--output", output.string()});
  REQUIRE(r.status == 0);
  REQUIRE(fs::exists(output));
  CHECK_FALSE(fs::exists(output.string() + ".tmp"));
  const auto j = nlohmann::json::parse(r.out);

  // h5py (as a user reads it): the scene text, the contact regions, and the fields agree with
  // the JSON summary.
  const fs::path script = scratch.write("read.py", R"(
import sys, h5py, numpy as np
f = h5py.File(sys.argv[1], "r")
scene = f["scene"][()].decode()
assert "kind = \"beam\"" in scene, scene
regions = f["contact_regions"][()]
w = f["fields/w"][()]
x = f["fields/coordinate"][()]
assert len(x) == len(w) and len(f["nodes/w"][()]) == 41
for name in ["rotation", "bending_moment", "shear_force", "reaction"]:
    assert len(f["fields/" + name][()]) == len(x)
print(regions.shape[0], repr(float(regions[0][0])), repr(float(w.max())), f.attrs["method"], f.attrs["sign_convention"].startswith("w > 0 into the foundation"))
)");
  const fs::path printed = scratch.dir / "h5py.txt";
  REQUIRE(std::system(
              ("/usr/bin/python3 " + script.string() + " " + output.string() + " > " + printed.string()).c_str()) == 0);
  std::ifstream in(printed);
  int regions = 0;
  std::string first_limit, w_max, method, sign;
  in >> regions >> first_limit >> w_max >> method >> sign;
  CHECK(regions == static_cast<int>(j["contact_regions"].size()));
  CHECK(std::stod(first_limit) == j["contact_regions"][0][0].get<double>());
  CHECK(std::stod(w_max) == j["w_max"].get<double>());
  CHECK(method == "fast");  // auto's choice
  CHECK(sign == "True");

  CHECK(std::system(("h5dump -H " + output.string() + " > /dev/null").c_str()) == 0);
}

TEST_CASE("cli: the Ritz method reports modes, iterations and amplitudes", "[app][ritz]") {
  const Run r = run_cli({"solve", scene_path("seed_beam_end_moments"), "--method", "ritz", "--modes", "24", "--json"});
  REQUIRE(r.status == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["method"] == "ritz");
  CHECK(j["modes"] == 24);
  CHECK(j["amplitudes"].size() == 24);
  CHECK(j["newton_iterations"].get<int>() >= 1);
  CHECK(j["residual_history"].back().get<double>() <= 1e-12);
  CHECK(j["contact_regions"].size() == 1);
}

TEST_CASE("cli: --method all runs primal, dual, fast and Ritz side by side", "[app][ritz]") {
  const Run r = run_cli({"solve", scene_path("seed_beam_end_moments_central_load"), "--method", "all", "--elements",
                         "60", "--modes", "16", "--json"});
  REQUIRE(r.status == 0);
  const auto j = nlohmann::json::parse(r.out);
  REQUIRE(j["methods"].size() == 4);
  CHECK(j["methods"][0]["method"] == "primal");
  CHECK(j["methods"][1]["method"] == "dual");
  CHECK(j["methods"][2]["method"] == "fast");
  CHECK(j["methods"][3]["method"] == "ritz");
  const Run text = run_cli({"solve", scene_path("seed_beam_end_moments_central_load"), "--method", "all", "--elements",
                            "60", "--modes", "16"});
  CHECK_THAT(text.out, Catch::Matchers::Contains("contact 2 begin"));

  // A free-free beam: the dual is refused, the others run, and that is not a failure.
  Scratch scratch;
  const fs::path scene = scratch.write("free.toml", free_beam(5184.0, 1.0));
  const Run free = run_cli({"solve", scene.string(), "--method", "all", "--elements", "40", "--modes", "24", "--json"});
  CHECK(free.status == 0);
  const auto f = nlohmann::json::parse(free.out);
  CHECK(f["methods"][1]["termination"] == "refused");
  CHECK(f["methods"][2]["termination"] == "solved");
  CHECK(f["methods"][3]["termination"] == "converged");
}

TEST_CASE("cli: the Ritz method refuses interior point supports, exit 2", "[app][ritz]") {
  Scratch scratch;
  std::string text = valid_beam;
  text.replace(text.find("right = \"pinned\""), 16, "right = \"pinned\"\ninterior = [0.5]");
  const fs::path scene = scratch.write("interior.toml", text);
  const Run r = run_cli({"solve", scene.string(), "--method", "ritz"});
  CHECK(r.status == 2);
  CHECK(one_line(r.err));
  CHECK_THAT(r.err, Catch::Matchers::Contains("interior point supports"));
}

// ---------------------------------------------------------------------------------------------
// Issue 10: failure output and the safety of the user's files.

namespace {

std::string file_text(const fs::path& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), {}};
}

// stdout of a --json run: exactly one JSON object (parse throws on a second one or on none)
// with the keys every object carries.
nlohmann::json one_object(const Run& r) {
  nlohmann::json j;
  REQUIRE_NOTHROW(j = nlohmann::json::parse(r.out));
  REQUIRE(j.is_object());
  for (const char* key : {"scene", "method_requested", "termination", "message", "exit_code"}) CHECK(j.contains(key));
  CHECK(j["exit_code"] == r.status);
  return j;
}

}  // namespace

TEST_CASE("cli: an integer a double cannot hold is refused by key, not read as 1e-323", "[app][errors]") {
  Scratch scratch;
  std::string text = valid_beam;
  text.replace(text.find("value = 1.0"), 11, "value = -9007199254740993");
  const Run r = run_cli({"solve", scratch.write("big.toml", text).string(), "--method", "fast"});
  CHECK(r.status == 2);  // was exit 0 with w = 0
  CHECK(one_line(r.err));
  CHECK_THAT(r.err, Catch::Matchers::Contains("key 'loads[0].value'") &&
                        Catch::Matchers::Contains("an integer that a double cannot hold exactly"));
  std::string k = valid_beam;
  k.replace(k.find("k = 1.0e4"), 9, "k = 9007199254740993");
  const Run rk = run_cli({"solve", scratch.write("bigk.toml", k).string()});
  CHECK(rk.status == 2);  // was exit 1, "solve_lemke: M contains NaN or Inf"
  CHECK_THAT(rk.err, Catch::Matchers::Contains("key 'foundation.nondimensional_k'"));
}

TEST_CASE("cli: an output never replaces the scene or another output; exit 2, nothing written", "[app][errors]") {
  Scratch scratch;
  const fs::path scene = scratch.write("s.toml", valid_beam);
  // --output on the scene itself, under another spelling, through a symbolic link and a hard link.
  const fs::path link = scratch.dir / "link.h5", hard = scratch.dir / "hard.h5";
  fs::create_symlink(scene, link);
  fs::create_hard_link(scene, hard);
  for (const std::string& output : {scene.string(), (scratch.dir / ".." / scratch.dir.filename() / "s.toml").string(),
                                    link.string(), hard.string()}) {
    const Run r = run_cli({"solve", scene.string(), "--method", "fast", "--output", output});
    CHECK(r.status == 2);  // was exit 0 with the scene replaced by the HDF5 file
    CHECK(r.err == "liftoff: --output '" + output + "': the same file as the scene '" + scene.string() +
                       "'; expected an output that is neither an input nor another output of this run (nothing was "
                       "written)\n");
    CHECK(file_text(scene) == valid_beam);
    const Run j = run_cli({"solve", scene.string(), "--output", output, "--json"});
    CHECK(one_object(j)["termination"] == "bad_input");
  }
  // The temporary name the HDF5 file is written under is an output too.
  const fs::path tmp_scene = scratch.write("t.h5.tmp", valid_beam);
  const Run t = run_cli({"solve", tmp_scene.string(), "--output", (scratch.dir / "t.h5").string()});
  CHECK(t.status == 2);
  CHECK_THAT(t.err, Catch::Matchers::Contains("its temporary file '" + tmp_scene.string() +
                                              "' is the same file as the scene"));
  CHECK(file_text(tmp_scene) == valid_beam);
  CHECK_FALSE(fs::exists(scratch.dir / "t.h5"));
  // `--method all` writes through the same check.
  CHECK(run_cli({"solve", scene.string(), "--method", "all", "--output", scene.string()}).status == 2);
  CHECK(file_text(scene) == valid_beam);

  // Nor does an output replace what is not a regular file (the rename would put the HDF5 file in
  // its place: run as root, --output /dev/null once replaced /dev/null). A named pipe and a
  // directory stand for the devices here.
  const fs::path pipe = scratch.dir / "pipe", dir = scratch.dir / "dir";
  REQUIRE(::mkfifo(pipe.c_str(), 0600) == 0);
  fs::create_directory(dir);
  Run p = run_cli({"solve", scene.string(), "--output", pipe.string()});
  CHECK(p.status == 2);
  CHECK(p.err == "liftoff: --output '" + pipe.string() +
                     "': is a named pipe; expected the name of a regular file, new or to be replaced (nothing was "
                     "written)\n");
  CHECK(fs::is_fifo(pipe));
  p = run_cli({"solve", scene.string(), "--output", dir.string()});
  CHECK(p.status == 2);
  CHECK_THAT(p.err, Catch::Matchers::Contains("is a directory"));
  CHECK(fs::is_empty(dir));
  CHECK_FALSE(fs::exists(dir.string() + ".tmp"));
}

TEST_CASE("cli: --json prints exactly one object for every outcome", "[app][errors]") {
  Scratch scratch;
  const fs::path good = scratch.write("good.toml", valid_beam);
  // Solved: the report, with the keys of a failure object too.
  Run r = run_cli({"solve", good.string(), "--method", "fast", "--json"});
  REQUIRE(r.status == 0);
  nlohmann::json j = one_object(r);
  CHECK(j["method_requested"] == "fast");
  CHECK(j["scene"] == good.string());
  CHECK(j["termination"] == "solved");

  // Bad scene (exit 2): what is known of the run; the scene's [solve] method is unknown.
  std::string bad = valid_beam;
  bad.replace(bad.find("EI = 3.0"), 8, "EI = -3.0");
  const fs::path bad_scene = scratch.write("bad.toml", bad);
  r = run_cli({"solve", bad_scene.string(), "--json"});
  CHECK(r.status == 2);
  j = one_object(r);
  CHECK(j["termination"] == "bad_input");
  CHECK(j["method_requested"].is_null());
  CHECK(j["scene"] == bad_scene.string());
  CHECK(j["message"] == r.err.substr(9, r.err.size() - 10));  // stderr: "liftoff: MESSAGE\n"
  CHECK(one_object(run_cli({"solve", bad_scene.string(), "--json", "--method", "primal"}))["method_requested"] ==
        "primal");

  // Bad command line (exit 2, refused by the parser), a scene that does not exist.
  r = run_cli({"solve", good.string(), "--json", "--elements", "0"});
  CHECK(r.status == 2);
  CHECK(one_object(r)["termination"] == "bad_input");
  r = run_cli({"solve", "/no/such/scene.toml", "--json"});
  CHECK(r.status == 2);
  CHECK(one_object(r)["scene"].is_null());

  // A refused formulation (exit 3): the dual form on a member only the foundation holds.
  const fs::path free = scratch.write("free.toml", free_beam(100.0, 1.0) + "[solve]\nelements = 10\n");
  r = run_cli({"solve", free.string(), "--method", "dual", "--json"});
  CHECK(r.status == 3);
  j = one_object(r);
  CHECK(j["termination"] == "refused");
  CHECK(j["method_requested"] == "dual");
  CHECK_THAT(j["message"].get<std::string>(), Catch::Matchers::Contains("primal"));

  // A solver failure (exit 3): no equilibrium, with what the solver knows.
  const fs::path lift =
      scratch.write("lift.toml", free_beam(100.0, -1.0) + "[solve]\nmethod = \"primal\"\nelements = 10\n");
  r = run_cli({"solve", lift.string(), "--json"});
  CHECK(r.status == 3);
  j = one_object(r);
  CHECK(j["method_requested"] == "primal");
  CHECK(j["termination"] != "solved");
  CHECK_THAT(j["message"].get<std::string>(), Catch::Matchers::Contains("no equilibrium"));
  CHECK(j["elements"] == 10);

  // The output cannot be written (exit 4): one object, the failure's, and no file.
  r = run_cli({"solve", good.string(), "--json", "--output", "/no/such/dir/out.h5"});
  CHECK(r.status == 4);
  CHECK(one_object(r)["termination"] == "output_error");
  r = run_cli({"solve", good.string(), "--json", "--method", "all", "--elements", "20", "--modes", "8", "--output",
               "/no/such/dir/out.h5"});
  CHECK(r.status == 4);
  CHECK(one_object(r)["termination"] == "output_error");

  // --method all: one object with the run's keys and every method.
  r = run_cli({"solve", free.string(), "--json", "--method", "all", "--modes", "8"});
  CHECK(r.status == 0);
  j = one_object(r);
  CHECK(j["method_requested"] == "all");
  CHECK(j["methods"].size() == 4);
}

// A script must not take a failure's figures for an answer: every answer key null, and `method`
// only a solver that ran (null when none did), `methods_run` all of them.
TEST_CASE("cli: a failure's JSON has null for every answer field and names only the solvers that ran",
          "[app][errors]") {
  Scratch scratch;
  const auto check_no_answer = [](const nlohmann::json& j) {
    for (const char* key : liftoff::io::answer_keys) {
      CAPTURE(key);
      REQUIRE(j.contains(key));
      CHECK(j[key].is_null());
    }
  };
  // Pulled off its foundation: the resultant check decides before the primal Lemke runs (w_max
  // was 0.0, max_reaction 0.0, residual -1 and method "primal").
  const fs::path lift =
      scratch.write("lift.toml", free_beam(100.0, -1.0) + "[solve]\nmethod = \"primal\"\nelements = 10\n");
  Run r = run_cli({"solve", lift.string(), "--json"});
  CHECK(r.status == 3);
  nlohmann::json j = one_object(r);
  CHECK(j["termination"] == "no_equilibrium");
  check_no_answer(j);
  CHECK(j["method"].is_null());
  CHECK(j["methods_run"] == nlohmann::json::array());
  CHECK(j["pivots"].is_null());  // not -1
  CHECK(j["elements"] == 10);    // the discretisation was made: not an answer

  // The shipped strut bowed away from its support beyond its Euler load (exit 5): auto runs fast
  // first (which hands over to Lemke inside the contact solver when it finds no contact set).
  std::ifstream in(std::string(LIFTOFF_SOURCE_DIR) + "/verification/scenes/axial/pinned_strut_one_sided.toml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text.replace(text.find("amplitude = 0.012"), 17, "amplitude = -0.012");
  text.replace(text.find("value = 2.467e6"), 15, "value = 3.300e6");
  r = run_cli({"solve", scratch.write("away.toml", text).string(), "--json"});
  CHECK(r.status == 5);
  j = one_object(r);
  CHECK(j["termination"] == "unstable_equilibrium");
  check_no_answer(j);
  REQUIRE_FALSE(j["methods_run"].empty());
  CHECK(j["methods_run"][0] == "fast");
  CHECK(j["method"] == j["methods_run"].back());

  // The Ritz model that cannot reach a tolerance within its modes: it ran; its amplitudes are no
  // answer, its residual history is the evidence.
  std::ifstream seed(scene_path("seed_beam_end_moments"));
  const std::string seed_text((std::istreambuf_iterator<char>(seed)), std::istreambuf_iterator<char>());
  r = run_cli({"solve",
               scratch.write("few_modes.toml", seed_text + "tolerance = 1e-12\n[ritz]\nmax_modes = 16\n").string(),
               "--method", "ritz", "--json"});
  CHECK(r.status == 3);
  j = one_object(r);
  CHECK(j["termination"] == "tolerance_not_reached");
  check_no_answer(j);
  CHECK(j["amplitudes"].is_null());
  CHECK(j["method"] == "ritz");
  CHECK_FALSE(j["residual_history"].empty());

  // A refusal before solving (the dual form on a member only the foundation holds), and bad input:
  // the failure object, its answer keys null too.
  const fs::path free = scratch.write("free.toml", free_beam(100.0, 1.0) + "[solve]\nelements = 10\n");
  r = run_cli({"solve", free.string(), "--method", "dual", "--json"});
  CHECK(r.status == 3);
  j = one_object(r);
  CHECK(j["termination"] == "refused");
  check_no_answer(j);
  r = run_cli({"solve", "/no/such/scene.toml", "--json"});
  CHECK(r.status == 2);
  j = one_object(r);
  check_no_answer(j);
  CHECK(j["method"].is_null());

  // --method all: the refused dual's object names no method; the answers keep theirs.
  j = one_object(run_cli({"solve", free.string(), "--json", "--method", "all", "--modes", "8"}));
  REQUIRE(j["methods"].size() == 4);
  const nlohmann::json& dual = j["methods"][1];
  CHECK(dual["method_requested"] == "dual");
  CHECK(dual["termination"] == "refused");
  CHECK(dual["method"].is_null());
  check_no_answer(dual);
  CHECK(j["methods"][2]["method"] == "fast");
  CHECK(j["methods"][2]["w_max"].is_number());
  CHECK_FALSE(j["methods"][2].contains("methods_run"));
}

// Arch supports resolved horizontally and vertically: the supports' V and the foundation carry the
// vertical load, the H and the foundation the horizontal one, and a symmetric arch's two H are
// equal and opposite. The certificate's force balance (certify/README.md) accepts an imbalance up
// to its round-off tolerance; H and V are a rotation of the same reactions, so they balance within
// it too (a wrong sign or angle would be off by the reactions themselves).
TEST_CASE("cli: arch support reactions as H and V balance the loads; a symmetric arch's thrusts are opposite",
          "[app][design]") {
  // The pinned seed arch (foundation inside, a crown load) and the buried culvert (side = "outside",
  // gravity and cover; its hand calculation: the footings carry 246.9 kN/m, 5.2 kN/m more than the
  // loads, and the thrust is below the 47.6 kN of the arch without fill).
  for (const std::string& scene :
       {scene_path("seed_arch_pinned"),
        std::string(LIFTOFF_SOURCE_DIR) + "/verification/scenes/engineering/buried_arch_gravity.toml"}) {
    CAPTURE(scene);
    const Run r = run_cli({"solve", scene, "--json"});
    REQUIRE(r.status == 0);
    const nlohmann::json j = nlohmann::json::parse(r.out);
    const nlohmann::json& c = j["certificate"];
    double tolerance = 0.0;
    for (const auto& check : c["checks"])
      if (check["name"] == "force_balance_x" || check["name"] == "force_balance_y")
        tolerance = std::max(tolerance, check["tolerance"].get<double>());
    REQUIRE(tolerance > 0.0);
    const nlohmann::json& supports = j["support_reactions"];
    REQUIRE(supports.size() == 2);
    double sum_h = 0.0, sum_v = 0.0;
    for (const auto& s : supports) {
      sum_h += s["horizontal"].get<double>();
      sum_v += s["vertical"].get<double>();
    }
    const double applied = c["applied_force"].get<double>();  // downward: toward the inside at the crown
    CHECK(std::abs(sum_v - (applied - c["foundation_resultant"].get<double>())) <= tolerance * std::abs(applied));
    CHECK(std::abs(sum_h - (c["applied_force_x"].get<double>() - c["foundation_resultant_x"].get<double>())) <=
          tolerance * std::abs(applied));
    const double left = supports[0]["horizontal"].get<double>(), right = supports[1]["horizontal"].get<double>();
    CHECK(left > 0.0);  // the left support pushes the arch to the right: a thrust
    CHECK(std::abs(left + right) <= tolerance * left);
    CHECK(std::abs(supports[0]["vertical"].get<double>() - supports[1]["vertical"].get<double>()) <=
          tolerance * std::abs(sum_v));
    CHECK_THAT(run_cli({"solve", scene}).out, Catch::Matchers::Contains("(H "));
    if (scene.find("buried") != std::string::npos) {
      CHECK(sum_v == Approx(246.9e3).epsilon(5e-4));  // the scene's figure, to its four digits
      CHECK(left < 47.6e3);
    }
  }
}

namespace {
// Every key of a JSON value, objects' and those of the first element of each array, with its path.
void collect_keys(const nlohmann::json& j, const std::string& path, std::vector<std::string>& out) {
  if (j.is_object()) {
    for (const auto& [key, value] : j.items()) {
      out.push_back(path + "." + key);
      collect_keys(value, path + "." + key, out);
    }
  } else if (j.is_array() && !j.empty()) {
    collect_keys(j.front(), path + "[]", out);
  }
}
}  // namespace

// The output reference lists every field the JSON writers emit: each key of a solve (an arch, a
// beam-column, a tolerance, the Ritz model, a failure) and of a trace must be named, as `key` or
// "key", in src/io/README.md or the documents it defers to (the certificate's, the trace's).
TEST_CASE("cli: every JSON output field is named in the output reference", "[app][json]") {
  std::string reference;
  for (const char* doc : {"/src/io/README.md", "/src/certify/README.md", "/continuation/README.md"}) {
    std::ifstream in(std::string(LIFTOFF_SOURCE_DIR) + doc);
    REQUIRE(in.good());
    reference += std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }
  const std::string engineering = std::string(LIFTOFF_SOURCE_DIR) + "/verification/scenes/";
  Scratch scratch;
  const fs::path lift = scratch.write("lift.toml", free_beam(100.0, -1.0) + "[solve]\nelements = 10\n");
  const std::vector<std::vector<std::string>> runs = {
      {"solve", "--json"},
      {"solve", engineering + "axial/pinned_strut_one_sided.toml", "--json"},
      {"solve", scene_path("seed_beam_end_moments"), "--json", "--tolerance", "1e-6"},
      {"solve", scene_path("seed_beam_end_moments"), "--json", "--method", "ritz"},
      {"solve", lift.string(), "--json"},
      {"trace", std::string(LIFTOFF_SOURCE_DIR) + "/continuation/scenes/arch_culvert.toml", "--json"}};
  for (const std::vector<std::string>& args : runs) {
    CAPTURE(args);
    const Run r = run_cli(args);
    std::vector<std::string> keys;
    collect_keys(nlohmann::json::parse(r.out), "", keys);
    CHECK(keys.size() > 10);
    std::vector<std::string> missing;
    for (const std::string& path : keys) {
      const std::string key = path.substr(path.rfind('.') + 1);
      if (reference.find("`" + key + "`") == std::string::npos &&
          reference.find("\"" + key + "\"") == std::string::npos)
        missing.push_back(path);
    }
    CAPTURE(missing);
    CHECK(missing.empty());
  }
}

TEST_CASE("cli: --method all shows the scene's k and no counters for a refused method", "[app]") {
  Scratch scratch;
  // Primal is listed first; with k known only from the methods that ran, a refused first column
  // once made the header read k = 0.
  const fs::path free = scratch.write("free.toml", free_beam(5184.0, 1.0) + "[solve]\nelements = 40\n");
  const Run r = run_cli({"solve", free.string(), "--method", "all", "--modes", "8"});
  REQUIRE(r.status == 0);
  CHECK_THAT(r.out, Catch::Matchers::Contains("on a tensionless foundation, nondimensional k = 5184\n"));
  // The dual is refused: no "-1 elements", "-1 pivots" or residual -1.0e+00, but "-".
  CHECK_THAT(r.out, !Catch::Matchers::Contains(" -1 ") && !Catch::Matchers::Contains(" -1.0e+00"));
  std::istringstream lines(r.out);
  std::string line;
  while (std::getline(lines, line))
    if (line.rfind("  size", 0) == 0) CHECK(line.find("     -") != std::string::npos);
  // The JSON of a refused method carries the scene's k too.
  const auto j =
      nlohmann::json::parse(run_cli({"solve", free.string(), "--method", "all", "--modes", "8", "--json"}).out);
  CHECK(j["methods"][1]["termination"] == "refused");
  CHECK(j["methods"][1]["k"] == 5184.0);
}

TEST_CASE("cli: trace needs a scene with [trace], and its help says so", "[app][trace]") {
  const Run help = run_cli({"trace", "--help"});
  CHECK(help.status == 0);
  CHECK_THAT(help.out, Catch::Matchers::Contains("with a [trace] table"));
  CHECK_THAT(help.out, !Catch::Matchers::Contains("default: "));
  const Run none = run_cli({"trace"});
  CHECK(none.status == 2);
  CHECK(one_line(none.err));
}

// ---- accuracy on demand: [solve] tolerance, --tolerance -----------------------------------------

TEST_CASE("cli: --tolerance gives limits within it, with the estimates and the meshes used", "[app][tolerance]") {
  // The seed beam with end moments: one contact region [t, L], t = 0.802388873075 L exactly
  // (verification/closed_form, 12 digits: well below the tolerances asked for here).
  const double exact_limit = 0.802388873075;
  // Dense Lemke gives the topology on a coarser mesh (primal takes seconds at 200 elements); the
  // tolerance wins over --elements, which sets only that first mesh.
  const std::pair<const char*, const char*> runs[] = {
      {"auto", "200"}, {"fast", "200"}, {"dual", "60"}, {"primal", "40"}};
  for (const auto& [method, elements] : runs) {
    CAPTURE(method);
    const Run r = run_cli({"solve", scene_path("seed_beam_end_moments"), "--method", method, "--elements", elements,
                           "--tolerance", "1e-8", "--json"});
    CAPTURE(r.err);
    REQUIRE(r.status == 0);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j["tolerance"].get<double>() == 1e-8);
    CHECK(j["limit_fitted"].get<bool>());
    CHECK(j["certificate"]["passed"].get<bool>());
    REQUIRE(j["contact_regions"].size() == 1);
    const double limit = j["contact_regions"][0][0].get<double>();
    CHECK(std::abs(limit - exact_limit) <= 1e-8);
    // The estimate is honest (at least a third of the true error) and below the tolerance.
    const double estimate = j["estimated_limit_error"].get<double>();
    CHECK(estimate <= 1e-8);
    CHECK(estimate >= std::abs(limit - exact_limit) / 3);
    CHECK(j["estimated_w_error"].get<double>() <= 1e-8);
    CHECK(j["estimated_reaction_error"].get<double>() <= 1e-8);
    const auto meshes = j["elements_used"].get<std::vector<int>>();
    REQUIRE(meshes.size() >= 2);
    CHECK(meshes.back() == j["elements"].get<int>());
    for (std::size_t i = 1; i < meshes.size(); ++i) CHECK(meshes[i] > meshes[i - 1]);
  }
  // The summary says it too.
  const Run text = run_cli({"solve", scene_path("seed_beam_end_moments"), "--tolerance", "1e-8"});
  CHECK(text.status == 0);
  CHECK(text.out.find("accuracy      tolerance 1.0e-08") != std::string::npos);
}

TEST_CASE("cli: a bad tolerance is exit 2 naming the option or the key", "[app][tolerance][errors]") {
  for (const char* bad : {"0", "-1e-8", "nan", "0.2", "1e-14", "tight"}) {
    CAPTURE(bad);
    const Run r = run_cli({"solve", scene_path("seed_beam_end_moments"), "--tolerance", bad});
    CHECK(r.status == 2);
    CHECK(r.err.find("--tolerance") != std::string::npos);
    CHECK(r.err.find("expected a number in [1e-13, 0.1]") != std::string::npos);
  }
  Scratch scratch;
  std::ifstream in(scene_path("seed_beam_end_moments"));
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const char* bad : {"0.0", "1e-20", "0.5", "\"fine\""}) {
    CAPTURE(bad);
    const fs::path scene = scratch.write("bad_tolerance.toml", text + "tolerance = " + bad + "\n");
    const Run r = run_cli({"solve", scene.string()});
    CHECK(r.status == 2);
    CHECK(one_line(r.err));
    CHECK(r.err.find("solve.tolerance") != std::string::npos);
  }
  const Run trace = run_cli({"trace", scene_path("seed_beam_end_moments"), "--tolerance", "1e-8"});
  CHECK(trace.status == 2);
}

TEST_CASE("cli: a tolerance the Ritz modes cannot reach is refused, exit 3, with the reason", "[app][tolerance]") {
  Scratch scratch;
  std::ifstream in(scene_path("seed_beam_end_moments"));
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const fs::path scene = scratch.write("few_modes.toml", text + "tolerance = 1e-12\n[ritz]\nmax_modes = 16\n");
  const Run r = run_cli({"solve", scene.string(), "--method", "ritz", "--json"});
  CHECK(r.status == 3);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["termination"] == "tolerance_not_reached");
  CHECK(j["message"].get<std::string>().find("16 modes") != std::string::npos);
}

TEST_CASE("cli: tolerances below 1e-10 are reached on the seed beam, and the round-off floor is stated",
          "[app][tolerance]") {
  // The certificate measures the round-off of the mixed solve in the mixed form (~1e-16 of max
  // |w|; measured in the stiffness form it read eps N^4, 3.5e-10 at 2048 elements, and refused
  // 1e-11). The floor is the reaction's: 16 eps times max |w| over the largest contact w (10
  // times smaller), 4e-14, far below 1e-11; the exact limit (closed form, 12 digits) is within it.
  const double exact_limit = 0.802388873075;
  const Run r = run_cli({"solve", scene_path("seed_beam_end_moments"), "--tolerance", "1e-11", "--json"});
  CAPTURE(r.err);
  REQUIRE(r.status == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["certificate"]["passed"].get<bool>());
  const double floor = j["round_off_floor"].get<double>();
  CHECK(floor > 0);
  CHECK(floor < 1e-11);
  CHECK(std::abs(j["contact_regions"][0][0].get<double>() - exact_limit) <= 1e-11);
  const Run text = run_cli({"solve", scene_path("seed_beam_end_moments"), "--tolerance", "1e-11"});
  CHECK(text.status == 0);
  CHECK(text.out.find("round-off floor") != std::string::npos);
  // The pinned arch's changes stop decreasing near 1e-11 (at 16384 elements): 1e-13 is below its
  // floor, refused with the floor in the message and the JSON.
  const Run arch = run_cli({"solve", scene_path("seed_arch_pinned"), "--tolerance", "1e-13", "--json"});
  CHECK(arch.status == 3);
  const auto a = nlohmann::json::parse(arch.out);
  CHECK(a["termination"] == "tolerance_not_reached");
  const double arch_floor = a["round_off_floor"].get<double>();
  CHECK(arch_floor > 1e-13);
  CHECK(a["message"].get<std::string>().find(fmt::format("the round-off floor is {:.1e}", arch_floor)) !=
        std::string::npos);
}

TEST_CASE("cli: a tolerance below the Ritz model's round-off is refused as such, with what it can honour",
          "[app][tolerance]") {
  // 1e-8 needs 128 modes on the seed beam, whose round-off (eps times the Jacobian's condition)
  // is 1.5e-5 there: not a failed answer but a tolerance the Ritz model cannot honour.
  const Run r =
      run_cli({"solve", scene_path("seed_beam_end_moments"), "--method", "ritz", "--tolerance", "1e-8", "--json"});
  CHECK(r.status == 3);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["termination"] == "tolerance_not_reached");
  const std::string message = j["message"].get<std::string>();
  CAPTURE(message);
  CHECK(message.find("below the Ritz model's round-off") != std::string::npos);
  CHECK(message.find(fmt::format("with {} modes its round-off is", j["modes"].get<int>() / 2)) != std::string::npos);
  // The floor: the smaller round-off of the two mode counts, above the tolerance; the certificate
  // is attached, failing on round-off.
  CHECK(j["round_off_floor"].get<double>() > 1e-8);
  CHECK(j["round_off_floor"].get<double>() < j["certificate"]["round_off_estimate"].get<double>());
  CHECK_FALSE(j["certificate"]["passed"].get<bool>());
}

TEST_CASE("cli: a limit-fitted answer clamped in contact passes its certificate", "[app][tolerance]") {
  // The 500 m pipeline is clamped at both ends, in contact up to them. Its limit-fitted answer's
  // P1 reaction there, the L2 projection of k w onto the contact elements where w is held at 0,
  // is an O(h^2) artefact of either sign (3.1e-4 of the largest at 1604 elements); the sign of
  // the reaction is checked pointwise (w >= 0 on contact elements) instead, as at the limits.
  const std::string path =
      std::string(LIFTOFF_SOURCE_DIR) + "/verification/scenes/engineering/pipeline_500m_uplift.toml";
  const Run r = run_cli({"solve", path, "--tolerance", "1e-6", "--json"});
  CAPTURE(r.err);
  REQUIRE(r.status == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["certificate"]["passed"].get<bool>());
  CHECK(j["limit_fitted"].get<bool>());
  CHECK(j["estimated_limit_error"].get<double>() <= 1e-6 * 500.0);
}

TEST_CASE("cli: a tolerance settles the Ritz model's deflection and reaction too, not only its limits",
          "[app][tolerance]") {
  // The limits settle first (3e-6 L at 32 modes on the seed beam) while w and the reaction near
  // the limits still move by 5e-6 and 6e-5: a tolerance promises all three.
  const Run r =
      run_cli({"solve", scene_path("seed_beam_end_moments"), "--method", "ritz", "--tolerance", "1e-4", "--json"});
  CAPTURE(r.err);
  REQUIRE(r.status == 0);
  const auto j = nlohmann::json::parse(r.out);
  REQUIRE(j["estimated_w_error"].is_number());
  REQUIRE(j["estimated_reaction_error"].is_number());
  CHECK(j["estimated_w_error"].get<double>() <= 1e-4);
  CHECK(j["estimated_reaction_error"].get<double>() <= 1e-4);
  // Against the limit-fitted FE answer at 1e-10 (its true error ~1e-12): w_max within the tolerance.
  const Run fe = run_cli({"solve", scene_path("seed_beam_end_moments"), "--tolerance", "1e-10", "--json"});
  REQUIRE(fe.status == 0);
  const auto f = nlohmann::json::parse(fe.out);
  const double w_max = f["w_max"].get<double>();
  CHECK(std::abs(j["w_max"].get<double>() - w_max) <= 1e-4 * std::abs(w_max));
}

TEST_CASE("cli: a tolerance on a member whose foundation covers part of it", "[app][tolerance]") {
  // The approach slab rests on soil over [3, 8] only, its span over [0, 3] is held by one
  // support: w there is free of any sign condition. The fitted solve checked w <= 0 on every
  // element without foundation, the span's included, and refused every tolerance ("wrong sign by
  // 1.0 of max |w|"). The answer is in contact over the whole soil; its w_max agrees with a
  // plain solve on 3200 elements (discretisation error ~h^4 there, below 1e-9 relative).
  const std::string path =
      std::string(LIFTOFF_SOURCE_DIR) + "/verification/scenes/engineering/approach_slab_one_support.toml";
  const Run r = run_cli({"solve", path, "--tolerance", "1e-8", "--json"});
  CAPTURE(r.err);
  REQUIRE(r.status == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["certificate"]["passed"].get<bool>());
  const Run plain = run_cli({"solve", path, "--elements", "3200", "--json"});
  REQUIRE(plain.status == 0);
  const double w_max = nlohmann::json::parse(plain.out)["w_max"].get<double>();
  CHECK(std::abs(j["w_max"].get<double>() - w_max) <= 1e-8 * std::abs(w_max));
}

TEST_CASE("cli: support reactions, design values and the foundation resultant in JSON and HDF5", "[app][design]") {
  Scratch scratch;
  // Pinned-pinned with an interior support and a lift-off: three reactions, a hogging moment.
  const fs::path scene = scratch.write("supported.toml", R"(
[structure]
kind = "beam"
length = 4.0
EI = 2.0e3
[supports]
left = "pinned"
right = "free"
interior = [2.5]
[foundation]
k = 200.0
[[loads]]
kind = "force"
at = 3.5
value = 50.0
[[loads]]
kind = "uniform"
value = 3.0
[solve]
elements = 80
)");
  const fs::path output = scratch.dir / "out.h5";
  const Run r = run_cli({"solve", scene.string(), "--json", "--output", output.string()});
  REQUIRE(r.status == 0);
  const auto j = nlohmann::json::parse(r.out);
  REQUIRE(j.contains("support_reactions"));
  REQUIRE(j["support_reactions"].size() == 2);
  double forces = 0.0, magnitude = 0.0;
  for (const auto& s : j["support_reactions"]) {
    CHECK(s.contains("at"));
    CHECK(s.contains("moment"));
    forces += s["force"].get<double>();
    magnitude += std::abs(s["force"].get<double>());
  }
  // Supports + foundation = applied, within the certificate's own force-balance tolerance
  // (relative to the same terms).
  const auto& c = j["certificate"];
  const double applied = c["applied_force"], resultant = j["foundation_resultant"]["force"];
  double tolerance = 0.0;
  for (const auto& check : c["checks"])
    if (check["name"] == "force_balance") tolerance = check["tolerance"];
  REQUIRE(tolerance > 0.0);
  CHECK(std::abs(forces + resultant - applied) <= tolerance * (magnitude + std::abs(resultant) + std::abs(applied)));
  CHECK(j["foundation_resultant"]["centroid"].get<double>() == c["foundation_centroid"].get<double>());
  REQUIRE(j.contains("design"));
  for (const char* name : {"moment_max", "moment_min", "shear_max_abs", "pressure_max", "uplift_max"}) {
    INFO(name);
    REQUIRE(j["design"].contains(name));
    CHECK(j["design"][name].contains("value"));
    CHECK(j["design"][name].contains("at"));
  }
  CHECK(j["design"]["moment_min"]["value"].get<double>() < 0.0);  // hogging over the interior support
  CHECK(j["design"]["moment_max"]["value"].get<double>() > 0.0);
  CHECK(j["design"]["from_statics"] == true);
  // The summary prints them.
  const Run summary = run_cli({"solve", scene.string()});
  CHECK_THAT(summary.out, Catch::Contains("  supports      x = 0") && Catch::Contains("  moment        max ") &&
                              Catch::Contains("  shear         max |V|") && Catch::Contains("  uplift        "));

  // HDF5: /design's attributes are the JSON's.
  const fs::path script = scratch.write("read.py", R"(
import sys, h5py
f = h5py.File(sys.argv[1], "r")
print(repr(float(f["design"].attrs["moment_min"])), repr(float(f["design"].attrs["moment_min_at"])), f["support_reactions"].shape[0])
)");
  const fs::path printed = scratch.dir / "h5py.txt";
  REQUIRE(std::system(
              ("/usr/bin/python3 " + script.string() + " " + output.string() + " > " + printed.string()).c_str()) == 0);
  std::ifstream in(printed);
  std::string value, at;
  int supports = 0;
  in >> value >> at >> supports;
  CHECK(std::stod(value) == j["design"]["moment_min"]["value"].get<double>());
  CHECK(std::stod(at) == j["design"]["moment_min"]["at"].get<double>());
  CHECK(supports == 2);
}

TEST_CASE("cli: --csv-fields writes the sampled fields; an unwritable one is exit 4 and leaves nothing", "[app][csv]") {
  Scratch scratch;
  const fs::path scene = scratch.write("free.toml", free_beam(100.0, 1.0) + "[solve]\nelements = 20\n");
  const fs::path csv = scratch.dir / "fields.csv";
  const Run r = run_cli({"solve", scene.string(), "--csv-fields", csv.string()});
  REQUIRE(r.status == 0);
  CHECK_FALSE(fs::exists(csv.string() + ".tmp"));
  std::ifstream in(csv);
  std::string header, line;
  std::getline(in, header);
  CHECK(header == "x,w,rotation,moment,shear,reaction");
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream cells(line);
    std::string cell;
    while (std::getline(cells, cell, ',')) row.push_back(std::stod(cell));
    CHECK(row.size() == 6);
    rows.push_back(row);
  }
  // 16 samples per element (the default) plus the end.
  CHECK(rows.size() == 20 * 16 + 1);
  CHECK(rows.front()[0] == 0.0);
  CHECK(rows.back()[0] == 1.0);
  // Free ends: shear and moment from the statics vanish there (to round-off of the 0.5 peak).
  CHECK(std::abs(rows.back()[4]) <= 1e-12);
  CHECK(std::abs(rows.back()[3]) <= 1e-12);

  // A directory that does not exist: exit 4, no file, no temporary, no HDF5 either.
  const fs::path h5 = scratch.dir / "out.h5";
  const Run bad = run_cli({"solve", scene.string(), "--output", h5.string(), "--csv-fields", "/no/such/dir/f.csv"});
  CHECK(bad.status == 4);
  CHECK(one_line(bad.err));
  CHECK_FALSE(fs::exists(h5));
  CHECK_FALSE(fs::exists(h5.string() + ".tmp"));
}

// The issue's trap: the B70 sleeper (verification/scenes/engineering/sleeper_b70_ballast.toml) with
// its modulus K = 2.5e7 N/m^2 written as the old nondimensional key k.
const std::string sleeper_trap = sleeper_b70("k = 2.5e7", "[units]\nsystem = \"N-m\"\n");

TEST_CASE("cli: units and the foundation's scale in the summary, JSON and HDF5; the trap warns", "[app][units]") {
  Scratch scratch;
  const fs::path scene = scratch.write("trap.toml", sleeper_trap);
  const Run text = run_cli({"solve", scene.string()});
  REQUIRE(text.status == 0);
  CHECK_THAT(text.out, Catch::Contains("  WARNING       " + scene.string() +
                                       ":10: key 'foundation.k': 'k' is the "
                                       "old name of 'nondimensional_k'"));
  CHECK_THAT(text.out, Catch::Contains("  WARNING       foundation: nondimensional_k = 2.5e+07 (K L^4/EI) gives beta "
                                       "L = 50") &&
                           Catch::Contains("write modulus = 2.5e+07 instead"));
  CHECK_THAT(text.out, Catch::Contains("  units         N-m: force N, length m, moment N m"));
  CHECK_THAT(text.out, Catch::Contains("beta L = 50, 1/beta = 0.052 m"));
  CHECK_THAT(text.out, Catch::Contains(" m at ") && Catch::Contains("max reaction") && Catch::Contains(" N/m\n"));

  const fs::path output = scratch.dir / "trap.h5";
  const Run r = run_cli({"solve", scene.string(), "--json", "--output", output.string()});
  REQUIRE(r.status == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["units"]["length"] == "m");
  CHECK(j["units"]["force"] == "N");
  CHECK(j["units"]["modulus"] == "N/m^2");
  CHECK(j["scale"]["beta_L"].get<double>() == Approx(50.0).epsilon(1e-14));  // (2.5e7/4)^(1/4), round-off
  CHECK(j["scale"]["nondimensional_k"] == 2.5e7);
  REQUIRE(j["warnings"].size() == 3);  // the old key, the likely mistake, a K no real bed has
  CHECK_THAT(j["warnings"][1].get<std::string>(), Catch::Contains("write modulus = 2.5e+07 instead"));
  const fs::path script = scratch.write("units.py", R"(
import sys, h5py
f = h5py.File(sys.argv[1], "r")
print(f.attrs["units_length"], f.attrs["units_force"], f.attrs["units_moment"].replace(" ", "_"), "modulus = 2.5e+07" in f.attrs["warnings"], round(float(f.attrs["scale_beta_L"]), 9))
)");
  const fs::path printed = scratch.dir / "units.txt";
  REQUIRE(std::system(
              ("/usr/bin/python3 " + script.string() + " " + output.string() + " > " + printed.string()).c_str()) == 0);
  std::ifstream in(printed);
  std::string length, force, moment, warned, beta_L;
  in >> length >> force >> moment >> warned >> beta_L;
  CHECK(length == "m");
  CHECK(force == "N");
  CHECK(moment == "N_m");
  CHECK(warned == "True");
  CHECK(beta_L == "50.0");

  // Written as `modulus` (what was meant): no warning, and full contact.
  std::string meant = sleeper_trap;
  meant.replace(meant.find("k = 2.5e7"), 9, "modulus = 2.5e7");
  const Run fixed = run_cli({"solve", scratch.write("meant.toml", meant).string(), "--json"});
  REQUIRE(fixed.status == 0);
  const auto m = nlohmann::json::parse(fixed.out);
  CHECK(m["warnings"].empty());
  CHECK(m["contact_regions"].size() == 1);
}

TEST_CASE("cli: a bad [units] is bad input: exit 2, one line naming the file and the key", "[app][units]") {
  Scratch scratch;
  std::string text = sleeper_trap;
  text.replace(text.find("system = \"N-m\""), 14, "system = \"N-m\"\nforce = \"kN\"");
  const fs::path scene = scratch.write("bad_units.toml", text);
  const fs::path output = scratch.dir / "never.h5";
  const Run r = run_cli({"solve", scene.string(), "--output", output.string()});
  CHECK(r.status == 2);
  CHECK(one_line(r.err));
  CHECK_THAT(r.err, Catch::Contains(scene.string() + ":21: key 'units.force': expected either 'system' or the "
                                                     "labels 'length' and 'force', got both ways"));
  CHECK_FALSE(fs::exists(output));
}

TEST_CASE("cli: sweeps edit the renamed key under either name and report warnings on stderr", "[app][units]") {
  Scratch scratch;
  const fs::path old_scene = scratch.write("old.toml", sleeper_trap);  // k = 2.5e7 (the old name)
  // The new name edits the old key (no second key, which the reader would refuse).
  const Run r = run_cli({"sweep", old_scene.string(), "--set", "foundation.nondimensional_k=2.5e7,254", "--jobs", "1"});
  REQUIRE(r.status == 0);
  CHECK_THAT(r.err, Catch::Contains("liftoff: warning: ") && Catch::Contains("'k' is the old name"));
  CHECK_THAT(r.err, Catch::Contains("foundation.nondimensional_k=2.5e+07]: foundation: nondimensional_k = 2.5e+07"));
  CHECK_THAT(r.err, !Catch::Contains("nondimensional_k = 254 (K L^4/EI) gives"));  // the plausible case is quiet
  // And the old name edits the new key.
  std::string renamed = sleeper_trap;
  renamed.replace(renamed.find("k = 2.5e7"), 9, "nondimensional_k = 2.5e7");
  const Run n =
      run_cli({"sweep", scratch.write("new.toml", renamed).string(), "--set", "foundation.k=254", "--jobs", "1"});
  REQUIRE(n.status == 0);
  CHECK_THAT(n.err, !Catch::Contains("warning"));
}

TEST_CASE("cli: an axial force reports its force and the initial shape; an unstable state exits 5", "[app][axial]") {
  // The shipped strut (verification/scenes/axial/pinned_strut_one_sided.toml): solved, certified,
  // with axial_force and w_initial in its JSON; midspan w from its hand calculation.
  const std::string strut = std::string(LIFTOFF_SOURCE_DIR) + "/verification/scenes/axial/pinned_strut_one_sided.toml";
  const Run r = run_cli({"solve", strut, "--json"});
  CAPTURE(r.err);
  REQUIRE(r.status == 0);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  CHECK(j["termination"] == "solved");
  CHECK(j["axial_force"].get<double>() == 2.467e6);
  const std::vector<double> x = j["w_initial"]["coordinate"], w0 = j["w_initial"]["value"];
  REQUIRE(x.size() == 121);
  CHECK(w0[60] == Approx(0.012).epsilon(1e-12));  // the sampled half sine's crest, at midspan
  // v = P a0 / (P_E + K L^2/pi^2 - P) = 7.547e-3 m; the sampled bow and the mesh differ by < 1e-4.
  CHECK(j["w_max"].get<double>() == Approx(7.547e-3).epsilon(1e-3));

  // The same strut bowed away from its one-sided support beyond its Euler load: refused, exit 5.
  Scratch scratch;
  std::ifstream in(strut);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text.replace(text.find("amplitude = 0.012"), 17, "amplitude = -0.012");
  text.replace(text.find("value = 2.467e6"), 15, "value = 3.300e6");
  const fs::path away = scratch.write("away.toml", text);
  const Run unstable = run_cli({"solve", away.string(), "--json"});
  CHECK(unstable.status == 5);
  const nlohmann::json u = nlohmann::json::parse(unstable.out);
  CHECK(u["termination"] == "unstable_equilibrium");
  CHECK_THAT(u["message"].get<std::string>(), Catch::Matchers::Contains("exceeds the critical load"));
  // The Ritz method's start is that FE solve: refused the same way, exit 5 (not a solver failure).
  const Run ritz = run_cli({"solve", away.string(), "--method", "ritz", "--json"});
  CHECK(ritz.status == 5);
  CHECK(nlohmann::json::parse(ritz.out)["termination"] == "unstable_equilibrium");
}

TEST_CASE("cli: a von Karman scene is solved by solve, sweep and envelope; the unserved methods are refused, exit 2",
          "[app][von_karman]") {
  // Issue 16's shallow arch (verification/dolfinx/scenes/issue16/). The theory table
  // (app/theory_gate.hpp): solve auto/fast/ritz, sweep and envelope solve it (trace too: both
  // paths, tests/app/trace_test.cpp); dual, primal and a tolerance are refused before any work,
  // one line naming the key, nothing written.
  std::ifstream in(std::string(LIFTOFF_SOURCE_DIR) +
                   "/verification/dolfinx/scenes/issue16/shallow_arch_tensionless.toml");
  REQUIRE(in);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Scratch scratch;
  const fs::path scene = scratch.write("arch.toml", text +
                                                        "\n[trace]\nlambda_max = 1.0\n\n[[combinations]]\nname = "
                                                        "\"ULS\"\nfactors = { live = 1.5 }\n");
  const fs::path output = scratch.dir / "out.h5";
  const std::vector<std::pair<std::string, std::vector<std::string>>> refused = {
      {"option '--method': theory = \"von_karman\": the dual and primal methods solve a linear complementarity "
       "problem (Lemke), linear theory only; expected \"auto\", \"fast\" or \"ritz\" (liftoff solve)",
       {"solve", scene.string(), "--method", "dual", "--output", output.string()}},
      {"option '--tolerance': theory = \"von_karman\": the limit-fitted meshes of a tolerance are linear theory "
       "only; expected no tolerance (the von Karman FE solve uses [solve] elements) (liftoff solve)",
       {"solve", scene.string(), "--tolerance", "1e-4", "--output", output.string()}},
  };
  for (const auto& [message, args] : refused) {
    CAPTURE(args);
    const Run r = run_cli(args);
    CHECK(r.status == 2);
    CHECK(r.out.empty());
    CHECK(r.err == "liftoff: " + scene.string() + ": " + message + "\n");
    CHECK_FALSE(fs::exists(output));
  }
  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{{"solve", scene.string()},
                                             {"solve", scene.string(), "--method", "ritz"},
                                             {"solve", scene.string(), "--method", "all"},
                                             {"sweep", scene.string(), "--set", "loads[0].value=1,2"},
                                             {"envelope", scene.string()}}) {
    CAPTURE(args);
    const Run r = run_cli(args);
    CAPTURE(r.err);
    CHECK(r.status == 0);
  }
  // --json: the theory, the membrane force per element, stable, u at the nodes, the thrust.
  const Run json = run_cli({"solve", scene.string(), "--json"});
  REQUIRE(json.status == 0);
  const nlohmann::json j = nlohmann::json::parse(json.out);
  CHECK(j["theory"] == "von_karman");
  CHECK(j["stable"] == true);
  CHECK(j["membrane_force"]["per"] == "element");
  CHECK(j["membrane_force"]["value"].size() == 64);
  CHECK(j["u"]["value"].size() == 65);
  REQUIRE(j["support_reactions"].size() == 2);
  const double n = j["membrane_force"]["value"][0].get<double>();
  CHECK(n < 0);  // the arch is compressed by a load toward its foundation
  CHECK(j["support_reactions"][0]["horizontal"].get<double>() == Approx(-n).epsilon(1e-9));
  CHECK(j["support_reactions"][1]["horizontal"].get<double>() == Approx(n).epsilon(1e-9));
  // A load past the limit point: refused as limit_point, exit 5 (a loss of stability), nothing written.
  std::string heavy = text;
  heavy.replace(heavy.find("value = 1.0"), 11, "value = 25.0");
  const Run limit = run_cli({"solve", scratch.write("heavy.toml", heavy).string(), "--output", output.string()});
  CHECK(limit.status == 5);
  CHECK_THAT(limit.err, Catch::Matchers::Contains("limit point") && Catch::Matchers::Contains("use liftoff trace"));
  CHECK_FALSE(fs::exists(output));
}

TEST_CASE(
    "cli: a von Karman arch is solved by `solve` (auto, fast) and traced by the FE path, refused by every other "
    "method and command: exit 2, one line",
    "[app][von_karman]") {
  // `liftoff solve` serves the arch with the FE von Karman solve and certifies the answer, `liftoff
  // trace` with the FE path; the theory table (app/theory_gate.hpp) refuses the rest before any
  // work, keyed to structure.theory, nothing written.
  std::ifstream in(std::string(LIFTOFF_SOURCE_DIR) + "/verification/scenes/seed_arch_pinned.toml");
  REQUIRE(in);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text.replace(text.find("[structure]\n"), 12, "[structure]\ntheory = \"von_karman\"\n");
  Scratch scratch;
  const fs::path scene = scratch.write("arch.toml", text);
  const fs::path output = scratch.dir / "out.h5";
  const Run solved = run_cli({"solve", scene.string(), "--json"});
  CHECK(solved.status == 0);
  const auto j = nlohmann::json::parse(solved.out);
  CHECK(j["theory"] == "von_karman");
  CHECK(j["termination"] == "solved");
  CHECK(j["certificate"]["passed"] == true);
  // An arch's supports, whatever the theory: radial and tangential forces, and the same resolved
  // into horizontal (the thrust) and vertical; the two horizontal reactions of this symmetric
  // arch balance (no horizontal load), within the backward error a solve accepts (1e-8 relative).
  double horizontal = 0.0, size = 0.0;
  for (const auto& support : j["support_reactions"]) {
    CHECK(support.contains("tangential"));
    REQUIRE(support.contains("horizontal"));
    CHECK(support.contains("vertical"));
    horizontal += support["horizontal"].get<double>();
    size = std::max(size, std::abs(support["horizontal"].get<double>()));
  }
  CHECK(std::abs(horizontal) <= 1e-8 * size);
  const fs::path traced = scratch.write("arch_trace.toml", text + "\n[trace]\nlambda_max = 1.0\n");
  const Run trace = run_cli({"trace", traced.string(), "--elements", "40", "--json"});
  CHECK(trace.status == 0);
  CHECK(nlohmann::json::parse(trace.out)["termination"] == "completed");
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {"solve", scene.string(), "--method", "ritz", "--output", output.string()},
           {"solve", scene.string(), "--method", "dual", "--output", output.string()},
           {"solve", scene.string(), "--tolerance", "1e-4", "--output", output.string()},
           {"sweep", scene.string(), "--set", "loads[0].value=0.1,0.2", "--output", output.string()}}) {
    CAPTURE(args);
    const Run r = run_cli(args);
    CHECK(r.status == 2);
    CHECK(r.out.empty());
    CHECK_THAT(r.err, Catch::Matchers::StartsWith("liftoff: " + scene.string() + ": key 'structure.theory': ") &&
                          Catch::Matchers::Contains("theory = \"von_karman\" on an arch"));
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(output));
  }
  // The Ritz path has no membrane term for arches: refused as a scene the Ritz model cannot take.
  for (const char* method : {"ritz", "all"}) {
    CAPTURE(method);
    const Run r = run_cli({"trace", traced.string(), "--method", method, "--output", output.string()});
    CHECK(r.status == 2);
    CHECK_THAT(r.err, Catch::Matchers::Contains("key 'structure.theory'") && Catch::Matchers::Contains("arches"));
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(output));
  }
}

namespace {

// The eccentric footing of verification/scenes/engineering/footing_eccentric_column.toml in kN
// and m, with its EI and modulus as written.
std::string footing_kn(const std::string& EI, const std::string& modulus = "3.0e4") {
  return "[structure]\nkind = \"beam\"\nlength = 3.0\nEI = " + EI +
         "\n[supports]\nleft = \"free\"\nright = \"free\"\n[foundation]\nmodulus = " + modulus +
         "\n[[loads]]\nkind = \"force\"\nat = 1.8\nvalue = 800.0\n[[loads]]\nkind = \"moment\"\nat = 1.8\n"
         "value = -400.0\n[solve]\nelements = 100\n[units]\nsystem = \"kN-m\"\n";
}

}  // namespace

TEST_CASE("cli: the kN-m footing with EI written in N m^2 gives the answer of EI in kN m^2, bit for bit",
          "[app][units]") {
  Scratch scratch;
  const Run plain = run_cli({"solve", scratch.write("plain.toml", footing_kn("5.4e5")).string(), "--json"});
  const Run newtons =
      run_cli({"solve", scratch.write("newtons.toml", footing_kn("\"5.4e8 N m^2\"")).string(), "--json"});
  REQUIRE(plain.status == 0);
  REQUIRE(newtons.status == 0);
  nlohmann::json a = one_object(plain), b = one_object(newtons);
  // Everything but the scene's name and the time taken: the JSON compares its doubles exactly.
  for (nlohmann::json* j : {&a, &b}) j->erase("scene"), j->erase("time_s");
  CHECK(a == b);
  CHECK(a["termination"] == "solved");
  CHECK(a["warnings"].empty());
}

TEST_CASE("cli: a value of the wrong dimension is exit 2, one line naming the key", "[app][units][errors]") {
  Scratch scratch;
  const Run r = run_cli({"solve", scratch.write("wrong.toml", footing_kn("\"30 MN/m^2\"")).string()});
  CHECK(r.status == 2);
  CHECK(r.out.empty());
  CHECK(r.err == "liftoff: " + (scratch.dir / "wrong.toml").string() +
                     ":4: key 'structure.EI': expected a force*length^2 (a number > 0) in kN m^2 or a unit convertible "
                     "to it, got \"30 MN/m^2\" (\"MN/m^2\" is a force/length^2)\n");
}

TEST_CASE("cli: a modulus in MN/m^2 in a kN-m scene is named by the deflection it makes", "[app][units][warnings]") {
  // modulus = 30 meant as 30 MN/m^2: the rigid footing sinks about 800 / (30 x 3) = 8.9 m on its
  // 3 m; as 3e4 kN/m^2, about 9 mm.
  Scratch scratch;
  const Run r = run_cli({"solve", scratch.write("soft.toml", footing_kn("5.4e5", "30.0")).string(), "--json"});
  REQUIRE(r.status == 0);
  const nlohmann::json j = one_object(r);
  std::string deflection;
  for (const auto& w : j["warnings"])
    if (w.get<std::string>().rfind("deflection:", 0) == 0) deflection = w.get<std::string>();
  INFO(j["warnings"].dump());
  CHECK_THAT(deflection, Catch::Matchers::Contains("of the member's length L = 3 m") &&
                             Catch::Matchers::Contains("key 'foundation.modulus': modulus = 30 looks like MN/m^2 in a "
                                                       "kN-m scene: 1000x (as 3e+04 kN/m^2 w is about"));
  // The same modulus written with its unit solves the footing with no warning.
  const Run stated =
      run_cli({"solve", scratch.write("stated.toml", footing_kn("5.4e5", "\"30 MN/m^2\"")).string(), "--json"});
  CHECK(one_object(stated)["warnings"].empty());
}
