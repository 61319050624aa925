// The enums' names come from one table each: every value has a name that reads back to it, and
// the names that reach JSON and HDF5 (a public contract) are spelled as they always were.
#include "core/enum_names.hpp"

#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "contact/active_set_solver.hpp"
#include "contact/contact_solver.hpp"
#include "contact/fitted_limits.hpp"
#include "contact/fitted_refinement.hpp"
#include "continuation/arclength.hpp"
#include "continuation/trace.hpp"
#include "lcp/lemke.hpp"
#include "nonlinear/newton.hpp"
#include "ritz/ritz_solver.hpp"

using namespace liftoff;

namespace {

template <class Enum>
void check_names(const std::vector<std::pair<Enum, std::string>>& contract) {
  for (const auto& [value, name] : contract) {
    CAPTURE(name);
    CHECK(to_string(value) == name);
    const std::optional<Enum> parsed = from_string<Enum>(name);
    REQUIRE(parsed.has_value());
    CHECK(*parsed == value);
  }
  CHECK_FALSE(from_string<Enum>("no_such_name").has_value());
  CHECK_FALSE(from_string<Enum>("").has_value());
}

// For enums written but never read back (to_string only).
template <class Enum>
void check_spelling(const std::vector<std::pair<Enum, std::string>>& contract) {
  for (const auto& [value, name] : contract) {
    CAPTURE(name);
    CHECK(to_string(value) == name);
  }
}

}  // namespace

TEST_CASE("enum names: one table each, read both ways, spelled as the outputs have them", "[core]") {
  using continuation::EventKind;
  check_names<EventKind>({{EventKind::lift_off_opens, "lift_off_opens"},
                          {EventKind::contact_opens, "contact_opens"},
                          {EventKind::region_vanishes, "region_vanishes"},
                          {EventKind::lift_off_vanishes, "lift_off_vanishes"},
                          {EventKind::limit_at_support, "limit_at_support"},
                          {EventKind::limit_at_load, "limit_at_load"},
                          {EventKind::limit_at_end, "limit_at_end"},
                          {EventKind::limit_point, "limit_point"},
                          {EventKind::bifurcation, "bifurcation"}});
  check_names<continuation::Stability>({{continuation::Stability::unknown, "unknown"},
                                        {continuation::Stability::stable, "stable"},
                                        {continuation::Stability::unstable, "unstable"}});
  using continuation::TraceTermination;
  check_names<TraceTermination>({{TraceTermination::completed, "completed"},
                                 {TraceTermination::no_equilibrium, "no_equilibrium"},
                                 {TraceTermination::step_too_small, "step_too_small"},
                                 {TraceTermination::step_limit, "step_limit"},
                                 {TraceTermination::solver_failure, "solver_failure"}});
  check_names<continuation::PathKind>({{continuation::PathKind::fe, "fe"}, {continuation::PathKind::ritz, "ritz"}});
  using contact::ContactTermination;
  check_names<ContactTermination>({{ContactTermination::solved, "solved"},
                                   {ContactTermination::no_equilibrium, "no_equilibrium"},
                                   {ContactTermination::pivot_limit, "pivot_limit"},
                                   {ContactTermination::iteration_limit, "iteration_limit"},
                                   {ContactTermination::numerical_failure, "numerical_failure"}});
  using lcp::LemkeTermination;
  check_names<LemkeTermination>({{LemkeTermination::solution, "solution"},
                                 {LemkeTermination::ray, "ray"},
                                 {LemkeTermination::pivot_limit, "pivot_limit"},
                                 {LemkeTermination::numerical_failure, "numerical_failure"}});
}

TEST_CASE("enum names: the solvers' terminations, from one table each, spelled as the outputs have them", "[core]") {
  using contact::ActiveSetTermination;
  check_spelling<ActiveSetTermination>({{ActiveSetTermination::solved, "solved"},
                                        {ActiveSetTermination::iteration_limit, "iteration_limit"},
                                        {ActiveSetTermination::cycling, "cycling"},
                                        {ActiveSetTermination::singular_system, "singular_system"}});
  using contact::FittedTermination;
  check_spelling<FittedTermination>({{FittedTermination::solved, "solved"},
                                     {FittedTermination::no_convergence, "no_convergence"},
                                     {FittedTermination::topology_changed, "topology_changed"},
                                     {FittedTermination::inequalities_violated, "inequalities_violated"},
                                     {FittedTermination::singular_system, "singular_system"}});
  using contact::ToleranceTermination;
  check_spelling<ToleranceTermination>({{ToleranceTermination::reached, "reached"},
                                        {ToleranceTermination::cap_reached, "cap_reached"},
                                        {ToleranceTermination::round_off, "round_off"},
                                        {ToleranceTermination::fitted_failed, "fitted_failed"}});
  using ritz::RitzTermination;
  check_spelling<RitzTermination>({{RitzTermination::converged, "converged"},
                                   {RitzTermination::newton_failed, "newton_failed"},
                                   {RitzTermination::inequalities_violated, "inequalities_violated"},
                                   {RitzTermination::modes_not_converged, "modes_not_converged"},
                                   {RitzTermination::no_starting_point, "no_starting_point"}});
  using nonlinear::Globalisation;
  check_spelling<Globalisation>({{Globalisation::line_search, "line_search"}, {Globalisation::none, "none"}});
  using nonlinear::NewtonTermination;
  check_spelling<NewtonTermination>({{NewtonTermination::converged, "converged"},
                                     {NewtonTermination::step_below_tolerance, "step_below_tolerance"},
                                     {NewtonTermination::line_search_failed, "line_search_failed"},
                                     {NewtonTermination::iteration_limit, "iteration_limit"},
                                     {NewtonTermination::linear_solver_failed, "linear_solver_failed"},
                                     {NewtonTermination::residual_failed, "residual_failed"},
                                     {NewtonTermination::setup_failed, "setup_failed"},
                                     {NewtonTermination::other_failure, "other_failure"}});
  using continuation::ArcLengthTermination;
  check_spelling<ArcLengthTermination>({{ArcLengthTermination::completed, "completed"},
                                        {ArcLengthTermination::stopped_by_observer, "stopped_by_observer"},
                                        {ArcLengthTermination::step_too_small, "step_too_small"},
                                        {ArcLengthTermination::step_limit, "step_limit"},
                                        {ArcLengthTermination::step_rejected, "step_rejected"},
                                        {ArcLengthTermination::start_failed, "start_failed"},
                                        {ArcLengthTermination::singular_tangent, "singular_tangent"}});
}
