#include "app/trace_load.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace liftoff::app {

namespace {

// The physical quantities a live load can be, each with what the kinds of scene::Load make of it.
enum class Quantity { force, moment, distributed, axial, temperature, curvature };

Quantity quantity_of(scene::LoadKind kind) {
  switch (kind) {
    case scene::LoadKind::force:
      return Quantity::force;
    case scene::LoadKind::moment:
      return Quantity::moment;
    case scene::LoadKind::uniform:
    case scene::LoadKind::distributed:
    case scene::LoadKind::sine:
      return Quantity::distributed;
    case scene::LoadKind::axial:
      return Quantity::axial;
    case scene::LoadKind::temperature:
      return Quantity::temperature;
    case scene::LoadKind::curvature:
      return Quantity::curvature;
  }
  return Quantity::force;
}

struct QuantityName {
  const char* quantity;  // PhysicalLoad::quantity
  const char* plural;    // for messages: "point forces"
  const char* symbol;
};
QuantityName name_of(Quantity q) {
  switch (q) {
    case Quantity::force:
      return {"point force", "point forces", "P"};
    case Quantity::moment:
      return {"moment", "moments", "M"};
    case Quantity::distributed:
      return {"distributed force", "distributed forces", "q"};
    case Quantity::axial:
      return {"axial force", "axial forces", "N"};
    case Quantity::temperature:
      return {"temperature rise", "temperature rises", "dT"};
    case Quantity::curvature:
      return {"imposed curvature", "imposed curvatures", "kappa"};
  }
  return {"", "", ""};
}

std::string unit_of(Quantity q, const scene::Units& units) {
  switch (q) {
    case Quantity::force:
    case Quantity::axial:
      return units.force;
    case Quantity::moment:
      return units.moment();
    case Quantity::distributed:
      return units.distributed_force();
    case Quantity::temperature:
      return "deg";
    case Quantity::curvature:
      return units.inverse_length();
  }
  return "";
}

// A load's size as its quantity measures it: its value, a table's largest |value|.
double size_of(const scene::Load& load) {
  if (load.kind != scene::LoadKind::distributed || load.table_value.empty()) return load.value;
  return *std::max_element(load.table_value.begin(), load.table_value.end(),
                           [](double a, double b) { return std::abs(a) < std::abs(b); });
}

std::string loads_list(const std::vector<std::size_t>& indices) {
  std::string out;
  for (std::size_t i : indices) out += fmt::format("{}loads[{}]", out.empty() ? "" : ", ", i);
  return out;
}

}  // namespace

LiveLoad live_load(const scene::Scene& scene) {
  std::vector<std::size_t> live;
  for (std::size_t i = 0; i < scene.loads.size(); ++i)
    if (scene.loads[i].load_case == scene::LoadCase::live) live.push_back(i);
  if (live.empty()) return {std::nullopt, "the scene has no live load"};
  const Quantity quantity = quantity_of(scene.loads[live.front()].kind);
  for (std::size_t i : live)
    if (const Quantity other = quantity_of(scene.loads[i].kind); other != quantity)
      return {std::nullopt,
              fmt::format("the live case mixes {} and {}", name_of(quantity).plural, name_of(other).plural)};
  const QuantityName name = name_of(quantity);
  continuation::PhysicalLoad load;
  load.quantity = name.quantity;
  load.symbol = name.symbol;
  load.unit = unit_of(quantity, scene.units);
  const bool summed = quantity == Quantity::axial || quantity == Quantity::temperature;
  if (summed) {
    for (std::size_t i : live) {
      if (scene.loads[i].alpha != scene.loads[live.front()].alpha)
        return {std::nullopt, fmt::format("the live temperature rises have different alphas ({})", loads_list(live))};
      load.reference += scene.loads[i].value;
    }
    load.definition = live.size() == 1
                          ? fmt::format("the live {} ({})", name.quantity, loads_list(live))
                          : fmt::format("the sum of the {} live {} ({})", live.size(), name.plural, loads_list(live));
  } else {
    std::size_t largest = live.front();
    for (std::size_t i : live)
      if (std::abs(size_of(scene.loads[i])) > std::abs(size_of(scene.loads[largest]))) largest = i;
    load.reference = size_of(scene.loads[largest]);
    load.definition = live.size() == 1
                          ? fmt::format("the live {} ({})", name.quantity, loads_list(live))
                          : fmt::format("the largest of the {} live {} (loads[{}]; the others keep their ratio to it)",
                                        live.size(), name.plural, largest);
  }
  if (!(load.reference != 0.0 && std::isfinite(load.reference)))
    return {std::nullopt, fmt::format("the live {} is zero", name.plural)};
  return {std::move(load), ""};
}

std::vector<double> report_at_load_factors(const std::vector<double>& values,
                                           const std::optional<continuation::PhysicalLoad>& load, double lambda_min,
                                           double lambda_max, const std::function<std::string(std::size_t)>& where) {
  const double lo = std::min(lambda_min, lambda_max), hi = std::max(lambda_min, lambda_max);
  const double snap = 1e-12 * std::max({hi - lo, std::abs(lo), std::abs(hi)});
  std::vector<double> lambdas;
  for (std::size_t i = 0; i < values.size(); ++i) {
    double lambda = load ? values[i] / load->reference : values[i];
    if (std::abs(lambda - lo) <= snap) lambda = lo;
    if (std::abs(lambda - hi) <= snap) lambda = hi;
    if (!(std::isfinite(lambda) && lambda >= lo && lambda <= hi)) {
      const std::string unit = load && !load->unit.empty() ? " " + load->unit : "";
      const double a = load ? load->at(lo) : lo, b = load ? load->at(hi) : hi;
      throw InputError(
          load ? fmt::format("{}: expected {} {} {} in [{:g}, {:g}]{} (lambda in [{:g}, {:g}] x {}, {:g}{}), got {:g}",
                             where(i), std::string("aeiou").find(load->quantity[0]) != std::string::npos ? "an" : "a",
                             load->quantity, load->symbol, std::min(a, b), std::max(a, b), unit, lo, hi,
                             load->definition, load->reference, unit, values[i])
               : fmt::format("{}: expected a load factor in [{:g}, {:g}] ([trace] lambda_min, lambda_max), got {:g}",
                             where(i), lo, hi, values[i]));
    }
    lambdas.push_back(lambda);
  }
  return lambdas;
}

std::string load_text(const std::optional<continuation::PhysicalLoad>& load, double lambda) {
  if (!load) return fmt::format("lambda {:.8g}", lambda);
  return fmt::format("{} = {:.6g}{}", load->symbol, load->at(lambda), load->unit.empty() ? "" : " " + load->unit);
}

}  // namespace liftoff::app
