#include "app/envelope_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/error.hpp"

namespace liftoff::app {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

// A field of one case at x: linear between the samples around it (the samples are ascending; at a
// node two samples share a coordinate, and x there takes the right-hand one).
double interpolate(const std::vector<double>& coordinate, const std::vector<double>& values, double x) {
  const auto upper = std::upper_bound(coordinate.begin(), coordinate.end(), x);
  if (upper == coordinate.begin()) return values.front();
  if (upper == coordinate.end()) return values.back();
  const std::size_t j = upper - coordinate.begin(), i = j - 1;
  const double t = (x - coordinate[i]) / (coordinate[j] - coordinate[i]);
  return values[i] + t * (values[j] - values[i]);
}

// The case's extreme of `values` (largest of sign * value), against the envelope's so far.
void take_extreme(io::Extreme& extreme, const std::vector<double>& coordinate, const std::vector<double>& values,
                  double sign, int case_index) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double v = sign * values[i];
    if (extreme.governing < 0 || v > sign * extreme.value) {
      extreme.value = v * sign;
      extreme.at = coordinate[i];
      extreme.governing = case_index;
    }
  }
}

}  // namespace

void EnvelopeRequest::validate() const {
  if (samples < 2) throw std::invalid_argument("EnvelopeRequest::samples must be at least 2");
}

scene::Scene case_scene(const scene::Scene& scene, const scene::Combination* combination, std::optional<double> lead) {
  scene::Scene one = scene;
  one.loads.clear();
  one.combinations.clear();
  one.moving.reset();
  const auto add = [&](scene::Load load, double factor) {
    if (factor == 0.0) return;  // not in this combination
    load.value *= factor;
    for (double& v : load.table_value) v *= factor;
    one.loads.push_back(std::move(load));
  };
  for (const scene::Load& load : scene.loads) add(load, combination ? combination->factor_of(load.case_name) : 1.0);
  if (scene.moving && lead) {
    const double factor = combination ? combination->factor_of(scene.moving->case_name) : 1.0;
    for (scene::Load load : scene.moving->group) {
      // The reader keeps the group on the member; the clamp only removes the sum's round-off.
      load.at = std::clamp(*lead + load.at, scene.begin(), scene.end());
      add(load, factor);
    }
  }
  return one;
}

io::EnvelopeReport run_envelope(const scene::Scene& scene, const EnvelopeRequest& request,
                                const std::function<void(int, int)>& progress) {
  request.validate();
  if (scene.combinations.empty() && !scene.moving)
    throw InputError(
        fmt::format("{}: key 'combinations': missing (expected [[combinations]] or a [moving] table: "
                    "`liftoff envelope` has nothing to envelope)",
                    scene.source_name));
  io::EnvelopeReport out;
  out.scene_name = scene.source_name;
  out.units = scene.units;
  out.scene_text = scene.text;
  out.coordinate_name = scene.structure.kind == scene::StructureKind::beam ? "x" : "theta_deg";
  out.tensionless = scene.foundation.tensionless;
  out.warm_start = request.warm_start;

  std::vector<const scene::Combination*> combinations;
  for (const scene::Combination& c : scene.combinations) combinations.push_back(&c);
  if (combinations.empty()) combinations.push_back(nullptr);
  std::vector<std::optional<double>> positions;
  if (scene.moving)
    for (double p : scene.moving->positions) positions.emplace_back(p);
  else
    positions.emplace_back(std::nullopt);

  const int total = static_cast<int>(combinations.size() * positions.size());
  for (const scene::Combination* combination : combinations) {
    std::optional<std::vector<ContactRegion>> previous;  // the last position's contact regions
    for (const std::optional<double>& lead : positions) {
      io::EnvelopeCase c;
      c.combination = combination ? combination->name : "";
      c.position = lead;
      SolveRequest solve = request.solve;
      solve.fields = true;
      if (request.warm_start && previous) {
        solve.initial_contact_regions = previous;
        c.warm_started = true;
      }
      const scene::Scene one = case_scene(scene, combination, lead);
      try {
        c.report = solve_scene(one, solve);
      } catch (const SolverFailure& e) {
        c.error = e.what();
      } catch (const MechanismError& e) {  // this position or combination drives a mechanism
        c.error = e.what();
      }
      previous.reset();
      if (c.passed()) previous = c.report.contact_regions;
      out.cases.push_back(std::move(c));
      if (progress) progress(static_cast<int>(out.cases.size()), total);
    }
  }

  // The envelopes on a uniform grid, and the extremes from each case's own samples.
  const int n = request.samples;
  out.coordinate.resize(n);
  for (int i = 0; i < n; ++i)
    out.coordinate[i] = i + 1 == n ? scene.end() : scene.begin() + (scene.end() - scene.begin()) * i / (n - 1);
  for (auto* v : {&out.w_max, &out.pressure_max, &out.moment_max, &out.shear_max}) v->assign(n, -inf);
  for (auto* v : {&out.w_min, &out.pressure_min, &out.moment_min, &out.shear_min}) v->assign(n, inf);
  for (int k = 0; k < static_cast<int>(out.cases.size()); ++k) {
    const io::EnvelopeCase& c = out.cases[k];
    const io::FieldTable& f = c.report.fields;
    if (!c.passed() || f.coordinate.size() < 2) continue;
    const auto envelope = [&](const std::vector<double>& values, std::vector<double>& high, std::vector<double>& low) {
      for (int i = 0; i < n; ++i) {
        const double v = interpolate(f.coordinate, values, out.coordinate[i]);
        high[i] = std::max(high[i], v);
        low[i] = std::min(low[i], v);
      }
    };
    envelope(f.w, out.w_max, out.w_min);
    envelope(f.reaction, out.pressure_max, out.pressure_min);
    envelope(f.bending_moment, out.moment_max, out.moment_min);
    envelope(f.shear_force, out.shear_max, out.shear_min);
    take_extreme(out.design.moment_max, f.coordinate, f.bending_moment, 1.0, k);
    take_extreme(out.design.moment_min, f.coordinate, f.bending_moment, -1.0, k);
    take_extreme(out.design.pressure_max, f.coordinate, f.reaction, 1.0, k);
    take_extreme(out.design.w_max, f.coordinate, f.w, 1.0, k);
    take_extreme(out.design.uplift_max, f.coordinate, f.w, -1.0, k);
    for (std::size_t i = 0; i < f.shear_force.size(); ++i) {
      if (out.design.shear_max_abs.governing < 0 ||
          std::abs(f.shear_force[i]) > std::abs(out.design.shear_max_abs.value)) {
        out.design.shear_max_abs = {f.shear_force[i], f.coordinate[i], k};
      }
    }
  }
  // uplift is -w: take_extreme kept the most negative w; the uplift is its opposite.
  out.design.uplift_max.value = -out.design.uplift_max.value;
  // No certified case: the envelopes are empty rather than infinite.
  if (out.design.moment_max.governing < 0)
    for (auto* v : {&out.w_max, &out.w_min, &out.pressure_max, &out.pressure_min, &out.moment_max, &out.moment_min,
                    &out.shear_max, &out.shear_min})
      v->clear();
  if (out.design.moment_max.governing < 0) out.coordinate.clear();
  return out;
}

}  // namespace liftoff::app
