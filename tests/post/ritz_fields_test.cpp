// The Ritz answer's post-processing: its fields are its model's series at uniform samples, its
// contact regions its model's contact pieces, and its beam statics replace V and M at those
// samples.
#include "post/ritz_fields.hpp"

#include <catch2/catch.hpp>
#include <cmath>

#include "model/from_scene.hpp"
#include "support/scenes.hpp"

using namespace liftoff;

TEST_CASE("ritz fields: the model's series at uniform samples, its pieces as contact regions", "[post]") {
  const scene::Scene s = test::shipped_scene("seed_beam_end_moments_central_load");
  const model::MemberModel member = model::make_member_model(s);
  ritz::RitzSolution solution;
  solution.model.emplace(member, 16, ritz::Topology{true, 2});
  const double length = member.s_end - member.s_begin;
  Eigen::VectorXd limits(2);
  limits << member.s_begin + 0.3 * length, member.s_begin + 0.7 * length;
  const std::optional<Eigen::VectorXd> x = solution.model->minimiser_for_limits(limits, 1.0);
  REQUIRE(x.has_value());
  solution.unknowns = *x;
  const ritz::RitzModel& model = *solution.model;

  const int samples = 41;
  const post::Fields f = post::sample_fields(member, solution, samples);
  REQUIRE(f.s.size() == samples);
  CHECK(f.s.front() == member.s_begin);
  CHECK(std::abs(f.s.back() - member.s_end) <= 1e-15 * length);
  CHECK(f.u.empty());  // a beam
  for (int i = 0; i < samples; ++i) {
    CHECK(f.w[i] == model.w(*x, f.s[i]));
    CHECK(f.rotation[i] == -model.w(*x, f.s[i], 1));
    CHECK(f.bending_moment[i] == -model.w(*x, f.s[i], 2));
    CHECK(f.reaction[i] == model.reaction(*x, f.s[i]));
  }

  const std::vector<ContactRegion> regions = post::contact_regions(solution);
  const std::vector<ContactRegion> pieces = model.contact_pieces(*x);
  REQUIRE(regions.size() == pieces.size());
  for (std::size_t i = 0; i < regions.size(); ++i) {
    CHECK(regions[i].begin == pieces[i].begin);
    CHECK(regions[i].end == pieces[i].end);
  }
  CHECK(post::contact_regions(ritz::RitzSolution{}).empty());

  post::Fields statics;
  post::ritz_beam_statics(member, solution, {}, 1.0, samples, statics);
  REQUIRE(statics.s == f.s);
  CHECK(statics.w == f.w);  // only V and M are replaced
}
