#include "post/contact_regions.hpp"

#include <algorithm>
#include <cmath>

#include "fe/shape_functions.hpp"
#include "post/fields.hpp"

namespace liftoff::post {

namespace {
// Subintervals per element in which a sign change of w is looked for; a cubic has at most
// three roots, so eight brackets separate all but nearly double roots.
constexpr int brackets = 8;
}  // namespace

std::vector<ContactRegion> contact_regions(const model::MemberModel& model, const fe::Discretisation& d,
                                           const Eigen::VectorXd& displacement) {
  const double begin = model.foundation_begin, end = model.foundation_end;
  const auto stretches = model.foundation_stretches();
  if (!d.tensionless) {
    std::vector<ContactRegion> whole;
    for (const auto& [a, b] : stretches) whole.push_back({a, b});
    return whole;
  }

  double w_scale = 0.0;
  for (int node = 0; node < static_cast<int>(d.mesh.nodes.size()); ++node)
    w_scale = std::max(
        {w_scale, std::abs(displacement[d.deflection_dof(node)]), std::abs(model.ground_gap(d.mesh.nodes[node]))});
  if (w_scale == 0.0) return {};
  const double threshold = 1e-12 * w_scale;
  const double edge = 1e-10 * model.length();

  // w - g: contact where the member reaches the ground (w >= g).
  auto w_at = [&](int e, double xi) {
    return evaluate(d, displacement, e, xi).w - model.ground_gap_in(d.mesh.nodes[e], d.mesh.element_size(e), xi);
  };
  // Points where w - g changes sign, found by bisection on the element's cubic (g is linear there).
  // The ends of the stretches of foundation cut too: no region spans a void.
  std::vector<double> cuts;
  for (const auto& [a, b] : stretches) cuts.insert(cuts.end(), {a, b});
  for (double s : model.ground_gap_at)  // a step of g is a node where w - g may change sign
    if (s - begin > edge && end - s > edge) cuts.push_back(s);
  for (int e = 0; e < d.mesh.elements(); ++e) {
    const double s0 = d.mesh.nodes[e], h = d.mesh.element_size(e);
    if (model.k_at(s0 + 0.5 * h) == 0.0) continue;
    // The element's cubic alone: gathered once, evaluated many times by the bisection.
    const std::vector<int> dofs = d.element_dofs(e);
    const Eigen::Vector4d w_dofs(displacement[dofs[0]], displacement[dofs[1]], displacement[dofs[2]],
                                 displacement[dofs[3]]);
    auto w_in = [&](double xi) { return fe::hermite_cubic(xi, h).value.dot(w_dofs) - model.ground_gap_in(s0, h, xi); };
    for (int i = 0; i < brackets; ++i) {
      double a = static_cast<double>(i) / brackets, b = static_cast<double>(i + 1) / brackets;
      double wa = w_in(a), wb = w_in(b);
      if ((wa > 0) == (wb > 0)) continue;
      while (b - a > 1e-15) {
        const double m = 0.5 * (a + b), wm = w_in(m);
        if ((wm > 0) == (wa > 0)) {
          a = m;
          wa = wm;
        } else {
          b = m;
        }
      }
      const double root = s0 + 0.5 * (a + b) * h;
      // A root at the foundation's end is the end itself (a support holds w = 0 there).
      if (root - begin > edge && end - root > edge) cuts.push_back(root);
    }
  }
  std::sort(cuts.begin(), cuts.end());

  std::vector<ContactRegion> regions;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double a = cuts[i], b = cuts[i + 1];
    if (b <= a || model.k_at(0.5 * (a + b)) == 0.0) continue;  // a void
    // Decide contact from the largest w on the piece (a few samples), so a piece in which w
    // only grazes round-off does not count.
    double w_max = -INFINITY;
    for (int k = 1; k <= 3; ++k) {
      const double s = a + (b - a) * k / 4.0;
      const int e = d.mesh.element_containing(s);
      w_max = std::max(w_max, w_at(e, (s - d.mesh.nodes[e]) / d.mesh.element_size(e)));
    }
    if (w_max <= threshold) continue;
    if (!regions.empty() && regions.back().end == a)
      regions.back().end = b;
    else
      regions.push_back({a, b});
  }
  return regions;
}

}  // namespace liftoff::post
