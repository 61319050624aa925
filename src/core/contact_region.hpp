#pragma once
// A contact region: one interval [begin, end] of the member's axis and whether the member presses
// into the foundation there (in_contact) or has lifted off it. The one type for contact regions
// everywhere: the FE answer's regions (post::contact_regions), the Ritz model's pieces, the trace's
// contact topology and the reports.
//
// The type does not fix the coordinate; whoever holds regions says which: the numerics (post,
// ritz, continuation) hold s, the nondimensional arc length; what reaches the outputs
// (io::SolveReport, continuation::TraceStep) holds the user's coordinate (x, or theta in degrees on an
// arch). The writers turn a region into the pair [begin, end] (JSON, HDF5 rows of two, CSV), so
// the files' layout does not depend on this type.

namespace liftoff {

struct ContactRegion {
  double begin = 0.0;
  double end = 0.0;
  bool in_contact = true;
  double length() const { return end - begin; }
  bool operator==(const ContactRegion&) const = default;  // exact: round trips through the files
};

}  // namespace liftoff
