#pragma once
// LU factorisation with partial pivoting of a banded matrix: LAPACK's dgbtf2 / dgbtrs algorithm,
// operation for operation (same pivots, same factors; tests/linalg/banded_lu_test.cpp compares
// them with LAPACK's), written out here rather than called.
//
// Why not LAPACK: at the bands of a member (kl = ku = 7) dgbtf2 makes four BLAS calls per column
// (idamax, dswap, dscal, dger) on vectors of at most 14 entries, and dgbtrs two more per column;
// with the reference BLAS Debian installs by default the call overhead is most of the time. The
// loops below factorise and solve a 160-element beam's system (673 unknowns) 1.3-2x faster than
// dgbtrf / dgbtrs with libblas3 (the mixed systems' zeros inside the band skip whole updates),
// and as fast at 1e6 elements, where memory traffic sets the pace (measured in-process).
//
// Why partial pivoting: the mixed (Hellinger-Reissner) systems of contact::ActiveSetSystem have
// a zero block (no K) and are indefinite, so an LDL^T without pivoting would have to eliminate
// the stresses first, i.e. form K again with its N^4 condition. Row interchanges keep the
// factorisation backward stable on the mixed matrix itself (condition ~N^2). A member is a
// one-dimensional chain, so with its unknowns numbered along it the bandwidth is a small
// constant (7 for beams): storage and work are O(n), (2 kl + ku + 1) doubles per unknown.
//
// Use: set_structure once, then per matrix: clear(), set(i, j, value) for the entries inside the
// band, factorise(), and any number of solve() calls. Nothing allocates after set_structure.

#include <algorithm>
#include <cstddef>
#include <vector>

namespace liftoff::linalg {

class BandedLu {
 public:
  // An n x n matrix with kl sub- and ku superdiagonals.
  void set_structure(int n, int lower, int upper);
  int size() const { return n_; }
  int lower() const { return kl_; }
  int upper() const { return ku_; }

  void clear();  // every entry (and the factor's fill) to zero
  // Column col's entries and fill to zero: a caller that sets a matrix column by column clears
  // each just before (one pass over the storage instead of two; at 1e6 elements it is 700 MB).
  void clear_column(int col) {
    std::fill_n(ab_.begin() + static_cast<std::ptrdiff_t>(col) * ldab_, ldab_, 0.0);
    factorised_ = false;
  }
  void set(int row, int col, double value) { ab_[index(row, col)] = value; }

  // False when a pivot is exactly zero (the matrix is singular); the factors are then unusable.
  bool factorise();
  bool factorised() const { return factorised_; }
  // Overwrites b (length n) with A^-1 b.
  void solve(double* b) const;
  // Smallest and largest |pivot| of U (after factorise).
  double smallest_pivot() const;
  double largest_pivot() const;
  // The factors in LAPACK band storage (column-major, 2 kl + ku + 1 rows) and the row each
  // column's pivot came from (0-based; LAPACK's ipiv minus 1): for comparison with dgbtrf.
  const std::vector<double>& band_storage() const { return ab_; }
  int pivot_row(int col) const { return pivots_[col]; }

 private:
  std::size_t index(int row, int col) const {
    return static_cast<std::size_t>(col) * ldab_ + static_cast<std::size_t>(kl_ + ku_ + row - col);
  }
  int n_ = 0, kl_ = 0, ku_ = 0, ldab_ = 1;
  std::vector<double> ab_;  // LAPACK band storage, column-major, ldab = 2 kl + ku + 1 rows
  std::vector<int> pivots_;
  bool factorised_ = false;
};

}  // namespace liftoff::linalg
