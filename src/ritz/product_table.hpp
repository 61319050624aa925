#pragma once
// The integrals over [a, b] of all pairwise products f_i g_j of two families of TrigPolynomials,
// cheap enough to redo at every Newton step (the contact Gram matrix over moving limits).
//
// The products of a Ritz family share few distinct terms: sin(i pi xi) sin(j pi xi) for all
// i, j uses only the 2N + 1 cosines cos(k pi xi). So the table is built once, by the product-to-
// sum rules of TrigPolynomial's operator*, as ATOMS (the distinct terms s^p cos(omega s) and
// s^p sin(omega s), frequencies merged to a relative 1e-13 as TrigPolynomial does) and, per
// pair, the coefficients of its atoms. An integral over [a, b] then integrates each atom once
// and sums the coefficients: O(atoms) transcendental functions instead of O(N^2 terms). The
// values equal (f_i * g_j).integral(a, b) up to round-off.

#include <Eigen/Dense>
#include <vector>

#include "ritz/trig_polynomial.hpp"

namespace liftoff::ritz {

class ProductTable {
 public:
  ProductTable() = default;
  // All products left[i] * right[j].
  ProductTable(const std::vector<TrigPolynomial>& left, const std::vector<TrigPolynomial>& right);
  // Symmetric: the products f[i] * f[j] with i <= j only (the upper triangle).
  explicit ProductTable(const std::vector<TrigPolynomial>& f);

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  bool symmetric() const { return symmetric_; }
  int atoms() const { return static_cast<int>(atoms_.size()); }

  // g(i, j) += factor * integral over [a, b] of left[i] right[j], g sized rows x cols; for a
  // symmetric table the upper triangle (i <= j) only.
  void add_integrals(double a, double b, double factor, Eigen::MatrixXd& g) const;

 private:
  void build(const std::vector<TrigPolynomial>& left, const std::vector<TrigPolynomial>& right);

  int rows_ = 0;
  int cols_ = 0;
  bool symmetric_ = false;
  std::vector<TrigTerm> atoms_;  // coefficient 1
  // Pair k (row-major over the stored pairs) has the atoms atom_[begin_[k] .. begin_[k + 1]).
  std::vector<int> begin_;
  std::vector<int> atom_;
  std::vector<double> coefficient_;
};

}  // namespace liftoff::ritz
