// The certificate of von Karman arch answers (certify::certify of a VonKarmanAnswer on an arch):
// it passes on contact::solve_arch_von_karman's answers of the seed's arch (pinned, clamped and
// roller ends, at its load) and each check bites on a spoilt answer: the crown deflection
// perturbed (backward error), a membrane force misreported (compatibility), a reaction made to
// pull (sign), every reaction scaled (balance: the foundation no longer carries the load). The
// spoilings are 1e-6 of the spoilt quantity: far above the tolerances (1e-14 to 1e-9), far
// below what changes the look of the answer.

#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "certify/certificate.hpp"
#include "contact/von_karman_solve.hpp"
#include "fe/discretisation.hpp"
#include "model/from_scene.hpp"
#include "support/scenes.hpp"

using namespace liftoff;

namespace {

struct Solved {
  model::MemberModel model;
  fe::Discretisation d;
  certify::VonKarmanAnswer answer;
};

// The seed's arch (R/h = 500, 10 degrees, k = 1e6, crown load) under von Karman theory, solved at
// its load from zero on 100 elements.
Solved seed_arch(const std::string& ends) {
  Solved s;
  s.model = model::make_member_model(test::shipped_scene("seed_arch_" + ends));
  s.model.theory = model::Theory::von_karman;
  s.d = fe::discretise(s.model, 100);
  const contact::VonKarmanResult r = contact::solve_arch_von_karman(s.model, s.d, 1.0);
  CAPTURE(ends, r.message);
  REQUIRE(r.is_usable());
  s.answer.displacement = s.d.expand_displacement(r.x.head(s.d.equations));
  s.answer.axial = r.u;
  s.answer.reaction = r.reaction;
  s.answer.normal_force = r.normal_force;
  return s;
}

certify::Certificate certify_answer(const Solved& s, const certify::VonKarmanAnswer& answer) {
  certify::CertifyOptions options;
  options.sign_floor = contact::VonKarmanOptions{}.sign_tolerance;
  return certify::certify(s.model, s.d, answer, options);
}

const certify::Check& check(const certify::Certificate& c, std::string_view name) {
  const certify::Check* found = c.find(name);
  REQUIRE(found != nullptr);
  return *found;
}

}  // namespace

TEST_CASE("arch von Karman certificate: the solver's answers pass, the load carried by the foundation and supports",
          "[certify][von_karman][arch]") {
  const std::string ends = GENERATE("pinned", "clamped", "roller");
  const Solved s = seed_arch(ends);
  const certify::Certificate c = certify_answer(s, s.answer);
  CAPTURE(ends, c.message);
  CHECK(c.passed);
  for (std::string_view name :
       {certify::check_name::backward_error, certify::check_name::force_balance_x, certify::check_name::force_balance_y,
        certify::check_name::moment_balance, certify::check_name::membrane_compatibility,
        certify::check_name::reaction_sign, certify::check_name::penetration, certify::check_name::complementarity})
    CHECK(check(c, name).passed);
  // The beam's membrane checks do not apply: N varies along an arch (N' = -Q/R - p_t).
  CHECK(c.find(certify::check_name::membrane_uniform) == nullptr);
  // The resultants the balance reports (user_figures converts them): the crown load toward the
  // foundation, the foundation's reaction carrying most of it.
  CHECK(c.applied_force > 0.0);
  CHECK(c.foundation_resultant > 0.0);
  CHECK(c.support_reactions.size() == 2);
}

TEST_CASE("arch von Karman certificate: each spoilt field fails its check", "[certify][von_karman][arch]") {
  const Solved s = seed_arch("pinned");
  REQUIRE(certify_answer(s, s.answer).passed);
  const int crown = s.d.mesh.elements() / 2;

  SECTION("the crown deflection perturbed: the equations no longer hold") {
    certify::VonKarmanAnswer spoilt = s.answer;
    spoilt.displacement[s.d.deflection_dof(crown)] *= 1.0 + 1e-6;
    const certify::Certificate c = certify_answer(s, spoilt);
    CHECK_FALSE(c.passed);
    CHECK_FALSE(check(c, certify::check_name::backward_error).passed);
  }
  SECTION("a membrane force misreported: compatibility with EA (u' - w + beta^2 / 2)") {
    certify::VonKarmanAnswer spoilt = s.answer;
    spoilt.normal_force[crown] *= 1.0 + 1e-6;
    const certify::Certificate c = certify_answer(s, spoilt);
    CHECK_FALSE(c.passed);
    CHECK_FALSE(check(c, certify::check_name::membrane_compatibility).passed);
    CHECK(check(c, certify::check_name::backward_error).passed);  // the fields still solve the equations
  }
  SECTION("the reported u not the field's") {
    certify::VonKarmanAnswer spoilt = s.answer;
    spoilt.axial[crown / 2] += 1e-6 * spoilt.axial.cwiseAbs().maxCoeff();
    CHECK_FALSE(check(certify_answer(s, spoilt), certify::check_name::membrane_compatibility).passed);
  }
  SECTION("a reaction made to pull: the contact inequalities") {
    certify::VonKarmanAnswer spoilt = s.answer;
    Eigen::Index largest = 0;
    spoilt.reaction.maxCoeff(&largest);
    spoilt.reaction[largest] = -spoilt.reaction[largest];
    const certify::Certificate c = certify_answer(s, spoilt);
    CHECK_FALSE(c.passed);
    CHECK_FALSE(check(c, certify::check_name::reaction_sign).passed);
  }
  SECTION("a lifted-off node made to press: complementarity") {
    certify::VonKarmanAnswer spoilt = s.answer;
    const Eigen::Index lifted = 0;  // the end of the foundation: lifted off (the contact is around the crown)
    REQUIRE(spoilt.reaction[lifted] == 0.0);
    spoilt.reaction[lifted] = 1e-6 * spoilt.reaction.maxCoeff();
    CHECK_FALSE(check(certify_answer(s, spoilt), certify::check_name::complementarity).passed);
  }
  SECTION("every reaction scaled: the foundation no longer balances the load") {
    certify::VonKarmanAnswer spoilt = s.answer;
    spoilt.reaction *= 1.0 + 1e-6;
    const certify::Certificate c = certify_answer(s, spoilt);
    CHECK_FALSE(c.passed);
    CHECK_FALSE(check(c, certify::check_name::force_balance_y).passed);
  }
}
