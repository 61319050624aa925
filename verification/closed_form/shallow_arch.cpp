#include "closed_form/shallow_arch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <stdexcept>

namespace liftoff::closed_form {

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

double beta(const ShallowArch& arch) { return M_PI / arch.length; }

// Real roots of t^3 + P t + Q = 0, ascending, polished by Newton.
std::vector<double> depressed_cubic_roots(double P, double Q) {
  std::vector<double> t;
  const double disc = -(4 * P * P * P + 27 * Q * Q);
  if (P < 0 && disc > 0) {
    const double m = 2 * std::sqrt(-P / 3);
    const double c = std::clamp(3 * Q / (P * m), -1.0, 1.0);  // cos(3 phi)
    const double phi = std::acos(c) / 3;
    for (int k = 0; k < 3; ++k) t.push_back(m * std::cos(phi - 2 * M_PI * k / 3));
  } else if (P > 0) {
    const double m = 2 * std::sqrt(P / 3);
    t.push_back(-m * std::sinh(std::asinh(3 * Q / (P * m)) / 3));
  } else if (P < 0) {
    const double m = 2 * std::sqrt(-P / 3);
    t.push_back(-std::copysign(1.0, Q) * m * std::cosh(std::acosh(std::max(1.0, -3 * std::abs(Q) / (P * m))) / 3));
  } else {
    t.push_back(std::cbrt(-Q));
  }
  for (double& x : t)
    for (int i = 0; i < 3; ++i) {
      const double d = 3 * x * x + P;
      if (d != 0.0) x -= (x * x * x + P * x + Q) / d;
    }
  std::sort(t.begin(), t.end());
  return t;
}

// Gauss-Legendre, 5 points on [-1, 1].
constexpr double gauss_x[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640};
constexpr double gauss_w[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                               0.2369268850561891};

}  // namespace

void ShallowArch::validate() const {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  require(positive(length), "length: expected a positive number");
  require(positive(bending_stiffness), "EI: expected a positive number");
  require(positive(axial_stiffness), "EA: expected a positive number");
  require(positive(rise), "rise: expected a positive number (the arch rises away from the foundation)");
  require(std::isfinite(foundation_modulus) && foundation_modulus >= 0.0, "modulus: expected a number >= 0");
  require(positive(load_amplitude), "load: expected a positive number (q0 pushes toward the foundation)");
}

double ShallowArch::radius_of_gyration() const { return std::sqrt(bending_stiffness / axial_stiffness); }
double ShallowArch::relative_rise() const { return rise / radius_of_gyration(); }
double ShallowArch::relative_modulus() const {
  return foundation_modulus / (bending_stiffness * std::pow(M_PI / length, 4));
}
double ShallowArch::load_unit() const {
  return bending_stiffness * std::pow(M_PI / length, 4) * radius_of_gyration() / load_amplitude;
}

double symmetric_load(const ShallowArch& arch, double deflection) {
  const double xi = deflection / arch.radius_of_gyration(), alpha = arch.relative_rise();
  const double kappa = arch.relative_modulus();
  return arch.load_unit() * ((1 + kappa) * xi + xi * (xi - alpha) * (xi - 2 * alpha) / 4);
}

std::vector<double> symmetric_deflections(const ShallowArch& arch, double lambda) {
  const double alpha = arch.relative_rise(), kappa = arch.relative_modulus(), r = arch.radius_of_gyration();
  const double p = lambda / arch.load_unit();
  // t^3 + (4 (1 + kappa) - alpha^2) t + 4 ((1 + kappa) alpha - p) = 0, xi = alpha + t.
  std::vector<double> a1;
  for (double t : depressed_cubic_roots(4 * (1 + kappa) - alpha * alpha, 4 * ((1 + kappa) * alpha - p)))
    a1.push_back(r * (alpha + t));
  return a1;
}

double thrust(const ShallowArch& arch, double a1, double a2) {
  const double b = beta(arch);
  return -arch.axial_stiffness * b * b / 4 * (a1 * a1 + 4 * a2 * a2 - 2 * arch.rise * a1);
}

double bifurcated_load(const ShallowArch& arch, double a1) {
  const double alpha = arch.relative_rise(), kappa = arch.relative_modulus();
  const double t = a1 / arch.radius_of_gyration() - alpha;
  return arch.load_unit() * ((1 + kappa) * alpha + 3 * (kappa - 4) * t / 4);
}

double bifurcated_asymmetry(const ShallowArch& arch, double a1) {
  const double alpha = arch.relative_rise(), kappa = arch.relative_modulus(), r = arch.radius_of_gyration();
  const double t = a1 / r - alpha;
  const double eta2 = (alpha * alpha - 16 - kappa - t * t) / 4;
  return eta2 >= 0 ? r * std::sqrt(eta2) : -1.0;
}

double potential_energy(const ShallowArch& arch, double lambda, double a1, double a2, bool tensionless) {
  const double L = arch.length, b = beta(arch), k = arch.foundation_modulus;
  constexpr int panels = 64;
  double bulk = 0.0, stretch = 0.0;
  for (int i = 0; i < panels; ++i)
    for (int g = 0; g < 5; ++g) {
      const double x = L * (i + 0.5 + 0.5 * gauss_x[g]) / panels, weight = 0.5 * L / panels * gauss_w[g];
      const double s1 = std::sin(b * x), s2 = std::sin(2 * b * x);
      const double w = a1 * s1 + a2 * s2;
      const double dw = b * (a1 * std::cos(b * x) + 2 * a2 * std::cos(2 * b * x));
      const double ddw = -b * b * (a1 * s1 + 4 * a2 * s2);
      const double dw0 = -arch.rise * b * std::cos(b * x);
      const double reacting = tensionless ? std::max(w, 0.0) : w;
      bulk += weight * (0.5 * arch.bending_stiffness * ddw * ddw + 0.5 * k * reacting * reacting -
                        lambda * arch.load_amplitude * s1 * w);
      stretch += weight * (dw0 * dw + 0.5 * dw * dw);
    }
  const double N = arch.axial_stiffness / L * stretch;
  return bulk + L * N * N / (2 * arch.axial_stiffness);
}

Eigen::Matrix2d energy_hessian(const ShallowArch& arch, double a1, double a2) {
  const double r = arch.radius_of_gyration(), alpha = arch.relative_rise(), kappa = arch.relative_modulus();
  const double xi = a1 / r, eta = a2 / r, E = xi * xi + 4 * eta * eta - 2 * alpha * xi;
  Eigen::Matrix2d h;
  h(0, 0) = 2 * (1 + kappa) + (xi - alpha) * (xi - alpha) + E / 2;
  h(1, 1) = 2 * (16 + kappa + E) + 16 * eta * eta;
  h(0, 1) = h(1, 0) = 4 * eta * (xi - alpha);
  // Pi = (L EI beta^4 r^2 / 4) Pihat and A = r xi: d2Pi/dA2 = (L EI beta^4 / 4) d2Pihat/dxi2.
  return arch.length * arch.bending_stiffness * std::pow(beta(arch), 4) / 4 * h;
}

// Names in the enums' declaration order (shallow_arch.hpp).
constexpr const char* branch_stability_names[] = {"stable", "unstable", "neutral"};
constexpr const char* first_critical_names[] = {"none", "limit_point", "unstable_bifurcation", "neutral_bifurcation",
                                                "stable_bifurcation"};
std::string to_string(BranchStability s) { return branch_stability_names[static_cast<int>(s)]; }
std::string to_string(FirstCritical f) { return first_critical_names[static_cast<int>(f)]; }

ShallowArchAnalysis analyse(const ShallowArch& arch) {
  arch.validate();
  const double alpha = arch.relative_rise(), kappa = arch.relative_modulus(), r = arch.radius_of_gyration();
  const double unit = arch.load_unit();
  ShallowArchAnalysis out;
  out.limit_rise = 2 * std::sqrt(1 + kappa);
  out.bifurcation_rise = std::sqrt(16 + kappa);
  out.bifurcation_first_rise = kappa < 4 ? std::sqrt(22 - kappa / 2) : out.bifurcation_rise;
  out.contact_event_rise = std::sqrt(2 * (16 + kappa));
  const auto point = [&](double a1, double a2, double lambda) {
    return ArchPoint{a1, a2, lambda, thrust(arch, a1, a2)};
  };
  const double tL2 = (alpha * alpha - 4 * (1 + kappa)) / 3, tB2 = alpha * alpha - 16 - kappa;
  const double tL = tL2 > 0 ? std::sqrt(tL2) : 0.0, tB = tB2 > 0 ? std::sqrt(tB2) : 0.0;
  // xi = alpha - t without cancellation when t is close to alpha: alpha - t = (alpha^2 - t^2) / (alpha + t).
  const auto below = [&](double t2, double t) { return (alpha * alpha - t2) / (alpha + t); };
  const double p0 = (1 + kappa) * alpha, branch = 3 * (kappa - 4) / 4;
  out.has_limit_points = tL2 > 0;
  if (out.has_limit_points) {
    const double dp = tL * tL * tL / 2;
    out.upper_limit = point(r * below(tL2, tL), 0.0, unit * (p0 + dp));
    out.lower_limit = point(r * (alpha + tL), 0.0, unit * (p0 - dp));
  }
  out.has_bifurcation = tB2 > 0;
  out.branch_slope = unit / r * branch;
  // Neutral within the round-off of kappa (k / (EI beta^4) carries a few ulps).
  const bool neutral = std::abs(kappa - 4) <= 64 * std::numeric_limits<double>::epsilon() * 4;
  out.branch_stability = neutral     ? BranchStability::neutral
                         : kappa > 4 ? BranchStability::stable
                                     : BranchStability::unstable;
  if (out.has_bifurcation) {
    out.first_bifurcation = point(r * below(tB2, tB), 0.0, unit * (p0 - branch * tB));
    out.second_bifurcation = point(r * (alpha + tB), 0.0, unit * (p0 + branch * tB));
  }
  // Lift-off: xi = (alpha -+ s) / 2, s = sqrt(alpha^2 - 2 (16 + kappa)); the smaller as (16 + kappa) / (alpha + s).
  const double c2 = alpha * alpha - 2 * (16 + kappa);
  out.has_contact_event = c2 >= 0;
  if (out.has_contact_event) {
    const double s = std::sqrt(c2);
    const auto event = [&](double xi) { return point(r * xi, r * xi / 2, unit * (p0 + branch * (xi - alpha))); };
    out.first_lift_off = event((16 + kappa) / (alpha + s));
    out.last_lift_off = event((alpha + s) / 2);
  }
  const bool bifurcation_first = out.has_bifurcation && (!out.has_limit_points || tB > tL);
  char text[512];
  if (bifurcation_first) {
    out.first = neutral     ? FirstCritical::neutral_bifurcation
                : kappa > 4 ? FirstCritical::stable_bifurcation
                            : FirstCritical::unstable_bifurcation;
    std::snprintf(text, sizeof text,
                  "a/r = %.6g > %.6g: the asymmetric bifurcation at lambda = %.6g comes first; its branch is %s "
                  "(d lambda / d A1 = %.6g)%s",
                  alpha, out.has_limit_points ? out.bifurcation_first_rise : out.bifurcation_rise,
                  out.first_bifurcation.load, to_string(out.branch_stability).c_str(), out.branch_slope,
                  kappa > 4 && !neutral ? ": no snap-through, the path rejoins the symmetric one"
                                        : ": the arch snaps through asymmetrically");
  } else if (out.has_limit_points) {
    out.first = FirstCritical::limit_point;
    std::snprintf(text, sizeof text,
                  "2 sqrt(1 + kappa) = %.6g < a/r = %.6g: symmetric snap-through at the limit point lambda = %.6g",
                  out.limit_rise, alpha, out.upper_limit.load);
  } else {
    std::snprintf(text, sizeof text, "a/r = %.6g <= %.6g: no limit point, no bifurcation; the path is stable", alpha,
                  std::min(out.limit_rise, out.bifurcation_rise));
  }
  out.reason = text;
  if (bifurcation_first && out.has_contact_event)
    out.reason += "; on a tensionless foundation the branch lifts off at an end at lambda = " +
                  std::to_string(out.first_lift_off.load) + ", beyond which this reference does not follow it";
  // The least thrust among the modes n >= 2 (n^2 + kappa / n^2 is convex in n^2: stop once it grows).
  double least = 4 + kappa / 4;
  for (int n = 3;; ++n) {
    const double thrust_n = n * n + kappa / (n * n);
    if (thrust_n >= least) break;
    least = thrust_n, out.critical_mode = n;
  }
  out.covered = out.critical_mode == 2 || alpha * alpha <= 4 * least;
  if (!out.covered)
    out.reason = "not covered: mode " + std::to_string(out.critical_mode) +
                 " bifurcates before the second one (k > 36 EI (pi/L)^4); " + out.reason;
  return out;
}

namespace {

void print_point(const char* name, const ArchPoint& p) {
  std::printf(", \"%s\": {\"A1\": %.17g, \"A2\": %.17g, \"lambda\": %.17g, \"thrust\": %.17g}", name, p.deflection,
              p.asymmetry, p.load, p.thrust);
}

}  // namespace

int shallow_arch_command(int argc, char** argv) {
  ShallowArch arch;
  int points = 0;
  bool have_rise = false;
  for (int i = 2; i < argc; ++i) {
    const std::string option = argv[i];
    if (option == "--help") {
      std::printf(
          "usage: closed_form_reference shallow-arch --rise a [--length L] [--EI EI] [--EA EA] [--modulus k] "
          "[--load q0] [--points N]\n"
          "  the sinusoidal shallow arch w0 = -a sin(pi x/L) (rising away from the foundation), pinned ends "
          "axially restrained, q = lambda q0 sin(pi x/L) toward the foundation, bilateral Winkler modulus k "
          "(tensionless agrees up to the contact event): limit points, asymmetric bifurcation, branch "
          "stability, first lift-off, as JSON; --points N adds the symmetric path at N + 1 values of A1 in "
          "[0, 2a] (defaults: L = EI = EA = q0 = 1, k = 0)\n");
      return 0;
    }
    if (i + 1 >= argc) {
      std::cerr << "closed_form_reference: shallow-arch: " << option << ": expected a value after it\n";
      return 2;
    }
    const std::string text = argv[++i];
    double value = NAN;
    try {
      std::size_t used = 0;
      value = std::stod(text, &used);
      if (used != text.size()) value = NAN;
    } catch (const std::exception&) {
    }
    if (!std::isfinite(value)) {
      std::cerr << "closed_form_reference: shallow-arch: " << option << ": expected a number, got '" << text << "'\n";
      return 2;
    }
    if (option == "--length")
      arch.length = value;
    else if (option == "--EI")
      arch.bending_stiffness = value;
    else if (option == "--EA")
      arch.axial_stiffness = value;
    else if (option == "--rise")
      arch.rise = value, have_rise = true;
    else if (option == "--modulus")
      arch.foundation_modulus = value;
    else if (option == "--load")
      arch.load_amplitude = value;
    else if (option == "--points") {
      if (value < 0 || value != std::floor(value) || value > 1e6) {
        std::cerr << "closed_form_reference: shallow-arch: --points: expected a whole number up to 1e6, got '" << text
                  << "'\n";
        return 2;
      }
      points = static_cast<int>(value);
    } else {
      std::cerr << "closed_form_reference: shallow-arch: " << option
                << ": unknown option; expected --length, --EI, --EA, --rise, --modulus, --load, --points or --help\n";
      return 2;
    }
  }
  if (!have_rise) {
    std::cerr << "closed_form_reference: shallow-arch: --rise: expected the arch's rise a > 0\n";
    return 2;
  }
  ShallowArchAnalysis a;
  try {
    a = analyse(arch);
  } catch (const std::invalid_argument& e) {
    std::cerr << "closed_form_reference: shallow-arch: --" << e.what() << "\n";
    return 2;
  }
  std::printf(
      "{\"method\": \"closed-form shallow arch\", \"length\": %.17g, \"EI\": %.17g, \"EA\": %.17g, \"rise\": %.17g, "
      "\"modulus\": %.17g, \"load\": %.17g, \"radius_of_gyration\": %.17g, \"relative_rise\": %.17g, "
      "\"relative_modulus\": %.17g, \"limit_rise\": %.17g, \"bifurcation_rise\": %.17g, "
      "\"bifurcation_first_rise\": %.17g, \"contact_event_rise\": %.17g, \"has_limit_points\": %s",
      arch.length, arch.bending_stiffness, arch.axial_stiffness, arch.rise, arch.foundation_modulus,
      arch.load_amplitude, arch.radius_of_gyration(), arch.relative_rise(), arch.relative_modulus(), a.limit_rise,
      a.bifurcation_rise, a.bifurcation_first_rise, a.contact_event_rise, a.has_limit_points ? "true" : "false");
  if (a.has_limit_points) {
    print_point("upper_limit", a.upper_limit);
    print_point("lower_limit", a.lower_limit);
  }
  std::printf(", \"has_bifurcation\": %s", a.has_bifurcation ? "true" : "false");
  if (a.has_bifurcation) {
    print_point("first_bifurcation", a.first_bifurcation);
    print_point("second_bifurcation", a.second_bifurcation);
  }
  std::printf(", \"branch_slope\": %.17g, \"branch_stability\": \"%s\", \"has_contact_event\": %s", a.branch_slope,
              to_string(a.branch_stability).c_str(), a.has_bifurcation && a.has_contact_event ? "true" : "false");
  if (a.has_bifurcation && a.has_contact_event) {
    print_point("first_lift_off", a.first_lift_off);
    print_point("last_lift_off", a.last_lift_off);
  }
  std::printf(", \"critical_mode\": %d, \"covered\": %s, \"first\": \"%s\", \"reason\": \"%s\"", a.critical_mode,
              a.covered ? "true" : "false", to_string(a.first).c_str(), a.reason.c_str());
  if (points > 0) {
    std::printf(", \"symmetric_path\": [");
    for (int i = 0; i <= points; ++i) {
      const double a1 = 2 * arch.rise * i / points;
      std::printf("%s\n  {\"A1\": %.17g, \"lambda\": %.17g, \"thrust\": %.17g}", i ? "," : "", a1,
                  symmetric_load(arch, a1), thrust(arch, a1, 0.0));
    }
    std::printf("]");
  }
  std::printf("}\n");
  return 0;
}

}  // namespace liftoff::closed_form
