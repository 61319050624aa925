#pragma once
// The contact topology of an FE deflection, and the events that turn one topology into another.
//
// The topology is what a load history reports as events: the foundation's extent cut into
// alternating contact (w > 0) and lift-off pieces, and, for every contact limit, which of the
// intervals between the special points (interior point supports and point loads) it lies in.
// A limit moving from one element to the next changes nothing here; a piece opening or
// vanishing, or a limit crossing a special point or reaching an end, does.
//
// The model places a contact limit to within an element, and no finer where a piece opens or
// vanishes: a piece that lies inside the two elements next to a point load opens (or vanishes)
// at that load, and counts as straddling it. Where the exact piece opens at the load (the
// load's side of a symmetric member), the discrete one opens a discretisation error away from
// it, on the side where the mesh is coarser, and its limit crosses the load at once: that is no
// event of its own (region_split at an odd number of elements).
//
// Contact is decided on the element cubics, exactly: w is sampled at the nodes and at the
// interior extrema of every element's cubic, between which w is monotone, so a lift-off zone
// opening inside an element is seen as soon as w dips below zero (post::contact_regions, which
// looks for sign changes on a fixed grid of brackets, sees it only once the zone spans a
// bracket point; its limits are what steps report).

#include <Eigen/Dense>
#include <vector>

#include "continuation/trace.hpp"
#include "core/contact_region.hpp"
#include "fe/discretisation.hpp"
#include "model/member_model.hpp"

namespace liftoff::continuation {

// A contact or lift-off piece of the topology (region in s), and the point load it straddles.
struct Piece {
  ContactRegion region;
  int at_load = -1;  // index in SpecialPoints::interior of the point load it lies next to, or -1
};

// Points of the foundation's extent at which a contact limit arriving is an event.
struct SpecialPoints {
  double begin = 0.0, end = 0.0;  // the foundation's extent (s)
  bool begin_supported = false;   // a support holds w = 0 at that end of the foundation
  bool end_supported = false;
  std::vector<double> interior;  // point supports and point loads strictly inside, sorted
  std::vector<bool> is_support;  // per interior point: support (true) or point load
};
SpecialPoints special_points(const model::MemberModel& model);

struct ContactTopology {
  std::vector<Piece> pieces;     // in order along the foundation; empty without a foundation
  std::vector<int> limit_slots;  // per interior limit: how many interior special points lie before it
  bool same_as(const ContactTopology& other) const;
};

// displacement on every dof (nondimensional). A bilateral foundation is one contact piece.
ContactTopology contact_topology(const model::MemberModel& model, const fe::Discretisation& d,
                                 const Eigen::VectorXd& displacement, const SpecialPoints& points);

// The beam-column measures of a step (TraceStep::amplitude, lifted_length), in the user's units:
// the largest lift of the member off the foundation surface, max of g - w over the foundation's
// extent (sampled at the nodes and the element cubics' extrema, where it peaks; 0 where nothing
// lifts), and the total length of the topology's lift-off pieces (user coordinate).
struct LiftMeasures {
  double amplitude = 0.0;
  double lifted_length = 0.0;
};
LiftMeasures lift_measures(const model::MemberModel& model, const fe::Discretisation& d,
                           const Eigen::VectorXd& displacement, const SpecialPoints& points);

// The events between two topologies on either side of one change (at load factor
// `load_factor`), with positions in the user's coordinate.
std::vector<TraceEvent> classify_events(const model::MemberModel& model, const SpecialPoints& points,
                                        const ContactTopology& before, const ContactTopology& after,
                                        double load_factor);

}  // namespace liftoff::continuation
