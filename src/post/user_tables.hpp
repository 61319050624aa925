#pragma once
// Fields and design values in the user's units: what `liftoff solve` reports (io/report.hpp) and
// what every step of `liftoff trace` records (continuation/result.hpp), one type for both.
// Plain data (no numerics): post/fields.hpp and post/design.hpp convert to them.
//
// Units and signs (io/report.hpp's): coordinate x (length) or theta in degrees (arches); w and u
// (length), w > 0 into the foundation, u toward increasing x or theta; rotation counterclockwise
// (radians); bending moment sagging positive; shear force (force); normal force tension positive
// (force); reaction, the foundation's, compression positive (force per length); gap, the open gap
// g - w between the member and the ground where the member has lifted off (length; 0 in contact
// and off the foundation).

#include <optional>
#include <vector>

namespace liftoff::post {

struct FieldTable {
  std::vector<double> coordinate, w, u, rotation, bending_moment, shear_force, normal_force, reaction;
  // Trace steps: the gap g - w where lifted off (see above); empty in a solve's report.
  std::vector<double> gap;
  // Nodes of a beam with an initial shape (solve): w0 there (length units), so that w + w_initial
  // is the total displacement from the straight line (w is measured from the stress-free shape).
  std::vector<double> w_initial;
  // Nodes of a beam under an axial force whose critical load was computed (solve): the buckling
  // mode's w (io::StabilityTable), max |w| = 1, w > 0 into the foundation; nondimensional.
  std::vector<double> buckling_mode;
  bool empty() const { return coordinate.empty(); }
};

// The design values (post/design.hpp) in the user's units: moments, shears, pressure (force per
// length), uplift (length); `at` in the user's coordinate, none where there is no such point.
struct DesignValue {
  double value = 0.0;
  std::optional<double> at;
};
struct DesignTable {
  DesignValue moment_max, moment_min, shear_max_abs, pressure_max, uplift_max;
  double shear_closure = -1.0, moment_closure = -1.0;  // relative; -1: not from statics
  bool from_statics = false;
};

}  // namespace liftoff::post
