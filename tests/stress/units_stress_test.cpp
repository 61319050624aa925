// Stress: the same beam written in kN and m and in N and mm gives the same nondimensional
// results (deflections / L, contact limits / L, reactions / (EI / L^3)) from every method, to
// round-off. The two scenes differ in their numbers by factors up to 1e13, so only the
// nondimensionalisation (model::MemberModel) makes them the same problem.
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>

#include "answer_check.hpp"
#include "app/solve_command.hpp"
#include "model/from_scene.hpp"
#include "support/scenes.hpp"
#include "support/solve.hpp"

using namespace liftoff;
using scene::Method;

namespace {

// A simply supported beam under sagging end moments and a central upward force (the second
// seed beam's loading, with values that are not powers of ten): L = 6.3 m, EI = 2.37e4 kN m^2,
// k = K L^4 / EI = 1e4; M = 0.8 EI / L, P = 1.3 EI / L^2. `length_unit` and `force_unit`
// convert from m and kN into the scene's units (1 and 1, or 1e3 and 1e3 for N and mm).
scene::Scene beam_in_units(double length_unit, double force_unit) {
  const double L = 6.3, EI = 2.37e4, k = 1e4;
  const double M = 0.8 * EI / L, P = 1.3 * EI / (L * L);
  scene::Scene s = test::beam_scene(L * length_unit, EI * force_unit * length_unit * length_unit,
                                    scene::EndSupport::pinned, scene::EndSupport::pinned, 0.0);
  s.source_name = length_unit == 1.0 ? "<beam in kN and m>" : "<beam in N and mm>";
  s.foundation.k.reset();
  s.foundation.modulus = k * EI / std::pow(L, 4) * force_unit / (length_unit * length_unit);  // kN/m^2
  s.loads = {test::point_moment(0.0, -M * force_unit * length_unit),
             test::point_moment(L * length_unit, M * force_unit * length_unit),
             test::point_force(0.5 * L * length_unit, -P * force_unit)};
  return s;
}

struct Nondimensional {
  std::vector<double> limits;  // / L
  double w_max = 0, w_min = 0, max_reaction = 0;
};

Nondimensional nondimensional(const io::SolveReport& r, const scene::Scene& s) {
  const double L = s.structure.length, EI = s.structure.bending_stiffness;
  Nondimensional n;
  for (const auto& region : r.contact_regions)
    for (double limit : {region.begin, region.end}) n.limits.push_back(limit / L);
  n.w_max = r.w_max / L;
  n.w_min = r.w_min / L;
  n.max_reaction = r.max_reaction / (EI / (L * L * L));
  return n;
}

double relative(double a, double b) { return std::abs(a - b) / std::max({std::abs(a), std::abs(b), 1e-300}); }

}  // namespace

TEST_CASE("stress: the same scene in kN-m and in N-mm gives the same nondimensional results", "[stress][units]") {
  const scene::Scene metres = beam_in_units(1.0, 1.0), millimetres = beam_in_units(1e3, 1e3);

  // How different the two problems are once nondimensional: each input was rounded on the way
  // (K L^4 / EI, M L / EI, P L^2 / EI in two unit systems), a few eps at most.
  const model::MemberModel a = model::make_member_model(metres), b = model::make_member_model(millimetres);
  double data_difference = relative(a.k, b.k);
  REQUIRE(a.loads.size() == b.loads.size());
  for (std::size_t i = 0; i < a.loads.size(); ++i)
    data_difference = std::max(
        {data_difference, relative(a.loads[i].value, b.loads[i].value), std::abs(a.loads[i].at - b.loads[i].at)});
  std::printf("units: nondimensional data differ by %.1e\n", data_difference);
  CHECK(data_difference <= 8 * test::eps);

  std::vector<Method> methods;  // the scene's names of the FE methods, then ritz
  for (contact::Method fe : test::fe_methods()) methods.push_back(*scene::parse_method(contact::to_string(fe)));
  methods.push_back(Method::ritz);
  for (Method method : methods) {
    app::SolveRequest request;
    request.method = method;
    request.elements = 80;
    const io::SolveReport ra = app::solve_scene(metres, request), rb = app::solve_scene(millimetres, request);
    CAPTURE(scene::to_string(method), ra.message, rb.message);
    REQUIRE(ra.usable);
    REQUIRE(rb.usable);
    const Nondimensional na = nondimensional(ra, metres), nb = nondimensional(rb, millimetres);

    // Round-off in the data (data_difference, an ulp or two) moves every result by the
    // solver's sensitivity to ulp-sized changes of its input, which mixes the condition of the
    // result with how the rounding of the whole computation reacts. Measured, not guessed: the
    // same scene (kN-m) with k and the loads moved by +-1 to +-8 ulps; the spread of those
    // answers is the noise floor, and the N-mm scene must fall within 4 times it.
    std::vector<Nondimensional> nearby;
    for (double ulps : {-8.0, -4.0, -2.0, -1.0, 1.0, 2.0, 4.0, 8.0}) {
      scene::Scene moved = metres;
      *moved.foundation.modulus *= 1.0 + ulps * test::eps;
      for (auto& load : moved.loads) load.value *= 1.0 - ulps * test::eps;
      const io::SolveReport r = app::solve_scene(moved, request);
      REQUIRE(r.usable);
      nearby.push_back(nondimensional(r, moved));
      REQUIRE(nearby.back().limits.size() == na.limits.size());
    }
    auto tolerance = [&](auto value_of) {
      double noise = test::eps * std::abs(value_of(na));
      for (const Nondimensional& n : nearby) noise = std::max(noise, std::abs(value_of(n) - value_of(na)));
      return 4.0 * noise;
    };

    REQUIRE(na.limits.size() == nb.limits.size());
    double worst_ratio = 0.0;
    auto compare = [&](const char* name, auto value_of) {
      const double tol = tolerance(value_of), difference = std::abs(value_of(na) - value_of(nb));
      CAPTURE(name, value_of(na), value_of(nb), tol);
      CHECK(difference <= tol);
      worst_ratio = std::max(worst_ratio, difference / tol);
      if (std::getenv("LIFTOFF_STRESS_VERBOSE"))
        std::printf("    %s: %.17g vs %.17g, tolerance %.1e\n", name, value_of(na), value_of(nb), tol);
    };
    for (std::size_t i = 0; i < na.limits.size(); ++i)
      compare("limit", [i](const Nondimensional& n) { return n.limits[i]; });
    compare("w_max", [](const Nondimensional& n) { return n.w_max; });
    compare("w_min", [](const Nondimensional& n) { return n.w_min; });
    compare("max_reaction", [](const Nondimensional& n) { return n.max_reaction; });
    std::printf("units, %-6s: limits/L %s; w_max/L %.15e vs %.15e; worst difference %.2f of its noise tolerance\n",
                scene::to_string(method).data(), fmt::format("{}", fmt::join(na.limits, ", ")).c_str(), na.w_max,
                nb.w_max, worst_ratio);
  }
}
