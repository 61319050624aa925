// The command line as a user meets it: exit codes, one-line errors naming file and key, no
// output file after a failure, JSON on stdout, and an HDF5 file that describes itself.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "app/cli.hpp"

namespace fs = std::filesystem;

namespace {

struct Run {
  int status;
  std::string out, err;
};

Run run(std::vector<std::string> args) {
  args.insert(args.begin(), "liftoff");
  std::vector<const char*> argv;
  for (const auto& a : args) argv.push_back(a.c_str());
  std::ostringstream out, err;
  const int status = liftoff::app::run_cli(static_cast<int>(argv.size()), argv.data(), out, err);
  return {status, out.str(), err.str()};
}

std::string scene_path(const std::string& name) {
  return std::string(LIFTOFF_SOURCE_DIR) + "/verification/scenes/" + name + ".toml";
}

// A scratch directory, removed at the end of the test.
struct Scratch {
  fs::path dir = fs::temp_directory_path() / ("liftoff_cli_test_" + std::to_string(::getpid()));
  Scratch() { fs::create_directories(dir); }
  ~Scratch() { fs::remove_all(dir); }
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name) << text;
    return dir / name;
  }
};

bool one_line(const std::string& s) { return !s.empty() && s.find('\n') == s.size() - 1; }

const char* valid_beam = R"(
[structure]
kind = "beam"
length = 2.0
EI = 3.0
[supports]
left = "pinned"
right = "pinned"
[foundation]
k = 1.0e4
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
         "[foundation]\nk = " + std::to_string(k) + "\n[[loads]]\nkind = \"force\"\nat = 0.5\nvalue = " +
         std::to_string(force) + "\n";
}

}  // namespace

TEST_CASE("cli: help and version exit 0", "[app]") {
  CHECK(run({"--help"}).status == 0);
  CHECK(run({"solve", "--help"}).status == 0);
  CHECK_THAT(run({"solve", "--help"}).out, Catch::Matchers::Contains("--method"));
}

TEST_CASE("cli: solve with no scene runs the seed arch", "[app]") {
  const Run r = run({"solve", "--json"});
  REQUIRE(r.status == 0);
  const auto j = nlohmann::json::parse(r.out);  // stdout is exactly one JSON object
  CHECK(j["structure"] == "arch");
  CHECK(j["contact_regions"].size() == 1);
  for (const char* key : {"method", "contact_regions", "w_max", "at_w_max", "w_min", "at_w_min", "max_reaction",
                          "pivots", "residual", "elements", "time_s"})
    CHECK(j.contains(key));
}

TEST_CASE("cli: a malformed scene is one line naming file and key, exit 2, no output", "[app]") {
  Scratch scratch;
  std::string bad = valid_beam;
  bad.replace(bad.find("EI = 3.0"), 8, "EI = -3.0");
  const fs::path scene = scratch.write("bad.toml", bad);
  const fs::path output = scratch.dir / "out.h5";
  const Run r = run({"solve", scene.string(), "--output", output.string()});
  CHECK(r.status == 2);
  CHECK(one_line(r.err));
  CHECK_THAT(r.err, Catch::Matchers::Contains(scene.string()) && Catch::Matchers::Contains("structure.EI"));
  CHECK_FALSE(fs::exists(output));
  CHECK_FALSE(fs::exists(output.string() + ".tmp"));
}

TEST_CASE("cli: bad command-line values exit 2", "[app]") {
  CHECK(run({"solve", scene_path("seed_arch_pinned"), "--method", "fastest"}).status == 2);
  CHECK(run({"solve", scene_path("seed_arch_pinned"), "--elements", "0"}).status == 2);
  CHECK(run({"solve", "/no/such/scene.toml"}).status == 2);
  CHECK(run({"frobnicate"}).status == 2);
}

TEST_CASE("cli: a solver failure has its own exit code and a reason, no output", "[app]") {
  Scratch scratch;
  // A free beam pulled away from the foundation: no equilibrium.
  const fs::path scene = scratch.write("lift.toml", free_beam(100.0, -1.0) + "[solve]\nmethod = \"primal\"\nelements = 10\n");
  const fs::path output = scratch.dir / "out.h5";
  const Run r = run({"solve", scene.string(), "--output", output.string()});
  CHECK(r.status == 3);
  CHECK(one_line(r.err));
  CHECK_THAT(r.err, Catch::Matchers::Contains("no equilibrium"));
  CHECK_FALSE(fs::exists(output));
  // The dual form is refused for a free beam with a pointer to auto and fast.
  const fs::path pressed = scratch.write("press.toml", free_beam(100.0, 1.0));
  const Run dual = run({"solve", pressed.string(), "--method", "dual"});
  CHECK(dual.status == 3);
  CHECK_THAT(dual.err, Catch::Matchers::Contains("\"auto\"") && Catch::Matchers::Contains("\"fast\""));
}

TEST_CASE("cli: an unwritable output is exit 4 and leaves nothing", "[app]") {
  Scratch scratch;
  const fs::path scene = scratch.write("ok.toml", valid_beam);
  const Run r = run({"solve", scene.string(), "--output", "/no/such/dir/out.h5"});
  CHECK(r.status == 4);
  CHECK(one_line(r.err));
}

TEST_CASE("cli: the HDF5 file is complete and readable by h5py and h5dump", "[app][hdf5]") {
  Scratch scratch;
  const fs::path scene = scratch.write("ok.toml", valid_beam);
  const fs::path output = scratch.dir / "out.h5";
  const Run r = run({"solve", scene.string(), "--json", "--output", output.string()});
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
  REQUIRE(std::system(("/usr/bin/python3 " + script.string() + " " + output.string() + " > " + printed.string()).c_str()) == 0);
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
  const Run r = run({"solve", scene_path("seed_beam_end_moments"), "--method", "ritz", "--modes", "24", "--json"});
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
  const Run r = run({"solve", scene_path("seed_beam_end_moments_central_load"), "--method", "all", "--elements", "60",
                     "--modes", "16", "--json"});
  REQUIRE(r.status == 0);
  const auto j = nlohmann::json::parse(r.out);
  REQUIRE(j["methods"].size() == 4);
  CHECK(j["methods"][0]["method"] == "primal");
  CHECK(j["methods"][1]["method"] == "dual");
  CHECK(j["methods"][2]["method"] == "fast");
  CHECK(j["methods"][3]["method"] == "ritz");
  const Run text = run({"solve", scene_path("seed_beam_end_moments_central_load"), "--method", "all", "--elements",
                        "60", "--modes", "16"});
  CHECK_THAT(text.out, Catch::Matchers::Contains("contact 2 begin"));

  // A free-free beam: the dual is refused, the others run, and that is not a failure.
  Scratch scratch;
  const fs::path scene = scratch.write("free.toml", free_beam(5184.0, 1.0));
  const Run free = run({"solve", scene.string(), "--method", "all", "--elements", "40", "--modes", "24", "--json"});
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
  const Run r = run({"solve", scene.string(), "--method", "ritz"});
  CHECK(r.status == 2);
  CHECK(one_line(r.err));
  CHECK_THAT(r.err, Catch::Matchers::Contains("interior point supports"));
}
