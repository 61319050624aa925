#pragma once
// Solving a scene in-process, as `liftoff solve` does, for tests that check numbers.

#include <cmath>
#include <vector>

#include "contact/contact_solver.hpp"
#include "fe/discretisation.hpp"
#include "model/from_scene.hpp"
#include "model/member_model.hpp"
#include "post/contact_regions.hpp"
#include "scene/scene.hpp"

namespace liftoff::test {

struct Solved {
  model::MemberModel model;
  fe::Discretisation discretisation;
  contact::ContactSolution solution;
  std::vector<ContactRegion> regions;  // in s
};

inline Solved solve(const scene::Scene& scene, contact::Method method, int elements, double load_factor = 1.0) {
  Solved out;
  out.model = model::make_member_model(scene);
  out.discretisation = fe::discretise(out.model, elements);
  contact::ContactOptions options;
  options.method = method;
  options.load_factor = load_factor;
  out.solution = contact::solve_contact(out.discretisation, options);
  out.regions = post::contact_regions(out.model, out.discretisation, out.solution.displacement);
  return out;
}

// max |a - b| / max(|a|, |b|) over two displacement vectors.
inline double relative_difference(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  const double scale = std::max(a.lpNorm<Eigen::Infinity>(), b.lpNorm<Eigen::Infinity>());
  return scale == 0.0 ? 0.0 : (a - b).lpNorm<Eigen::Infinity>() / scale;
}

// Least-squares slope of log(error) against log(h): the observed order of convergence.
inline double observed_order(const std::vector<double>& h, const std::vector<double>& error) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(h.size());
  for (std::size_t i = 0; i < h.size(); ++i) {
    const double x = std::log(h[i]), y = std::log(error[i]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace liftoff::test
