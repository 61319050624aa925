#pragma once
// Where a Ritz solve starts: the topology (which pieces of the foundation are in contact) and
// initial limits, either as the scene's [ritz] table gives them (ritz/from_scene.hpp, the
// boundary) or read off the contact regions of an FE + LCP solution of the same member. Shared by
// `liftoff solve --method ritz` and the Ritz load history, which both start this way.

#include <vector>

#include "model/member_model.hpp"
#include "ritz/ritz_model.hpp"

namespace liftoff::ritz {

struct StartingPoint {
  Topology topology;
  std::vector<double> limits;  // s
};

// The topology of contact regions (intervals of s with members `begin` and `end`, as
// post::contact_regions returns them): limits within 1e-9 of the member's length of a
// foundation end are that end, not a limit.
template <class Intervals>
StartingPoint starting_point_from_regions(const Intervals& regions, const model::MemberModel& model) {
  StartingPoint start;
  const double begin = model.foundation_begin, end = model.foundation_end, edge = 1e-9 * model.length();
  start.topology.first_in_contact = !regions.empty() && regions.front().begin <= begin + edge;
  for (const auto& region : regions)
    for (double limit : {region.begin, region.end})
      if (limit > begin + edge && limit < end - edge) start.limits.push_back(limit);
  start.topology.limits = static_cast<int>(start.limits.size());
  return start;
}

// A topology given as its pieces in order (true = contact; at least one) with the limits' guesses
// in the user coordinate (evenly spaced where none are given, or not one per change of piece).
inline StartingPoint starting_point_from_pieces(const std::vector<bool>& pieces, const std::vector<double>& limits,
                                                const model::MemberModel& model) {
  StartingPoint start;
  start.topology = {pieces.front(), static_cast<int>(pieces.size()) - 1};
  for (double limit : limits) start.limits.push_back(model.s_from_user(limit));
  const double begin = model.foundation_begin, end = model.foundation_end;
  if (start.limits.empty())  // evenly spaced guesses
    for (int m = 0; m < start.topology.limits; ++m)
      start.limits.push_back(begin + (end - begin) * (m + 1) / (start.topology.limits + 1));
  if (static_cast<int>(start.limits.size()) != start.topology.limits) start.limits.clear();
  return start;
}

}  // namespace liftoff::ritz
