#include "linalg/banded_lu.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

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

namespace {

// LAPACK's dgbtf2 (the unblocked band LU that dgbtrf runs for kl < 32), operation for
// operation: the pivot is the first entry of largest magnitude in the column, the multipliers
// are scaled by the pivot's reciprocal, and the update is dger's (a + x (-y)). Rows and columns
// 0-based; band row kv = kl + ku holds the diagonal. KL > 0: the band fixed at compile time
// (the loops unrolled); 0: kl given. Returns the first column with a zero pivot, or -1.
template <int KL>
int factorise_band(double* ab, int* pivots, int n, int kl_given, int ku) {
  const int kl = KL > 0 ? KL : kl_given, kv = kl + ku, ld = 2 * kl + ku + 1;
  auto at = [ab, ld](int row, int col) -> double& {
    return ab[static_cast<std::size_t>(col) * static_cast<std::size_t>(ld) + static_cast<std::size_t>(row)];
  };
  // The fill-in rows of the first columns (dgbtf2 zeroes them; the caller may have left values).
  for (int j = ku + 1; j < std::min(kv, n); ++j)
    for (int i = kv - j; i < kl; ++i) at(i, j) = 0.0;
  int ju = 0;  // the last column the current stage affects
  int singular_at = -1;
  for (int j = 0; j < n; ++j) {
    if (j + kv < n)
      for (int i = 0; i < kl; ++i) at(i, j + kv) = 0.0;
    const int km = std::min(kl, n - 1 - j);  // subdiagonal entries of column j
    double* column = &at(kv, j);
    int jp = 0;
    double largest = std::abs(column[0]);
    for (int i = 1; i <= km; ++i)
      if (std::abs(column[i]) > largest) {
        largest = std::abs(column[i]);
        jp = i;
      }
    pivots[j] = j + jp;
    if (column[jp] == 0.0) {
      if (singular_at < 0) singular_at = j;
      continue;
    }
    ju = std::max(ju, std::min(j + ku + jp, n - 1));
    if (jp != 0)  // rows j and j + jp, columns j..ju
      for (int c = 0; c <= ju - j; ++c) std::swap(at(kv + jp - c, j + c), at(kv - c, j + c));
    if (km == 0) continue;
    const double reciprocal = 1.0 / column[0];
    double x[KL > 0 ? KL : 1];  // the multipliers, copied: the updated columns never alias them
    if (KL > 0 && km == KL) {
      for (int i = 0; i < KL; ++i) x[i] = column[1 + i] *= reciprocal;
      for (int c = 1; c <= ju - j; ++c) {
        const double y = at(kv - c, j + c);
        if (y == 0.0) continue;
        const double minus_y = -y;
        double* target = &at(kv - c + 1, j + c);
        for (int i = 0; i < KL; ++i) target[i] += x[i] * minus_y;
      }
      continue;
    }
    for (int i = 1; i <= km; ++i) column[i] *= reciprocal;
    for (int c = 1; c <= ju - j; ++c) {
      const double y = at(kv - c, j + c);
      if (y == 0.0) continue;
      const double minus_y = -y;
      double* target = &at(kv - c + 1, j + c);
      for (int i = 0; i < km; ++i) target[i] += column[1 + i] * minus_y;
    }
  }
  return singular_at;
}

}  // namespace

bool BandedLu::factorise() {
  // Beams (and most meshes of arches' neighbours) have kl = 7: its loops unrolled.
  const int singular_at = kl_ == 7 ? factorise_band<7>(ab_.data(), pivots_.data(), n_, kl_, ku_)
                                   : factorise_band<0>(ab_.data(), pivots_.data(), n_, kl_, ku_);
  factorised_ = singular_at < 0;
  return factorised_;
}

namespace {

// LAPACK's dgbtrs ('N', one right-hand side), operation for operation: L's interchanges and
// multipliers column by column (dger), then U by dtbsv (upper, non-unit, kl + ku superdiagonals).
// KL, KU > 0: the band fixed at compile time for the interior columns.
template <int KL, int KU>
void solve_band(const double* ab, const int* pivots, int n, int kl_given, int ku_given, double* b) {
  const int kl = KL > 0 ? KL : kl_given, kv = kl + (KU > 0 ? KU : ku_given), ld = kv + kl + 1;
  auto column = [ab, ld](int col) { return ab + static_cast<std::size_t>(col) * static_cast<std::size_t>(ld); };
  if (kl > 0)
    for (int j = 0; j + 1 < n; ++j) {
      const int lm = std::min(kl, n - 1 - j), l = pivots[j];
      if (l != j) std::swap(b[l], b[j]);
      if (b[j] == 0.0) continue;
      const double minus_b = -b[j];
      const double* multipliers = column(j) + kv + 1;
      if (KL > 0 && lm == KL)
        for (int i = 0; i < KL; ++i) b[j + 1 + i] += multipliers[i] * minus_b;
      else
        for (int i = 0; i < lm; ++i) b[j + 1 + i] += multipliers[i] * minus_b;
    }
  for (int j = n - 1; j >= 0; --j) {
    if (b[j] == 0.0) continue;
    const double* u = column(j) + kv - j;  // u[i] = U(i, j)
    b[j] /= u[j];
    const double t = b[j];
    if (KL > 0 && j >= KL + KU)
      for (int i = j - 1; i >= j - (KL + KU); --i) b[i] -= t * u[i];
    else
      for (int i = j - 1; i >= std::max(0, j - kv); --i) b[i] -= t * u[i];
  }
}

}  // namespace

void BandedLu::solve(double* b) const {
  if (!factorised_) throw std::logic_error("BandedLu::solve before a successful factorise()");
  if (kl_ == 7 && ku_ == 7)
    solve_band<7, 7>(ab_.data(), pivots_.data(), n_, kl_, ku_, b);
  else
    solve_band<0, 0>(ab_.data(), pivots_.data(), n_, kl_, ku_, b);
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
