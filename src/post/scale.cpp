#include "post/scale.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace liftoff::post {
namespace {

// beta l = (k/4)^(1/4): the decay rate per unit of the member coordinate s (x/L, or theta).
double beta_s(double k) { return std::pow(k / 4.0, 0.25); }

std::string g(double x) { return fmt::format("{:.3g}", x); }

std::string with_unit(const std::string& label) { return label.empty() ? std::string() : " " + label; }

}  // namespace

ScaleFigures scale_figures(const model::MemberModel& model, const std::vector<double>& mesh_nodes) {
  ScaleFigures f;
  f.arch = model.kind == model::StructureKind::arch;
  const double l = model.scales.length, EI = model.scales.bending_stiffness, span = model.length();
  f.length_scale = l;
  f.member_length = span * l;
  f.k_min = std::numeric_limits<double>::infinity();
  for (const model::FoundationPiece& piece : model.pieces()) {
    for (const double k : {piece.k, piece.end_k.value_or(piece.k)}) {
      f.k_min = std::min(f.k_min, k);
      f.k_max = std::max(f.k_max, k);
    }
  }
  if (!(f.k_min <= f.k_max)) f.k_min = f.k_max;  // no foundation piece (a model built in code)
  const double modulus_scale = EI / std::pow(l, 4);
  f.K_min = f.k_min * modulus_scale;
  f.K_max = f.k_max * modulus_scale;
  f.beta_min = beta_s(f.k_min) / l;
  f.beta_max = beta_s(f.k_max) / l;
  f.beta_length_min = beta_s(f.k_min) * span;
  f.beta_length_max = beta_s(f.k_max) * span;
  if (f.arch) {
    f.beta_radius_min = beta_s(f.k_min);
    f.beta_radius_max = beta_s(f.k_max);
  }
  if (mesh_nodes.size() >= 2) {
    f.elements = static_cast<int>(mesh_nodes.size()) - 1;
    for (std::size_t e = 0; e + 1 < mesh_nodes.size(); ++e) {
      const double a = mesh_nodes[e], b = mesh_nodes[e + 1];
      const auto [k_a, k_b] = model.k_on(a, b);
      const double k = std::max(k_a, k_b);
      if (!(k > 0.0)) continue;  // no foundation under this element
      if (const double bh = beta_s(k) * (b - a); bh > f.beta_h) {
        f.beta_h = bh;
        f.element_size = (b - a) * l;
      }
    }
  }
  return f;
}

std::vector<std::string> scale_warnings(const scene::Scene& scene, const model::MemberModel& model,
                                        const ScaleFigures& f) {
  std::vector<std::string> out;
  const scene::Units& units = scene.units;
  const double l = model.scales.length, span = model.length();
  const double l4_over_EI = std::pow(l, 4) / model.scales.bending_stiffness;
  const char* member = f.arch ? "S" : "L";
  const char* k_name = f.arch ? "K R^4/EI" : "K L^4/EI";
  const std::string modulus_unit = units.stated() ? units.modulus() : "force per length per length";
  const std::string length_unit = with_unit(units.length);

  // The moduli as the user gave them: nondimensional (nondimensional_k) or dimensional (modulus).
  std::vector<double> nondimensional, dimensional;
  const scene::Foundation& foundation = scene.foundation;
  std::vector<scene::FoundationSegment> pieces = foundation.segments;
  if (pieces.empty()) pieces.push_back({foundation.from, foundation.to, foundation.k, foundation.modulus});
  for (const scene::FoundationSegment& piece : pieces) {
    std::vector<double>& given = piece.k ? nondimensional : dimensional;
    const std::optional<double> value = piece.k ? piece.k : piece.modulus;
    if (value) given.push_back(*value);
    if (piece.at_to) given.push_back(*piece.at_to);
  }
  const auto beta_length = [&](double k) { return beta_s(k) * span; };
  const auto plausible = [](double beta_l) { return beta_l >= rigid_beta_length && beta_l <= long_beta_length; };

  // A nondimensional k that reads like a dimensional K: k = 2.5e7 meant as N/m^2 on a 2.6 m sleeper
  // gives beta L = 50 (two tiny contact patches) where the K it meant gives 2.8 (full contact).
  if (!nondimensional.empty()) {
    const double x = *std::max_element(nondimensional.begin(), nondimensional.end());
    const double given = beta_length(x), meant = beta_length(x * l4_over_EI);
    if (given > long_beta_length && plausible(meant))
      out.push_back(fmt::format(
          "foundation: nondimensional_k = {} ({}) gives beta {} = {} (1/beta = {}{}: the member is {} decay lengths "
          "long and carries each load on a short stretch of foundation); if {} is the foundation modulus K ({}), "
          "write modulus = {} instead (that gives {} = {} and beta {} = {})",
          g(x), k_name, member, g(given), g(f.member_length / given), length_unit, g(given), g(x), modulus_unit, g(x),
          k_name, g(x * l4_over_EI), member, g(meant)));
  }
  // The reverse: a modulus K that reads like a nondimensional k (K = 30 meaning K L^4/EI = 30).
  if (!dimensional.empty()) {
    const double x = *std::max_element(dimensional.begin(), dimensional.end());
    const double given = beta_length(x * l4_over_EI), meant = beta_length(x);
    // Only below the rigid limit: a large beta L from a modulus is an ordinary long member (a
    // 500 m pipeline on the seabed has beta L = 100).
    if (given < rigid_beta_length && plausible(meant))
      out.push_back(fmt::format(
          "foundation: modulus = {} ({}) gives {} = {} and beta {} = {}; if {} is the nondimensional {}, write "
          "nondimensional_k = {} instead (beta {} = {})",
          g(x), modulus_unit, k_name, g(x * l4_over_EI), member, g(given), g(x), k_name, g(x), member, g(meant)));
  }
  // A system's units are known in SI: a modulus no real bed has is a units mistake.
  if (units.metres() && units.newtons()) {
    const double to_si = *units.newtons() / (*units.metres() * *units.metres());
    const double least = f.K_min * to_si, largest = f.K_max * to_si;
    if (least < least_real_modulus || largest > largest_real_modulus)
      out.push_back(fmt::format(
          "foundation: K = {}{}{} is outside the moduli of real beds (soft soil to rock, about {:g} to {:g} N/m^2: "
          "a subgrade modulus in N/m^3 times the bearing width); check the modulus, EI and the [units]",
          g(largest > largest_real_modulus ? f.K_max : f.K_min), with_unit(units.modulus()),
          to_si == 1.0 ? std::string()
                       : fmt::format(" ({} N/m^2)", g(largest > largest_real_modulus ? largest : least)),
          least_real_modulus, largest_real_modulus));
  }
  if (f.beta_length_max < rigid_beta_length)
    out.push_back(fmt::format(
        "beta {} = {} < {:g}: the member is practically rigid on this foundation ({} = 4 (beta {})^4 = {}: its "
        "bending is negligible beside its settlement); contact and lift-off follow from statics (the loads' "
        "resultant and its eccentricity); check EI and the modulus if this is not intended",
        member, g(f.beta_length_max), rigid_beta_length, k_name, member, g(f.k_max)));
  if (f.beta_h > unresolved_beta_h)
    out.push_back(fmt::format(
        "the mesh does not resolve the decay length 1/beta = {}{}: elements up to h = {}{} on the foundation "
        "(beta h = {} > {:g}; cubic elements follow w ~ exp(-beta x) cos(beta x) only with beta h <= 1); use at least "
        "{} elements ([solve] elements, --elements)",
        g(f.characteristic_length()), length_unit, g(f.element_size), length_unit, g(f.beta_h), unresolved_beta_h,
        // (less a round-off margin: 5 elements at beta h = 2 need 10, not 11)
        static_cast<long long>(std::ceil(f.elements * f.beta_h / unresolved_beta_h * (1 - 1e-12)))));
  return out;
}

}  // namespace liftoff::post
