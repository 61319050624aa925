#include "fe/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace liftoff::fe {

namespace {
double tolerance(const model::MemberModel& model) { return 1e-12 * model.length(); }
}  // namespace

int Mesh::node_at(double s) const {
  const double tol = 1e-12 * (nodes.back() - nodes.front());
  auto it = std::lower_bound(nodes.begin(), nodes.end(), s - tol);
  if (it != nodes.end() && std::abs(*it - s) <= tol) return static_cast<int>(it - nodes.begin());
  return -1;
}

int Mesh::element_containing(double s) const {
  auto it = std::upper_bound(nodes.begin(), nodes.end(), s);
  int element = static_cast<int>(it - nodes.begin()) - 1;
  return std::clamp(element, 0, elements() - 1);
}

std::vector<double> mesh_breakpoints(const model::MemberModel& model) {
  std::vector<double> points{model.s_begin, model.s_end, model.foundation_begin, model.foundation_end};
  for (const model::FoundationPiece& piece : model.pieces()) {
    points.push_back(piece.begin);
    points.push_back(piece.end);
  }
  for (double s : model.point_supports) points.push_back(s);
  for (const model::SupportSpring& spring : model.springs) points.push_back(spring.s);
  for (double s : model.ground_gap_at) points.push_back(s);  // g is linear within elements
  for (const auto& load : model.loads) {
    if (load.has_extent()) {  // a distributed table's points too
      points.push_back(load.from);
      points.push_back(load.to);
    } else {
      points.push_back(load.at);
    }
  }
  // Roller ends leave the arch free to rotate about its centre; the gauge that removes this
  // motion fixes u at the crown, so the crown must be a node.
  if (model.kind == model::StructureKind::arch && model.left == model::EndSupport::roller &&
      model.right == model::EndSupport::roller)
    points.push_back(0.5 * (model.s_begin + model.s_end));

  for (double& s : points) s = std::clamp(s, model.s_begin, model.s_end);
  std::sort(points.begin(), points.end());
  const double tol = tolerance(model);
  std::vector<double> unique;
  for (double s : points)
    if (unique.empty() || s - unique.back() > tol) unique.push_back(s);
  unique.back() = model.s_end;
  return unique;
}

std::vector<int> apportion_elements(const std::vector<double>& points, int requested) {
  const int segments = static_cast<int>(points.size()) - 1;
  const int total = std::max(requested, segments);
  const double length = points.back() - points.front();
  // Largest-remainder apportionment with at least one element per segment.
  std::vector<double> share(segments);
  std::vector<int> count(segments);
  for (int i = 0; i < segments; ++i) {
    share[i] = total * (points[i + 1] - points[i]) / length;
    count[i] = std::max(1, static_cast<int>(std::floor(share[i])));
  }
  int assigned = std::accumulate(count.begin(), count.end(), 0);
  std::vector<int> order(segments);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return share[a] - count[a] > share[b] - count[b]; });
  for (int i = 0; assigned < total; i = (i + 1) % segments, ++assigned) ++count[order[i]];
  return count;
}

Mesh make_mesh(const std::vector<double>& points, const std::vector<int>& counts) {
  if (points.size() < 2 || counts.size() + 1 != points.size())
    throw std::invalid_argument("make_mesh: one element count per segment between breakpoints expected");
  Mesh mesh;
  const int total = std::accumulate(counts.begin(), counts.end(), 0);
  mesh.nodes.reserve(static_cast<std::size_t>(total) + 1);
  mesh.sizes.reserve(static_cast<std::size_t>(total));
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    const double a = points[i], b = points[i + 1];
    if (!(b > a) || counts[i] < 1) throw std::invalid_argument("make_mesh: breakpoints must increase, counts be >= 1");
    const double h = (b - a) / counts[i];
    for (int j = 0; j < counts[i]; ++j) {
      mesh.nodes.push_back(a + (b - a) * j / counts[i]);
      mesh.sizes.push_back(h);
    }
  }
  mesh.nodes.push_back(points.back());
  return mesh;
}

Mesh make_mesh(const model::MemberModel& model, int requested_elements) {
  const std::vector<double> points = mesh_breakpoints(model);
  return make_mesh(points, apportion_elements(points, requested_elements));
}

}  // namespace liftoff::fe
