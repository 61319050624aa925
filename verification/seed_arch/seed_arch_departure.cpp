// seed_arch_departure: the seed's arch beyond linear theory (issue 16, item 6). For each end
// condition (pinned, clamped, roller: verification/scenes/seed_arch_*.toml) along the load history
// lambda = 0.05, 0.1, ..., max_factor (lambda = 1: the seed's crown load P = 0.1), on two meshes:
// the crown deflection, the contact half-angle and the crown thrust by linear and von Karman
// theory and their relative differences; the load factor at which each of the first two first
// reaches 1 % (bisection to 1e-4 in lambda); the first loss of stability, if any.
//
//   seed_arch_departure [--elements N] [--max-factor F] [--step S] [--csv FILE]
// prints a table per end condition and mesh (N and N / 2), and writes every row to FILE.
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "scene/scene_reader.hpp"
#include "seed_arch/departure.hpp"

using namespace liftoff;

int main(int argc, char** argv) {
  int elements = 200;
  double max_factor = 2.0, step = 0.05;
  std::string csv_path;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--elements"))
      elements = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--max-factor"))
      max_factor = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--step"))
      step = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--csv"))
      csv_path = argv[i + 1];
    else {
      std::fprintf(stderr, "seed_arch_departure: unknown option %s\n", argv[i]);
      return 2;
    }
  }
  if (elements < 4 || elements % 4 != 0 || !(max_factor > 0) || !(step > 0)) {
    std::fprintf(stderr, "seed_arch_departure: --elements a multiple of 4, --max-factor and --step > 0\n");
    return 2;
  }
  std::FILE* csv = csv_path.empty() ? nullptr : std::fopen(csv_path.c_str(), "w");
  if (!csv_path.empty() && csv == nullptr) {
    std::fprintf(stderr, "seed_arch_departure: cannot write %s\n", csv_path.c_str());
    return 3;
  }
  if (csv)
    std::fprintf(csv,
                 "ends,elements,load_factor,w0_linear,w0_vk,half_angle_linear,half_angle_vk,thrust_linear,thrust_vk,"
                 "regions_vk,stable,largest_slope_vk\n");
  int status = 0;
  for (const char* ends : {"pinned", "clamped", "roller"}) {
    const scene::Scene scene =
        scene::read_scene_file(std::string(LIFTOFF_SOURCE_DIR) + "/verification/scenes/seed_arch_" + ends + ".toml");
    for (int n : {elements, elements / 2}) {
      const study::SeedArchStudy arch(scene, n);
      std::printf("\n%s ends, %d elements: lambda = 1 is the seed's P = 0.1\n", ends, n);
      std::printf("%6s %11s %11s %8s | %9s %9s %8s | %9s %9s %8s | %s\n", "lambda", "w0 lin", "w0 vK", "diff",
                  "phi lin", "phi vK", "diff", "N0 lin", "N0 vK", "diff", "stable");
      contact::VonKarmanResult state, before;
      double previous = 0.0;
      double first_deflection = NAN, first_angle = NAN, unstable_at = NAN;
      const int steps = static_cast<int>(std::lround(max_factor / step));
      for (int k = 1; k <= steps; ++k) {
        const double lambda = k * step;
        before = state;
        study::DepartureRow row = arch.row(lambda, &state);
        // A failed step is retried in quarters from the last answer (the Newton start matters
        // most where the contact set moves fast); a failure after that ends the history.
        if (!row.von_karman.usable) {
          state = before;
          for (int q = 1; q <= 4 && (q == 1 || row.von_karman.usable); ++q)
            row = arch.row(previous + 0.25 * q * (lambda - previous), &state);
        }
        if (!row.linear.usable || !row.von_karman.usable) {
          std::printf("%6.3f  not solved: %s%s\n", lambda, row.linear.message.c_str(), row.von_karman.message.c_str());
          status = 1;
          break;
        }
        std::printf("%6.3f %11.5e %11.5e %+7.3f%% | %9.5f %9.5f %+7.3f%% | %9.4f %9.4f %+7.3f%% | %s%s\n", lambda,
                    row.linear.crown_deflection, row.von_karman.crown_deflection, 100 * row.deflection(),
                    row.linear.half_angle_deg, row.von_karman.half_angle_deg, 100 * row.half_angle(),
                    row.linear.crown_thrust, row.von_karman.crown_thrust, 100 * row.thrust(),
                    row.von_karman.stable ? "yes" : "NO", row.von_karman.contact_regions != 1 ? " (regions != 1)" : "");
        if (csv)
          std::fprintf(csv, "%s,%d,%.6f,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%d,%d,%.6e\n", ends, n, lambda,
                       row.linear.crown_deflection, row.von_karman.crown_deflection, row.linear.half_angle_deg,
                       row.von_karman.half_angle_deg, row.linear.crown_thrust, row.von_karman.crown_thrust,
                       row.von_karman.contact_regions, row.von_karman.stable ? 1 : 0, row.von_karman.largest_slope);
        const double resolution = 1e-4;
        if (std::isnan(first_deflection) && std::abs(row.deflection()) >= 0.01)
          first_deflection =
              study::crossing(arch, &study::DepartureRow::deflection, 0.01, previous, lambda, resolution, before);
        if (std::isnan(first_angle) && std::abs(row.half_angle()) >= 0.01)
          first_angle =
              study::crossing(arch, &study::DepartureRow::half_angle, 0.01, previous, lambda, resolution, before);
        if (std::isnan(unstable_at) && !row.von_karman.stable) unstable_at = lambda;
        previous = lambda;
      }
      // nan: the history never departed by 1 %.
      const auto at = [&](double crossing) {
        return std::isnan(crossing) ? fmt::format("not reached up to lambda = {:g}", max_factor)
                                    : fmt::format("at lambda = {:.4f}", crossing);
      };
      std::printf("1 %% departure (bisection, +-5e-5 in lambda): crown deflection %s, contact half-angle %s; %s\n",
                  at(first_deflection).c_str(), at(first_angle).c_str(),
                  std::isnan(unstable_at) ? "stable throughout"
                                          : fmt::format("first unstable answer at lambda = {:g}", unstable_at).c_str());
      if (csv)
        std::fprintf(csv, "# %s,%d,crossing_deflection=%.6f,crossing_half_angle=%.6f\n", ends, n, first_deflection,
                     first_angle);
    }
  }
  if (csv) std::fclose(csv);
  return status;
}
