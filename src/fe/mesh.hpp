#pragma once
// A one-dimensional mesh of the member coordinate s.
//
// Every point where something happens (a point load or support, the ends of a uniform or
// curvature load, the points of a distributed load's table, the ends of the foundation and of each
// of its pieces, the points of the ground-gap table) is a node, so point loads act at nodes and no element straddles a
// jump in the data. The requested number of elements is shared among the segments between those points in proportion to
// their lengths (at least one each), so a uniform mesh stays uniform when the points fall on it.
//
// Element sizes are stored, not taken as differences of node coordinates: every element of a
// segment has the size (b - a) / count, computed once, so their matrices are bitwise identical
// and the rounding of the element data is the same in every element of the segment. Differences
// of rounded coordinates differ from element to element by eps |s| / h relative (eps N), and
// that random perturbation of the Hermite stiffness alone moved a bilateral beam's deflection by
// 8.3e-5 at 1e4 elements (2.7e-9 with the stored sizes; verification/bench/accuracy_bench.cpp).

#include <vector>

#include "model/member_model.hpp"

namespace liftoff::fe {

struct Mesh {
  std::vector<double> nodes;  // strictly increasing s
  std::vector<double> sizes;  // one per element (empty: differences of the nodes)
  int elements() const { return static_cast<int>(nodes.size()) - 1; }
  double element_size(int element) const {
    return sizes.empty() ? nodes[element + 1] - nodes[element] : sizes[element];
  }
  // Index of the node at s (a breakpoint); -1 if there is none within round-off.
  int node_at(double s) const;
  // Element containing s (the left one at a node), clamped to the mesh.
  int element_containing(double s) const;
};

// The points the mesh must contain for this member (ends included), sorted and unique.
std::vector<double> mesh_breakpoints(const model::MemberModel& model);

// Elements per segment between consecutive breakpoints: `total` shared in proportion to the
// segment lengths (largest remainders), at least one each.
std::vector<int> apportion_elements(const std::vector<double>& breakpoints, int total);

// Uniform elements of size (b - a) / count on each segment [b_i, b_i+1].
Mesh make_mesh(const std::vector<double>& breakpoints, const std::vector<int>& counts);

Mesh make_mesh(const model::MemberModel& model, int requested_elements);

}  // namespace liftoff::fe
