#pragma once
// A one-dimensional mesh of the member coordinate s.
//
// Every point where something happens (a point load or support, the ends of a uniform load or
// of the foundation) is a node, so point loads act at nodes and no element straddles a jump in
// the data. The requested number of elements is shared among the segments between those points
// in proportion to their lengths (at least one each), so a uniform mesh stays uniform when the
// points fall on it.

#include <vector>

#include "fe/member_model.hpp"

namespace liftoff::fe {

struct Mesh {
  std::vector<double> nodes;  // strictly increasing s
  int elements() const { return static_cast<int>(nodes.size()) - 1; }
  double element_size(int element) const { return nodes[element + 1] - nodes[element]; }
  // Index of the node at s (a breakpoint); -1 if there is none within round-off.
  int node_at(double s) const;
  // Element containing s (the left one at a node), clamped to the mesh.
  int element_containing(double s) const;
};

// The points the mesh must contain for this member (ends included), sorted and unique.
std::vector<double> mesh_breakpoints(const MemberModel& model);

Mesh make_mesh(const MemberModel& model, int requested_elements);

}  // namespace liftoff::fe
