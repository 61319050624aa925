// The banded LU is LAPACK's dgbtf2 / dgbtrs written out: on the same matrix it must pick the
// same pivots and produce the same factors and solutions as dgbtrf / dgbtrs.

#include "linalg/banded_lu.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

extern "C" {
void dgbtrf_(const int* m, const int* n, const int* kl, const int* ku, double* ab, const int* ldab, int* ipiv,
             int* info);
void dgbtrs_(const char* trans, const int* n, const int* kl, const int* ku, const int* nrhs, const double* ab,
             const int* ldab, const int* ipiv, double* b, const int* ldb, int* info, std::size_t trans_length);
}

using liftoff::linalg::BandedLu;

namespace {

struct Case {
  int n, kl, ku;
  double zero_fraction;  // band entries left zero (the mixed systems are sparse inside the band)
};

// A random band matrix in both storages; the diagonal is small relative to the rest so that
// partial pivoting interchanges rows often.
void fill(const Case& c, std::mt19937& random, BandedLu& lu, std::vector<double>& lapack_band) {
  std::uniform_real_distribution<double> value(-1.0, 1.0), coin(0.0, 1.0);
  const int ld = 2 * c.kl + c.ku + 1;
  lu.set_structure(c.n, c.kl, c.ku);
  lapack_band.assign(static_cast<std::size_t>(ld) * c.n, 0.0);
  for (int col = 0; col < c.n; ++col)
    for (int row = std::max(0, col - c.ku); row <= std::min(c.n - 1, col + c.kl); ++row) {
      double v = coin(random) < c.zero_fraction ? 0.0 : value(random);
      if (row == col) v *= 1e-3;
      lu.set(row, col, v);
      lapack_band[static_cast<std::size_t>(col) * ld + c.kl + c.ku + row - col] = v;
    }
}

}  // namespace

TEST_CASE("the banded LU pivots, factorises and solves exactly as LAPACK's dgbtrf / dgbtrs") {
  std::mt19937 random(20261202);
  // kl = ku = 7 (beams: the unrolled path), other bands (the general path), tiny and empty.
  for (const Case c : {Case{673, 7, 7, 0.5}, Case{200, 7, 7, 0.0}, Case{9, 7, 7, 0.2}, Case{150, 11, 11, 0.5},
                       Case{120, 3, 5, 0.3}, Case{50, 0, 2, 0.0}, Case{1, 7, 7, 0.0}}) {
    CAPTURE(c.n, c.kl, c.ku, c.zero_fraction);
    BandedLu lu;
    std::vector<double> band;
    fill(c, random, lu, band);
    std::vector<int> ipiv(c.n);
    const int ld = 2 * c.kl + c.ku + 1;
    int info = 0;
    dgbtrf_(&c.n, &c.n, &c.kl, &c.ku, band.data(), &ld, ipiv.data(), &info);
    REQUIRE(info == 0);
    REQUIRE(lu.factorise());
    // The same operations in the same order on the same data: identical pivots and factors,
    // bit for bit (no tolerance: any difference would mean a different algorithm).
    for (int j = 0; j < c.n; ++j) REQUIRE(lu.pivot_row(j) == ipiv[j] - 1);
    REQUIRE(lu.band_storage() == band);
    std::vector<double> b(c.n), lapack_b;
    for (int i = 0; i < c.n; ++i) b[i] = std::sin(1.0 + i);
    lapack_b = b;
    const int one = 1;
    dgbtrs_("N", &c.n, &c.kl, &c.ku, &one, band.data(), &ld, ipiv.data(), lapack_b.data(), &c.n, &info, 1);
    REQUIRE(info == 0);
    lu.solve(b.data());
    CHECK(b == lapack_b);
  }
}

TEST_CASE("a zero pivot makes the factorisation report a singular matrix, like dgbtrf's info > 0") {
  BandedLu lu;
  lu.set_structure(4, 1, 1);
  lu.clear();
  // [1 1 0 0; 1 1 0 0; 0 0 1 0; 0 0 0 1]: after eliminating the first column the second is zero.
  lu.set(0, 0, 1.0), lu.set(0, 1, 1.0), lu.set(1, 0, 1.0), lu.set(1, 1, 1.0), lu.set(2, 2, 1.0), lu.set(3, 3, 1.0);
  CHECK_FALSE(lu.factorise());
  CHECK_FALSE(lu.factorised());
  CHECK_THROWS_AS(lu.solve(std::vector<double>(4, 1.0).data()), std::logic_error);
}

TEST_CASE("an empty matrix factorises and solves trivially") {
  BandedLu lu;
  lu.set_structure(0, 7, 7);
  CHECK(lu.factorise());
  lu.solve(nullptr);
}
