#include "post/scale.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>

namespace liftoff::post {
namespace {

// beta l = (k/4)^(1/4): the decay rate per unit of the member coordinate s (x/L, or theta).
double beta_s(double k) { return std::pow(k / 4.0, 0.25); }

std::string g(double x) { return fmt::format("{:.3g}", x); }

std::string with_unit(const std::string& label) { return label.empty() ? std::string() : " " + label; }

// A slip of units: a plain number written in `unit` (a sibling system's) where the scene's is
// meant; the scene reads x where the user meant x * factor in its units.
struct Slip {
  std::string unit;
  double factor = 1.0;
};

// The slips a plain number of force^a length^b may hold, nearest first (a force's prefix before
// a length's), each at least a factor of 100: smaller factors are no unit slip and no plausibility
// test here is sharp enough for them.
std::vector<Slip> slips(const scene::Units& units, int a, int b,
                        const std::function<std::string(const scene::Units&)>& label) {
  std::vector<std::pair<double, Slip>> ranked;
  for (const scene::Units& other : scene::sibling_systems(units)) {
    const double factor =
        std::pow(*other.newtons() / *units.newtons(), a) * std::pow(*other.metres() / *units.metres(), b);
    const double distance = std::abs(std::log10(factor));
    if (distance < 2 - 1e-9) continue;
    ranked.push_back({distance + (other.length == units.length ? 0.0 : 0.5), {label(other), factor}});
  }
  std::stable_sort(ranked.begin(), ranked.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<Slip> out;
  for (const auto& [unused, slip] : ranked) out.push_back(slip);
  return out;
}

// The first slip that makes `plausible` hold of the value it would have meant.
std::optional<Slip> first_slip(double x, const std::vector<Slip>& candidates,
                               const std::function<bool(double)>& plausible) {
  for (const Slip& slip : candidates)
    if (plausible(x * slip.factor)) return slip;
  return std::nullopt;
}

// "EI = 5.4e+08 looks like N m^2 in a kN-m scene: 1000x"
std::string slip_text(std::string_view name, double x, const Slip& slip, const scene::Units& units) {
  const std::string scene = units.system.empty() ? fmt::format("a scene of {} and {}", units.force, units.length)
                                                 : fmt::format("a {} scene", units.system);
  return fmt::format("{} = {} looks like {} in {}: {:.4g}x", name, g(x), slip.unit, scene,
                     std::max(slip.factor, 1.0 / slip.factor));
}

bool given_with_unit(const scene::Scene& scene, std::string_view path) {
  return std::find(scene.given_with_unit.begin(), scene.given_with_unit.end(), path) != scene.given_with_unit.end();
}

// "FILE: key 'structure.EI'", as the reader's warnings start.
std::string keyed(const scene::Scene& scene, std::string_view path) {
  return fmt::format("{}: key '{}'", scene.source_name, path);
}

// The plain dimensional modulus of a one-piece foundation, the one key a slip can be named in.
std::optional<double> plain_modulus(const scene::Scene& scene) {
  const scene::Foundation& f = scene.foundation;
  if (!f.segments.empty() || !f.modulus || given_with_unit(scene, "foundation.modulus")) return std::nullopt;
  return f.modulus;
}

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
  // A member as stiff as a section cannot be: the radius of gyration sqrt(EI/EA) more than a
  // quarter of L (of R on an arch); a rectangle's is 0.29 of its depth. EI in N m^2 in a kN-m
  // scene makes it 32 times too large, and so does EA in MN: each plain key whose slip would
  // explain it gets its warning.
  const std::optional<double> EA = scene.structure.axial_stiffness;
  const double EI = scene.structure.bending_stiffness;
  const bool si_known = units.metres() && units.newtons();
  if (EA && si_known && std::sqrt(EI / *EA) > l / max_gyration_ratio) {
    const auto deep = [&](double ei, double ea) { return std::sqrt(ei / ea) > l / max_gyration_ratio; };
    const std::string figure =
        fmt::format("the radius of gyration sqrt(EI/EA) = {}{} is more than {}/{:g} = {}{}: no section is that deep",
                    g(std::sqrt(EI / *EA)), length_unit, f.arch ? "R" : "L", max_gyration_ratio,
                    g(l / max_gyration_ratio), length_unit);
    std::vector<std::string> named;
    if (!given_with_unit(scene, "structure.EI"))
      if (const auto s = first_slip(EI, slips(units, 1, 2, [](const scene::Units& u) { return u.bending_stiffness(); }),
                                    [&](double ei) { return !deep(ei, *EA); }))
        named.push_back(fmt::format(
            "{}: {}; {} (as {}{} it gives {}{})", keyed(scene, "structure.EI"), figure, slip_text("EI", EI, *s, units),
            g(EI * s->factor), with_unit(units.bending_stiffness()), g(std::sqrt(EI * s->factor / *EA)), length_unit));
    if (!given_with_unit(scene, "structure.EA"))
      if (const auto s = first_slip(*EA, slips(units, 1, 0, [](const scene::Units& u) { return u.force; }),
                                    [&](double ea) { return !deep(EI, ea); }))
        named.push_back(fmt::format("{}: {}; {} (as {}{} it gives {}{})", keyed(scene, "structure.EA"), figure,
                                    slip_text("EA", *EA, *s, units), g(*EA * s->factor), with_unit(units.force),
                                    g(std::sqrt(EI / (*EA * s->factor))), length_unit));
    if (named.empty()) named.push_back(fmt::format("{}; check EI, EA and the [units]", figure));
    for (std::string& w : named) out.push_back(std::move(w));
  }
  if (f.beta_length_max < rigid_beta_length && si_known) {
    // A practically rigid member whose EI, or modulus, read in a sibling unit would not be: name
    // each slip that would explain it (beta L goes as (K/EI)^(1/4): 1000x in EI is 5.6x in beta L).
    const auto ordinary = [&](double ratio) {  // K/EI scaled by `ratio`
      const double bl = f.beta_length_max * std::pow(ratio, 0.25);
      return bl >= rigid_beta_length && bl <= long_beta_length;
    };
    if (!given_with_unit(scene, "structure.EI"))
      if (const auto s = first_slip(EI, slips(units, 1, 2, [](const scene::Units& u) { return u.bending_stiffness(); }),
                                    [&](double ei) { return ordinary(EI / ei); }))
        out.push_back(fmt::format("{}: {} (as {}{} it gives beta {} = {})", keyed(scene, "structure.EI"),
                                  slip_text("EI", EI, *s, units), g(EI * s->factor),
                                  with_unit(units.bending_stiffness()), member,
                                  g(f.beta_length_max * std::pow(1.0 / s->factor, 0.25))));
    if (const std::optional<double> K = plain_modulus(scene))
      if (const auto s = first_slip(*K, slips(units, 1, -2, [](const scene::Units& u) { return u.modulus(); }),
                                    [&](double k) { return ordinary(k / *K); }))
        out.push_back(fmt::format("{}: {} (as {}{} it gives beta {} = {})", keyed(scene, "foundation.modulus"),
                                  slip_text("modulus", *K, *s, units), g(*K * s->factor), with_unit(units.modulus()),
                                  member, g(f.beta_length_max * std::pow(s->factor, 0.25))));
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

std::vector<std::string> deflection_warnings(const scene::Scene& scene, const ScaleFigures& f, double w_extreme) {
  std::vector<std::string> out;
  const scene::Units& units = scene.units;
  const double w = std::abs(w_extreme);
  if (!units.stated() || !(w > f.member_length / max_deflection_ratio)) return out;
  const char* member = f.arch ? "S" : "L";
  // w goes as 1/K where the foundation carries the loads: a modulus whose sibling unit brings w
  // below the limit is the likely slip.
  std::string slip;
  // Only a soft modulus is suspected (an ordinary bed under a deflection this large points to the
  // loads), and only a slip to a real bed's modulus.
  const double to_si = units.metres() && units.newtons() ? *units.newtons() / std::pow(*units.metres(), 2) : 0.0;
  const auto real = [&](double k) { return k * to_si >= least_real_modulus && k * to_si <= largest_real_modulus; };
  if (const std::optional<double> K = plain_modulus(scene); K && to_si > 0 && *K * to_si < soft_modulus)
    if (const auto s = first_slip(
            *K, slips(units, 1, -2, [](const scene::Units& u) { return u.modulus(); }),
            [&](double k) { return k > *K && real(k) && w * *K / k <= f.member_length / max_deflection_ratio; }))
      slip = fmt::format("; {}: {} (as {}{} w is about {}{})", keyed(scene, "foundation.modulus"),
                         slip_text("modulus", *K, *s, units), g(*K * s->factor), with_unit(units.modulus()),
                         g(w / s->factor), with_unit(units.length));
  out.push_back(fmt::format(
      "deflection: |w| up to {}{} is {} of the member's length {} = {}{} (more than 1/{:g}: a linear model needs w "
      "small against the length); check the loads, the modulus, EI and their units{}",
      g(w), with_unit(units.length), g(w / f.member_length), member, g(f.member_length), with_unit(units.length),
      max_deflection_ratio, slip));
  return out;
}

}  // namespace liftoff::post
