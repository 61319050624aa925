#pragma once
// Before any LCP: can compressive foundation reactions balance the loads at all?
//
// A member whose supports leave rigid motions that only the foundation resists (a free-free
// beam, a beam on one pin, a free arch) is in equilibrium only if the loads' work on those
// motions is the work of some foundation reaction r >= 0. This is decided here from the
// resultant alone, in microseconds, instead of by a solver that runs into its iteration limit
// or a Lemke ray after thousands of pivots. The proof (necessity, and sufficiency for the
// elastic member) is in resultant_check.cpp. Beams: the net load must press into the
// foundation and its line of action must fall inside the foundation's extent (strictly, for
// the reaction k w+ has a density); with one pin, the loads' moment about it must press the
// member into the foundation where the foundation is.

#include <string>

#include "fe/discretisation.hpp"
#include "model/member_model.hpp"

namespace liftoff::certify {

struct ResultantCheck {
  bool applies = false;   // the supports leave rigid motions only the foundation resists
  bool balanced = true;   // false: no equilibrium exists; `message` gives the figures
  int rigid_motions = 0;  // how many such motions
  std::string message;    // user units; empty when balanced
};

// For the load F_dead + load_factor F_live. A bilateral foundation (it pulls too) always applies
// = false.
ResultantCheck check_resultant(const model::MemberModel& model, const fe::Discretisation& discretisation,
                               double load_factor = 1.0);

}  // namespace liftoff::certify
