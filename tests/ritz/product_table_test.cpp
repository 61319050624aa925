// ProductTable: its integrals of pairwise products against TrigPolynomial's own products and
// integrals, for a Ritz-like family (shared frequencies), a family with powers and phases, and
// the two shapes (full and symmetric).
#include "ritz/product_table.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <vector>

using namespace liftoff::ritz;

namespace {

constexpr double pi = std::numbers::pi;

// The table's values are the same exact integrals summed in another order (like terms merged
// across all products rather than within one): they agree to a few eps of the integral of
// |f g| term by term, bounded here by sum |c| X^(p+1) over the product's terms.
double round_off_bound(const TrigPolynomial& product, double a, double b) {
  const double x = std::max(std::abs(a), std::abs(b));
  double sum = 0.0;
  for (const TrigTerm& t : product.terms()) sum += std::abs(t.coefficient) * std::pow(x, t.power + 1);
  return 64 * 2.2e-16 * (1.0 + sum);
}

void check_against_products(const std::vector<TrigPolynomial>& left, const std::vector<TrigPolynomial>& right,
                            bool symmetric, double a, double b) {
  const ProductTable table = symmetric ? ProductTable(left) : ProductTable(left, right);
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(left.size(), right.size());
  table.add_integrals(a, b, -2.0, g);
  for (std::size_t i = 0; i < left.size(); ++i)
    for (std::size_t j = symmetric ? i : 0; j < right.size(); ++j) {
      const TrigPolynomial product = left[i] * right[j];
      CHECK(std::abs(g(i, j) + 2.0 * product.integral(a, b)) <= 2.0 * round_off_bound(product, a, b));
    }
  if (symmetric)  // the lower triangle is left alone
    for (std::size_t i = 1; i < left.size(); ++i) CHECK(g(i, 0) == 0.0);
}

}  // namespace

TEST_CASE("product table: sine family, few shared atoms, exact integrals", "[ritz][product]") {
  std::vector<TrigPolynomial> f;
  for (int j = 1; j <= 24; ++j) f.push_back(TrigPolynomial::sine(j * pi / 1.7));
  const ProductTable table(f);
  // sin(i w s) sin(j w s) uses only cos(k w s), k = 0..48: the atoms are shared.
  CHECK(table.atoms() <= 49);
  check_against_products(f, f, true, 0.0, 1.7);
  check_against_products(f, f, true, 0.31, 0.92);
  // Orthogonality over the whole span: int sin(i w s) sin(j w s) = delta_ij 1.7/2.
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(24, 24);
  table.add_integrals(0.0, 1.7, 1.0, g);
  for (int i = 0; i < 24; ++i)
    for (int j = i; j < 24; ++j) CHECK(g(i, j) == Approx(i == j ? 0.85 : 0.0).margin(1e-14));
}

TEST_CASE("product table: powers, phases and two families", "[ritz][product]") {
  std::vector<TrigPolynomial> left, right;
  for (int j = 0; j < 6; ++j) {
    left.push_back(TrigPolynomial::cosine(1.3 * j, 0.4 * j) + TrigPolynomial::monomial(j % 3, 0.5));
    right.push_back(TrigPolynomial::sine(2.1 * j + 0.5, -0.2) * TrigPolynomial::monomial(1 + j % 2));
  }
  check_against_products(left, right, false, -0.8, 1.4);
  check_against_products(left, left, true, -0.8, 1.4);
  check_against_products(left, right, false, 0.2, 0.2);  // an empty interval: zero
}
