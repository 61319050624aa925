// The certificate of von Karman FE answers (certify::certify of a VonKarmanAnswer): it passes on
// the solver's answers (a restrained straight beam on a bilateral and on a tensionless foundation,
// a beam with one end axially free, the issue 16 shallow arch lifted off on half its length) and
// catches each kind of spoilt answer: a membrane force perturbed (compatibility), a deflection
// perturbed (backward error), the axial displacement perturbed (N no longer uniform), a reaction
// made to pull (sign), an end's N made nonzero where it is free. The spoilings are 1e-6 of the
// spoilt quantity, far above the tolerances (1e-14 to 1e-9) and far below what changes the look.

#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "certify/certificate.hpp"
#include "contact/von_karman_loading.hpp"
#include "contact/von_karman_solve.hpp"
#include "fe/discretisation.hpp"
#include "model/member_model.hpp"

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

Solved solve(const model::MemberModel& m, int elements = 64) {
  Solved s{m, fe::discretise(m, elements), {}};
  const contact::VonKarmanSystem system(s.model, s.d);
  const Eigen::VectorXd dead = system.load(0.0), live = system.load(1.0) - dead;
  const contact::VonKarmanLoadingResult r = contact::load_from_zero(system, dead, live);
  REQUIRE(r.is_usable());
  s.answer.displacement = s.d.expand_displacement(r.result.x.head(s.d.equations));
  s.answer.axial = r.result.u;
  s.answer.reaction = r.result.reaction;
  s.answer.normal_force = r.result.normal_force;
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
