// Tests of src/post/scale.*: the foundation's scale figures against their definitions, and each
// warning fires on the scene it is for and stays silent on the control beside it.

#include "post/scale.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <string>

#include "model/from_scene.hpp"
#include "scene/scene_reader.hpp"
#include "support/scenes.hpp"

using namespace liftoff;
using Catch::Matchers::Contains;

namespace {

// The B70 sleeper of verification/scenes/engineering/sleeper_b70_ballast.toml (N, m): L = 2.6,
// EI = 4.5e6, on a foundation written as `foundation` (its lines), two rail-seat loads.
scene::Scene sleeper(const std::string& foundation, const std::string& units = "") {
  return scene::parse_scene(test::sleeper_b70(foundation, units), "sleeper.toml");
}

std::vector<std::string> warnings_of(const scene::Scene& s, int elements = 0) {
  const model::MemberModel model = model::make_member_model(s);
  std::vector<double> mesh;
  for (int i = 0; i <= elements && elements > 0; ++i)  // uniform, as [solve] elements makes it
    mesh.push_back(model.s_begin + (model.s_end - model.s_begin) * i / elements);
  return post::scale_warnings(s, model, post::scale_figures(model, mesh));
}

// Each figure is a handful of roundings of its definition: 1e-14 relative is ~50 ulps.
constexpr double round_off = 1e-14;

}  // namespace

TEST_CASE("scale: K, beta, beta L, 1/beta and k of a beam follow their definitions", "[post][scale]") {
  const scene::Scene s = sleeper("modulus = 3.0e7");
  const post::ScaleFigures f = post::scale_figures(model::make_member_model(s));
  const double K = 3.0e7, EI = 4.5e6, L = 2.6, beta = std::pow(K / (4 * EI), 0.25);
  CHECK(f.K_max == Approx(K).epsilon(round_off));
  CHECK(f.k_max == Approx(K * std::pow(L, 4) / EI).epsilon(round_off));
  CHECK(f.beta_max == Approx(beta).epsilon(round_off));
  CHECK(f.beta_length_max == Approx(beta * L).epsilon(round_off));
  CHECK(f.characteristic_length() == Approx(1 / beta).epsilon(round_off));
  CHECK(f.beta_max == Approx(1.136).epsilon(1e-3));  // the scene's hand calculation: 1.136 1/m
  CHECK_FALSE(f.varies());
  CHECK(f.beta_h < 0);  // no mesh given
}

TEST_CASE("scale: an arch's figures are beta R = (k/4)^(1/4) and beta S over its length", "[post][scale]") {
  const scene::Scene s = test::shipped_scene("seed_arch_pinned");  // R = 100, gamma = 10 deg, k = 1e6
  const post::ScaleFigures f = post::scale_figures(model::make_member_model(s));
  const double beta_R = std::pow(1e6 / 4, 0.25), gamma = 10 * M_PI / 180;
  CHECK(f.arch);
  CHECK(f.beta_radius_max == Approx(beta_R).epsilon(round_off));
  CHECK(f.beta_max == Approx(beta_R / 100).epsilon(round_off));
  CHECK(f.beta_length_max == Approx(beta_R * 2 * gamma).epsilon(round_off));
  CHECK(f.member_length == Approx(2 * gamma * 100).epsilon(round_off));
  CHECK(f.K_max == Approx(1e6 * 1.4 / 1e8).epsilon(round_off));  // K = k EI / R^4
}

TEST_CASE("scale: segments give the least and the largest of every figure", "[post][scale]") {
  const scene::Scene s = sleeper(
      "\n[[foundation.segments]]\nfrom = 0.0\nto = 1.0\nmodulus = 2.0e7\n"
      "\n[[foundation.segments]]\nfrom = 1.0\nto = 2.6\nmodulus = [3.0e7, 8.0e7]\n");
  const post::ScaleFigures f = post::scale_figures(model::make_member_model(s));
  CHECK(f.varies());
  CHECK(f.K_min == Approx(2.0e7).epsilon(round_off));
  CHECK(f.K_max == Approx(8.0e7).epsilon(round_off));
  CHECK(f.beta_min == Approx(std::pow(2.0e7 / (4 * 4.5e6), 0.25)).epsilon(round_off));
  CHECK(f.beta_max == Approx(std::pow(8.0e7 / (4 * 4.5e6), 0.25)).epsilon(round_off));
}

TEST_CASE("scale: k = 2.5e7 meant as N/m^2 on a sleeper is named as the likely mistake", "[post][scale][warnings]") {
  // The trap: read as K L^4/EI it gives beta L = 50 (two tiny contact patches); read as
  // K = 2.5e7 N/m^2 it gives K L^4/EI = 254 and beta L = 2.82 (full contact).
  const auto trap = warnings_of(sleeper("nondimensional_k = 2.5e7"));
  REQUIRE(trap.size() == 1);
  CHECK_THAT(trap[0], Contains("nondimensional_k = 2.5e+07 (K L^4/EI) gives beta L = 50") &&
                          Contains("write modulus = 2.5e+07 instead (that gives K L^4/EI = 254 and beta L = 2.82)"));
  // With [units] the modulus it implies, 2.5e12 N/m^2, is also beyond any real bed.
  const auto with_units = warnings_of(sleeper("nondimensional_k = 2.5e7", "\n[units]\nsystem = \"N-m\"\n"));
  REQUIRE(with_units.size() == 2);
  CHECK_THAT(with_units[0], Contains("(N/m^2), write modulus = 2.5e+07 instead"));
  CHECK_THAT(with_units[1], Contains("K = 2.46e+12 N/m^2 is outside the moduli of real beds"));
  // The controls: the same number as the modulus, and a nondimensional k of the same beam that a
  // dimensional reading would make no more plausible, say nothing.
  CHECK(warnings_of(sleeper("modulus = 2.5e7", "\n[units]\nsystem = \"N-m\"\n")).empty());
  CHECK(warnings_of(sleeper("nondimensional_k = 254.0")).empty());
  // A nondimensional k on a member whose l^4/EI is 1 reads the same either way: no warning.
  CHECK(warnings_of(
            scene::parse_scene("[structure]\nkind = \"beam\"\nlength = 1.0\nEI = 1.0\n[supports]\nleft = \"pinned\"\n"
                               "right = \"pinned\"\n[foundation]\nnondimensional_k = 1e8\n",
                               "unit.toml"))
            .empty());
}

TEST_CASE("scale: a modulus that reads like a nondimensional k, and a practically rigid member",
          "[post][scale][warnings]") {
  // modulus = 30 on the sleeper: K L^4/EI = 3e-4, beta L = 0.0934; as nondimensional_k beta L = 1.65.
  const auto w = warnings_of(sleeper("modulus = 30.0"));
  REQUIRE(w.size() == 2);
  CHECK_THAT(w[0], Contains("modulus = 30 (force per length per length) gives K L^4/EI = 0.000305 and beta L = "
                            "0.0934; if 30 is the nondimensional K L^4/EI, write nondimensional_k = 30 instead"));
  CHECK_THAT(w[1], Contains("beta L = 0.0934 < 0.1: the member is practically rigid"));
}

TEST_CASE("scale: a mesh that does not resolve 1/beta is named, with the elements it needs",
          "[post][scale][warnings]") {
  // beta L = (k/4)^(1/4) = 10 on a beam with l^4/EI = 1: 5 elements give beta h = 2, 20 give 0.5.
  const scene::Scene s = scene::parse_scene(
      "[structure]\nkind = \"beam\"\nlength = 1.0\nEI = 1.0\n[supports]\nleft = \"pinned\"\n"
      "right = \"pinned\"\n[foundation]\nnondimensional_k = 4e4\n",
      "unit.toml");
  const post::ScaleFigures f = post::scale_figures(model::make_member_model(s), {0.0, 0.2, 0.4, 0.6, 0.8, 1.0});
  CHECK(f.beta_h == Approx(2.0).epsilon(round_off));
  CHECK(f.element_size == Approx(0.2).epsilon(round_off));
  const auto coarse = warnings_of(s, 5);
  REQUIRE(coarse.size() == 1);
  CHECK_THAT(coarse[0], Contains("beta h = 2 > 1") && Contains("use at least 10 elements"));
  CHECK(warnings_of(s, 20).empty());
}

TEST_CASE("scale: the shipped scenes warn of nothing", "[post][scale][warnings]") {
  // Every scene shipped in verification/scenes (the seed's and the engineering corpus): the new
  // key names (no reader warning) and sensible scales, on the scene's own element count.
  int scenes = 0;
  for (const auto& entry :
       std::filesystem::recursive_directory_iterator(std::string(LIFTOFF_SOURCE_DIR) + "/verification/scenes")) {
    if (entry.path().extension() != ".toml") continue;
    const scene::Scene s = scene::read_scene_file(entry.path());
    INFO(entry.path());
    CHECK(s.warnings.empty());
    CHECK(warnings_of(s, s.solve.elements).empty());
    ++scenes;
  }
  CHECK(scenes >= 20);
  // The load paths' scenes too (continuation/scenes).
  for (const auto& entry :
       std::filesystem::recursive_directory_iterator(std::string(LIFTOFF_SOURCE_DIR) + "/continuation/scenes")) {
    if (entry.path().extension() != ".toml") continue;
    const scene::Scene s = scene::read_scene_file(entry.path());
    INFO(entry.path());
    CHECK(warnings_of(s, s.solve.elements).empty());
  }
}

namespace {

// A strip footing in kN and m (verification/scenes/engineering/footing_eccentric_column.toml's
// section, 0.6 m thick, K = 3e4 kN/m^2) of length L, with `structure` lines after its EI line.
scene::Scene footing_kn(double length, const std::string& EI, const std::string& modulus,
                        const std::string& structure = "") {
  return scene::parse_scene("[structure]\nkind = \"beam\"\nlength = " + std::to_string(length) + "\nEI = " + EI + "\n" +
                                structure +
                                "[supports]\nleft = \"free\"\nright = \"free\"\n[foundation]\nmodulus = " + modulus +
                                "\n[[loads]]\nkind = \"force\"\nat = 0.5\nvalue = 800.0\n[units]\nsystem = \"kN-m\"\n",
                            "footing.toml");
}

}  // namespace

// How many of the warnings contain `text`.
long warned(const std::vector<std::string>& warnings, const std::string& text) {
  return std::count_if(warnings.begin(), warnings.end(),
                       [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

TEST_CASE("scale: EI in N m^2 in a kN-m scene is named where it makes the member rigid", "[post][scale][warnings]") {
  // L = 1.5 m: beta L = (3e4 / (4 x 5.4e5))^(1/4) x 1.5 = 0.515 with EI in kN m^2; the same
  // number in N m^2 (5.4e8 read as kN m^2) is 1000x stiffer, beta L = 0.515 / 1000^(1/4) = 0.0916.
  const auto slip = warnings_of(footing_kn(1.5, "5.4e8", "3.0e4"));
  INFO(slip.size());
  CHECK(warned(slip,
               "footing.toml: key 'structure.EI': EI = 5.4e+08 looks like N m^2 in a kN-m scene: 1000x (as "
               "5.4e+05 kN m^2 it gives beta L = 0.515)") == 1);
  CHECK(warned(slip, "beta L = 0.0916 < 0.1: the member is practically rigid") == 1);
  CHECK(warnings_of(footing_kn(1.5, "5.4e5", "3.0e4")).empty());  // the control
  // Written with its unit, EI is what the user said: rigid, but no slip of EI suspected.
  const auto stated = warnings_of(footing_kn(1.5, "\"5.4e11 N m^2\"", "3.0e4"));
  CHECK(warned(stated, "practically rigid") == 1);
  CHECK(warned(stated, "key 'structure.EI'") == 0);
}

TEST_CASE("scale: a modulus in MN/m^2 in a kN-m scene is named where it makes the member rigid",
          "[post][scale][warnings]") {
  // modulus = 30 meant as MN/m^2: K 1000x too soft, beta L = 0.515 / 1000^(1/4) = 0.0916.
  const auto slip = warnings_of(footing_kn(1.5, "5.4e5", "30.0"));
  CHECK(warned(slip,
               "footing.toml: key 'foundation.modulus': modulus = 30 looks like MN/m^2 in a kN-m scene: "
               "1000x (as 3e+04 kN/m^2 it gives beta L = 0.515)") == 1);
  // With both written with their units, neither is suspected.
  CHECK(warned(warnings_of(footing_kn(1.5, "\"5.4e5 kN m^2\"", "\"30 MN/m^2\"")), "looks like") == 0);
}

TEST_CASE("scale: EI or EA a factor 1000 off makes a radius of gyration no section has", "[post][scale][warnings]") {
  // EA = 30e9 x 0.6 = 1.8e7 kN: r = sqrt(EI/EA) = 0.173 m (0.6 / sqrt(12)) with EI in kN m^2;
  // EI in N m^2 gives 5.48 m on a 3 m footing, and so would EA in MN: each plain key is named.
  CHECK(warnings_of(footing_kn(3.0, "5.4e5", "3.0e4", "EA = 1.8e7\n")).empty());
  const auto ei = warnings_of(footing_kn(3.0, "5.4e8", "3.0e4", "EA = 1.8e7\n"));
  CHECK(warned(ei,
               "footing.toml: key 'structure.EI': the radius of gyration sqrt(EI/EA) = 5.48 m is more than "
               "L/4 = 0.75 m: no section is that deep; EI = 5.4e+08 looks like N m^2 in a kN-m scene: 1000x (as "
               "5.4e+05 kN m^2 it gives 0.173 m)") == 1);
  // EI stated with its unit: only EA can hold the slip.
  const auto ea = warnings_of(footing_kn(3.0, "\"5.4e5 kN m^2\"", "3.0e4", "EA = 1.8e4\n"));
  REQUIRE(ea.size() == 1);
  CHECK_THAT(ea[0], Contains("footing.toml: key 'structure.EA': the radius of gyration sqrt(EI/EA) = 5.48 m") &&
                        Contains("EA = 1.8e+04 looks like MN in a kN-m scene: 1000x (as 1.8e+07 kN it gives 0.173 m)"));
}
