#pragma once
// Finite sums of terms  c s^p cos(omega s)  and  c s^p sin(omega s)  (p >= 0, omega >= 0), the
// functions of the Ritz model: its basis functions, their derivatives and their products are all
// of this form, and so the energy integrals over moving contact limits are exact, with no
// quadrature.
//
// Every operation returns a normalised sum: omega >= 0 (cos(-w s) = cos(w s),
// sin(-w s) = -sin(w s)), no sine with omega = 0, frequencies that agree to a relative 1e-13
// merged (they arise as sums and differences of the same multiples of pi), like terms merged,
// exact zeros dropped; terms sorted by (wave, omega, power).
//
// integral(a, b) is the exact definite integral, term by term: by the Taylor series of cos/sin
// where omega max(|a|, |b|) is small (the closed form's 1/omega^(k+1) terms would cancel), by the
// closed form of repeated integration by parts otherwise, whichever has the smaller bound on
// cancellation. Either way the absolute error is a few eps times the integral of |s^p| over
// [0, max(|a|, |b|)], continuous as omega -> 0 and accurate for large omega.
//
// antiderivative() is the closed form and carries the same 1/omega^(k+1) factors: exact for
// omega = 0 and accurate when omega max|s| is not small (as for every basis function: their
// frequencies are at least pi/2 over the member); prefer integral() for definite integrals.

#include <string>
#include <vector>

namespace liftoff::ritz {

enum class Wave { cosine, sine };

struct TrigTerm {
  double coefficient = 0.0;
  int power = 0;       // p >= 0
  double omega = 0.0;  // >= 0 after normalisation
  Wave wave = Wave::cosine;
};

// The exact integral of one term over [a, b] (see above for the accuracy).
double integral(const TrigTerm& term, double a, double b);

// Adds sum_t factors[t] * terms[t](s0 + k h) to out[k] for k = 0..count-1: what the terms'
// values give up to round-off, but the phases are rotated from point to point by the addition
// theorem, re-seeded with an exact sine and cosine every 32 points (the rotations' round-off
// grows with the run), so a dense grid costs a few multiplications per point and term instead
// of a sine. With rows, term t goes to out[rows[t] * count + k] instead: several functions
// sampled in one pass.
void add_on_grid(const TrigTerm* terms, const double* factors, int term_count, double s0, double h, int count,
                 double* out, const int* rows = nullptr);

class TrigPolynomial {
 public:
  TrigPolynomial() = default;  // the zero function
  // Throws std::invalid_argument for a negative power or a non-finite coefficient or frequency.
  explicit TrigPolynomial(std::vector<TrigTerm> terms);

  static TrigPolynomial constant(double c);
  static TrigPolynomial monomial(int power, double coefficient = 1.0);
  // coefficient * cos(omega s + phase), coefficient * sin(omega s + phase). A factor cos(phase)
  // or sin(phase) below 1e-15 in size is taken as 0, so that phases at multiples of pi/2 give
  // exact single terms.
  static TrigPolynomial cosine(double omega, double phase = 0.0, double coefficient = 1.0);
  static TrigPolynomial sine(double omega, double phase = 0.0, double coefficient = 1.0);

  const std::vector<TrigTerm>& terms() const { return terms_; }
  bool is_zero() const { return terms_.empty(); }

  double value(double s) const;
  double operator()(double s) const { return value(s); }
  // The values at a + (b - a) k / n, k = 0..n (n + 1 of them), by add_on_grid.
  std::vector<double> values_on_grid(double a, double b, int n) const;
  TrigPolynomial derivative(int order = 1) const;
  TrigPolynomial antiderivative() const;
  double integral(double a, double b) const;
  // The function s -> f(alpha s + beta) (change of coordinate, mirror).
  TrigPolynomial composed_affine(double alpha, double beta) const;

  TrigPolynomial& operator+=(const TrigPolynomial& other);
  TrigPolynomial& operator-=(const TrigPolynomial& other);
  TrigPolynomial& operator*=(double factor);
  friend TrigPolynomial operator+(TrigPolynomial a, const TrigPolynomial& b) { return a += b; }
  friend TrigPolynomial operator-(TrigPolynomial a, const TrigPolynomial& b) { return a -= b; }
  friend TrigPolynomial operator*(TrigPolynomial a, double c) { return a *= c; }
  friend TrigPolynomial operator*(double c, TrigPolynomial a) { return a *= c; }
  friend TrigPolynomial operator-(TrigPolynomial a) { return a *= -1.0; }
  // Product-to-sum: s^p s^q = s^(p+q), cos a cos b = (cos(a-b) + cos(a+b))/2, and so on.
  friend TrigPolynomial operator*(const TrigPolynomial& a, const TrigPolynomial& b);

  std::string to_string() const;  // e.g. "0.5 - 0.5 cos(6.28319 s)"

 private:
  void normalise();
  std::vector<TrigTerm> terms_;
};

}  // namespace liftoff::ritz
