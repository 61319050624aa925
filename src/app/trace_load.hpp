#pragma once
// The live load of `liftoff trace` as a physical quantity, and the loads at which the user wants
// the state ([trace] report_at, --at) as load factors. A property of the scene, derived here once
// and handed down in continuation::TraceOptions (nothing below app/ sees the scene).
//
// Where every live load is of one kind, `load` = lambda x reference, in the scene's units
// (scene::unit_labels):
//   point forces (kind "force")        P, force: the live force of largest magnitude (the first of
//                                      equal ones). Two wheel forces of 100 kN: P = lambda x 100 kN,
//                                      the force of each wheel; unequal forces keep their ratio to it.
//   moments ("moment")                 M, moment: likewise the largest.
//   distributed forces ("uniform",     q, force per length: the largest intensity among them (a
//   "distributed", "sine")             uniform load's value, a table's largest |value|, a sine's
//                                      amplitude); they scale together.
//   axial forces ("axial")             N, force: their sum, the compressive force along the member.
//   temperature rises ("temperature")  dT, "deg" (the degrees alpha is given per): their sum, when
//                                      they share one alpha (their forces EA alpha dT add).
//   imposed curvatures ("curvature")   kappa, 1/length: the largest.
// An arch's loads count by kind whatever their direction. A live case that mixes kinds (a force
// and a distributed load; an axial force and a temperature rise), temperature rises with
// different alphas, no live load, or a reference of zero: no physical load, lambda only; `why`
// says which.
//
// report_at values are physical loads in that unit where there is one (what an engineer types:
// "the state at 5 MN"), load factors otherwise.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "continuation/result.hpp"
#include "scene/scene.hpp"

namespace liftoff::app {

struct LiveLoad {
  std::optional<continuation::PhysicalLoad> load;
  std::string why_none;  // in words, when there is no load: "the live case mixes point forces and moments"
};
LiveLoad live_load(const scene::Scene& scene);

// The load factors of `values` (physical loads where `load` is given, else load factors), each
// checked in [lambda_min, lambda_max] (a value that rounds past an end by 1e-12 of the range is
// taken as that end). Throws InputError "<where(i)>: expected ..., got ..." for one outside.
std::vector<double> report_at_load_factors(const std::vector<double>& values,
                                           const std::optional<continuation::PhysicalLoad>& load, double lambda_min,
                                           double lambda_max, const std::function<std::string(std::size_t)>& where);

// "N = 5.8449e+06 N" (the load at lambda), or "lambda 5.8449" without a physical load.
std::string load_text(const std::optional<continuation::PhysicalLoad>& load, double lambda);

}  // namespace liftoff::app
