// The certificate of von Karman FE answers (certify::certify of a VonKarmanAnswer): it passes on
// the solver's answers (a restrained straight beam on a bilateral and on a tensionless foundation,
// a beam with one end axially free, the issue 16 shallow arch lifted off on half its length) and
// catches each kind of spoilt answer: a membrane force perturbed (compatibility), a deflection
// perturbed (backward error), the axial displacement perturbed (N no longer uniform), a reaction
// made to pull (sign), an end's N made nonzero where it is free. The spoilings are 1e-6 of the
// spoilt quantity, far above the tolerances (1e-14 to 1e-9) and far below what changes the look.
// Arches (the Marguerre/Donnell element): the solver's answers of the seed's arch (pinned, clamped,
// roller ends) pass, and each check bites: the crown deflection perturbed (backward error), a
// membrane force misreported and u not the field's (compatibility), a reaction made to pull
// (sign), a lifted-off node made to press (complementarity), every reaction scaled (balance).

#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "certify/certificate.hpp"
#include "contact/von_karman_loading.hpp"
#include "contact/von_karman_solve.hpp"
#include "fe/discretisation.hpp"
#include "model/from_scene.hpp"
#include "model/member_model.hpp"
#include "support/scenes.hpp"

using namespace liftoff;

namespace {

// A pinned beam, L = 1, EI = 1, von Karman, EA = 1e4, on k = 100, under a uniform load q over
// [from, to]; w0 = -rise sin(pi s).
model::MemberModel member(bool tensionless, double q, double from, double to, double rise = 0.0,
                          bool right_held = true) {
  model::MemberModel m;
  m.kind = model::StructureKind::beam;
  m.theory = model::Theory::von_karman;
  m.membrane_stiffness = 1e4;
  m.k = 100;
  m.tensionless = tensionless;
  m.right_axially_restrained = right_held;
  if (rise != 0.0) m.initial_sine = model::MemberModel::InitialSine{-rise, 0.0, 1.0};
  model::MemberLoad load;
  load.kind = model::LoadKind::uniform;
  load.from = from;
  load.to = to;
  load.value = q;
  load.load_case = model::LoadCase::live;
  m.loads.push_back(load);
  return m;
}

struct Solved {
  model::MemberModel model;
  fe::Discretisation d;
  certify::VonKarmanAnswer answer;
};

// The answer as `liftoff solve` reports it.
certify::VonKarmanAnswer answer_of(const fe::Discretisation& d, const contact::VonKarmanResult& r) {
  return {d.expand_displacement(r.x.head(d.equations)), r.u, r.reaction, r.normal_force};
}

Solved solve(const model::MemberModel& m, int elements = 64) {
  Solved s{m, fe::discretise(m, elements), {}};
  const contact::VonKarmanSystem system(s.model, s.d);
  const Eigen::VectorXd dead = system.load(0.0), live = system.load(1.0) - dead;
  const contact::VonKarmanLoadingResult r = contact::load_from_zero(system, dead, live);
  REQUIRE(r.is_usable());
  s.answer = answer_of(s.d, r.result);
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
  s.answer = answer_of(s.d, r);
  return s;
}

}  // namespace

TEST_CASE("von Karman certificate: the solver's answers pass, with the thrust among the support reactions",
          "[certify][von_karman]") {
  struct Case {
    const char* name;
    model::MemberModel model;
  };
  const std::vector<Case> cases = {
      {"straight, bilateral", member(false, 10, 0, 1)},
      {"straight, tensionless", member(true, 10, 0, 1)},
      {"right end axially free", member(true, 10, 0, 1, 0.0, false)},
      {"shallow arch, half loaded", member(true, 21, 0, 0.5, 0.06)},
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    const Solved s = solve(c.model);
    const certify::Certificate cert = certify_answer(s, s.answer);
    CAPTURE(cert.message);
    CHECK(cert.passed);
    const bool free_end = !c.model.right_axially_restrained;
    CHECK((cert.find(certify::check_name::membrane_free_end) != nullptr) == free_end);
    REQUIRE(cert.support_reactions.size() == 2);
    const double n = s.answer.normal_force.front();
    // Held ends: -N at the begin, +N at the end (along +x); a free end carries none.
    CHECK(cert.support_reactions.front().tangential == Approx(-n).epsilon(1e-9));
    if (free_end)
      CHECK(cert.support_reactions.back().tangential == 0.0);
    else
      CHECK(cert.support_reactions.back().tangential == Approx(n).epsilon(1e-9));
    if (free_end) CHECK(std::abs(n) <= 1e-9);
    // Vertical equilibrium in user terms: supports + foundation = applied.
    const double supports = cert.support_reactions.front().force + cert.support_reactions.back().force;
    CHECK(supports + cert.foundation_resultant == Approx(cert.applied_force).epsilon(1e-10));
  }
}

TEST_CASE("von Karman certificate: each spoilt field fails its check", "[certify][von_karman]") {
  const Solved s = solve(member(true, 21, 0, 0.5, 0.06));
  REQUIRE(certify_answer(s, s.answer).passed);
  const double spoil = 1e-6;
  {  // the reported membrane force of one element
    certify::VonKarmanAnswer a = s.answer;
    a.normal_force[10] *= 1 + spoil;
    const certify::Certificate c = certify_answer(s, a);
    CHECK_FALSE(c.passed);
    CHECK_FALSE(check(c, certify::check_name::membrane_compatibility).passed);
  }
  {  // every reported N scaled: the mean no longer meets EA/L integral (w0' w' + w'^2 / 2)
    certify::VonKarmanAnswer a = s.answer;
    for (double& n : a.normal_force) n *= 1 + spoil;
    CHECK_FALSE(check(certify_answer(s, a), certify::check_name::membrane_compatibility).passed);
  }
  {  // a deflection
    certify::VonKarmanAnswer a = s.answer;
    a.displacement[s.d.deflection_dof(20)] *= 1 + spoil;
    const certify::Certificate c = certify_answer(s, a);
    CHECK_FALSE(c.passed);
    CHECK_FALSE(check(c, certify::check_name::backward_error).passed);
  }
  {  // an axial displacement: N jumps between two elements
    certify::VonKarmanAnswer a = s.answer;
    a.axial[30] += spoil * a.axial.cwiseAbs().maxCoeff();
    const certify::Certificate c = certify_answer(s, a);
    CHECK_FALSE(check(c, certify::check_name::membrane_uniform).passed);
  }
  {  // a reaction that pulls at a lifted node (not the support at x = 1, whose w is held)
    certify::VonKarmanAnswer a = s.answer;
    int lifted = -1;
    for (int i = 0; i < s.d.reactions(); ++i)
      if (const double x = s.d.mesh.nodes[s.d.reaction_nodes[i]]; a.reaction[i] == 0.0 && x > 0.8 && x < 0.95)
        lifted = i;
    REQUIRE(lifted >= 0);
    a.reaction[lifted] = -spoil * a.reaction.cwiseAbs().maxCoeff();
    CHECK_FALSE(check(certify_answer(s, a), certify::check_name::reaction_sign).passed);
  }
}

TEST_CASE("von Karman certificate: a free end's membrane force must vanish", "[certify][von_karman]") {
  const Solved s = solve(member(true, 10, 0, 1, 0.0, false));
  certify::VonKarmanAnswer a = s.answer;
  // u shifted at the free end: that element's N is no longer 0.
  a.axial[a.axial.size() - 1] += 1e-6;
  const certify::Certificate c = certify_answer(s, a);
  CHECK_FALSE(check(c, certify::check_name::membrane_free_end).passed);
}

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
