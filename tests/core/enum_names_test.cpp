// The enums' names come from one table each: every value has a name that reads back to it, and
// the names that reach JSON and HDF5 (a public contract) are spelled as they always were.
#include "core/enum_names.hpp"

#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "contact/contact_solver.hpp"
#include "continuation/trace.hpp"
#include "lcp/lemke.hpp"

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
                          {EventKind::limit_point, "limit_point"}});
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
