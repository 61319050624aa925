#include "linalg/banded_lu.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

extern "C" {
void dgbtrf_(const int* m, const int* n, const int* kl, const int* ku, double* ab, const int* ldab, int* ipiv,
             int* info);
void dgbtrs_(const char* trans, const int* n, const int* kl, const int* ku, const int* nrhs, const double* ab,
             const int* ldab, const int* ipiv, double* b, const int* ldb, int* info, std::size_t trans_length);
}

namespace liftoff::linalg {

void BandedLu::set_structure(int n, int lower, int upper) {
  if (n < 0 || lower < 0 || upper < 0) throw std::invalid_argument("BandedLu::set_structure: negative size or band");
  n_ = n;
  kl_ = lower;
  ku_ = upper;
  ldab_ = 2 * kl_ + ku_ + 1;
  ab_.assign(static_cast<std::size_t>(ldab_) * static_cast<std::size_t>(std::max(n_, 1)), 0.0);
  pivots_.assign(std::max(n_, 1), 0);
  factorised_ = false;
}

void BandedLu::clear() {
  std::fill(ab_.begin(), ab_.end(), 0.0);
  factorised_ = false;
}

bool BandedLu::factorise() {
  int info = 0;
  if (n_ > 0) dgbtrf_(&n_, &n_, &kl_, &ku_, ab_.data(), &ldab_, pivots_.data(), &info);
  if (info < 0) throw std::logic_error("BandedLu::factorise: dgbtrf rejected its arguments");
  factorised_ = info == 0;
  return factorised_;
}

void BandedLu::solve(double* b) const {
  if (!factorised_) throw std::logic_error("BandedLu::solve before a successful factorise()");
  if (n_ == 0) return;
  const int one = 1;
  int info = 0;
  dgbtrs_("N", &n_, &kl_, &ku_, &one, ab_.data(), &ldab_, pivots_.data(), b, &n_, &info, 1);
  if (info != 0) throw std::logic_error("BandedLu::solve: dgbtrs rejected its arguments");
}

double BandedLu::smallest_pivot() const {
  double smallest = INFINITY;
  for (int j = 0; j < n_; ++j) smallest = std::min(smallest, std::abs(ab_[index(j, j)]));
  return smallest;
}

double BandedLu::largest_pivot() const {
  double largest = 0.0;
  for (int j = 0; j < n_; ++j) largest = std::max(largest, std::abs(ab_[index(j, j)]));
  return largest;
}

}  // namespace liftoff::linalg
