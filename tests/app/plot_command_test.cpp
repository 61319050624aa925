// `liftoff plot` in process (app/plot_command.hpp): the script's command line, the command's
// errors before the script runs, and a solve file drawn end to end. tests/app/plot_test.py runs
// the real executable on every kind of file and the script's own errors.
#include "app/plot_command.hpp"

#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "app/cli.hpp"
#include "support/cli.hpp"
#include "support/scratch.hpp"

namespace fs = std::filesystem;

using namespace liftoff::test;  // support/: the CLI runner, the scratch directory

namespace {}  // namespace

TEST_CASE("plot: the script's command line passes the file, --out and --normalise through", "[app][plot]") {
  using liftoff::app::PlotRequest;
  const auto line = liftoff::app::plot_command_line(PlotRequest{"r.h5", "", false});
  CHECK(line == std::vector<std::string>{liftoff::app::plot_python(), liftoff::app::plot_script(), "r.h5"});
  const auto full = liftoff::app::plot_command_line(PlotRequest{"r.h5", "fig/p", true});
  CHECK(full == std::vector<std::string>{liftoff::app::plot_python(), liftoff::app::plot_script(), "r.h5", "--out",
                                         "fig/p", "--normalise"});
  // The script is the source tree's (fixed at configure time), and it is there.
  CHECK(liftoff::app::plot_script() == std::string(LIFTOFF_SOURCE_DIR) + "/verification/plots/plot.py");
  CHECK(fs::is_regular_file(liftoff::app::plot_script()));
}

TEST_CASE("plot: no file, or a missing one, is exit 2 in one line before anything runs", "[app][plot][errors]") {
  const Run none = run_cli({"plot"});
  CHECK(none.status == 2);
  CHECK(one_line(none.err));
  CHECK(none.err.find("plot --help") != std::string::npos);
  const Run missing = run_cli({"plot", "/nonexistent/r.h5"});
  CHECK(missing.status == 2);
  CHECK(one_line(missing.err));
  CHECK(missing.err.find("/nonexistent/r.h5") != std::string::npos);
}

TEST_CASE("plot: a solve file is drawn, its PNG named after --out", "[app][plot]") {
  Scratch scratch;
  const std::string h5 = (scratch.dir / "arch.h5").string();
  REQUIRE(run_cli({"solve", "--output", h5}).status == 0);
  const std::string prefix = (scratch.dir / "fig").string();
  const Run r = run_cli({"plot", h5, "--out", prefix});
  INFO(r.err);
  REQUIRE(r.status == 0);
  // A figure of five diagrams and the scene at 120 dpi is over 100 kB; an empty one a few kB.
  CHECK(fs::file_size(prefix + "_diagrams.png") > 50'000);
  CHECK(fs::file_size(prefix + "_shape.png") > 10'000);
  CHECK_FALSE(fs::exists(prefix + "_diagrams.png.tmp"));
}
