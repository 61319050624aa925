#include "ritz/trig_polynomial.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <tuple>

namespace liftoff::ritz {

namespace {

// Frequencies closer than this (relative) are one frequency: they come from sums and
// differences of the same multiples of pi computed in different orders. Merging two that differ
// by d changes the function by about |c| d max|s|^(p+1), far below round-off of the terms.
constexpr double same_frequency = 1e-13;
// |cos(phase)| or |sin(phase)| below this is an exact zero (a phase at a multiple of pi/2 up
// to round-off); dropping it changes the term by less than 1e-15 of its size.
constexpr double negligible_phase_factor = 1e-15;

double snap(double factor) { return std::abs(factor) < negligible_phase_factor ? 0.0 : factor; }

// Integral of s^p cos(omega s) (wave cosine) or s^p sin(omega s) over [a, b] by the Taylor
// series of the trigonometric factor:
//   cos: sum_n (-1)^n omega^(2n)   / (2n)!   (b^q - a^q)/q,  q = p + 2n + 1
//   sin: sum_n (-1)^n omega^(2n+1) / (2n+1)! (b^q - a^q)/q,  q = p + 2n + 2
// Relative to the scale X^(p+1)/(p+1) (X = max|a|, |b|), its terms are bounded by
// z^m/m! with z = omega X, so its cancellation is at most cosh(z).
double series_integral(int p, double omega, Wave wave, double a, double b, double scale) {
  int m = wave == Wave::cosine ? 0 : 1;                // order of the Taylor term
  double factor = wave == Wave::cosine ? 1.0 : omega;  // (-1)^n omega^m / m!
  int q = p + m + 1;
  double pa = std::pow(a, q), pb = std::pow(b, q);
  const double a2 = a * a, b2 = b * b;
  const double x = std::max(std::abs(a), std::abs(b));
  const double z = omega * x;
  double sum = 0.0;
  for (int n = 0; n < 1000; ++n) {
    const double term = factor * (pb - pa) / q;
    sum += term;
    // Bound on every later term: |factor| X^q / q decreases geometrically once m > z.
    if (m > z && std::abs(factor) * std::pow(x, q) / q <= 1e-18 * scale) break;
    factor *= -omega * omega / ((m + 1.0) * (m + 2.0));
    m += 2;
    q += 2;
    pa *= a2;
    pb *= b2;
  }
  return sum;
}

// Closed form: s^p e^{i omega s} has the antiderivative
//   F(s) = e^{i omega s} sum_{k=0}^{p} (-1)^k p!/(p-k)! s^(p-k) / (i omega)^(k+1),
// whose real part integrates the cosine and imaginary part the sine. Relative to the scale its
// terms are bounded by (p+1)!/(p-k)! / z^(k+1).
double closed_form_integral(int p, double omega, Wave wave, double a, double b) {
  // d_k = (-1)^k p!/(p-k)! / (i omega)^(k+1) = m_k (-i)^(k+1), m_k real: F in real arithmetic.
  static constexpr double re_of[4] = {1.0, 0.0, -1.0, 0.0};  // (-i)^n by n mod 4
  static constexpr double im_of[4] = {0.0, -1.0, 0.0, 1.0};
  double buffer[16];
  std::vector<double> heap;
  double* magnitude = p < 16 ? buffer : (heap.resize(p + 1), heap.data());
  magnitude[0] = 1.0 / omega;
  for (int k = 1; k <= p; ++k) magnitude[k] = magnitude[k - 1] * -static_cast<double>(p - k + 1) / omega;
  auto antiderivative = [&](double s) {
    double sum_re = 0.0, sum_im = 0.0, power = 1.0;  // power = s^(p-k), k from p down
    for (int k = p; k >= 0; --k, power *= s) {
      sum_re += magnitude[k] * power * re_of[(k + 1) % 4];
      sum_im += magnitude[k] * power * im_of[(k + 1) % 4];
    }
    const double cos_s = std::cos(omega * s), sin_s = std::sin(omega * s);
    return wave == Wave::cosine ? sum_re * cos_s - sum_im * sin_s : sum_re * sin_s + sum_im * cos_s;
  };
  return antiderivative(b) - antiderivative(a);
}

}  // namespace

double integral(const TrigTerm& term, double a, double b) {
  const int p = term.power;
  const double omega = std::abs(term.omega);
  const double sign = term.wave == Wave::sine && term.omega < 0.0 ? -1.0 : 1.0;
  if (a == b || term.coefficient == 0.0) return 0.0;
  if (omega == 0.0) {
    if (term.wave == Wave::sine) return 0.0;
    return term.coefficient * (std::pow(b, p + 1) - std::pow(a, p + 1)) / (p + 1);
  }
  const double x = std::max(std::abs(a), std::abs(b));
  const double z = omega * x;
  // Choose the method with the smaller bound on cancellation (see the two functions above).
  double closed_amplification = 0.0, r = 1.0 / z;
  for (int k = 0; k <= p; ++k) {
    r *= static_cast<double>(p + 1 - k) / (k == 0 ? 1.0 : z);
    closed_amplification = std::max(closed_amplification, r);
  }
  // cosh >= 1: below 1 the closed form wins without computing it.
  const bool series = closed_amplification >= 1.0 && std::cosh(std::min(z, 700.0)) <= closed_amplification;
  const double value = series ? series_integral(p, omega, term.wave, a, b, std::pow(x, p + 1) / (p + 1))
                              : closed_form_integral(p, omega, term.wave, a, b);
  return sign * term.coefficient * value;
}

TrigPolynomial::TrigPolynomial(std::vector<TrigTerm> terms) : terms_(std::move(terms)) {
  for (const TrigTerm& t : terms_) {
    if (t.power < 0) throw std::invalid_argument(fmt::format("TrigPolynomial: power {} is negative", t.power));
    if (!std::isfinite(t.coefficient) || !std::isfinite(t.omega))
      throw std::invalid_argument("TrigPolynomial: non-finite coefficient or frequency");
  }
  normalise();
}

TrigPolynomial TrigPolynomial::constant(double c) { return TrigPolynomial({{c, 0, 0.0, Wave::cosine}}); }

TrigPolynomial TrigPolynomial::monomial(int power, double coefficient) {
  return TrigPolynomial({{coefficient, power, 0.0, Wave::cosine}});
}

// cos(w s + phi) = cos(phi) cos(w s) - sin(phi) sin(w s)
TrigPolynomial TrigPolynomial::cosine(double omega, double phase, double coefficient) {
  return TrigPolynomial({{coefficient * snap(std::cos(phase)), 0, omega, Wave::cosine},
                         {-coefficient * snap(std::sin(phase)), 0, omega, Wave::sine}});
}

// sin(w s + phi) = sin(phi) cos(w s) + cos(phi) sin(w s)
TrigPolynomial TrigPolynomial::sine(double omega, double phase, double coefficient) {
  return TrigPolynomial({{coefficient * snap(std::sin(phase)), 0, omega, Wave::cosine},
                         {coefficient * snap(std::cos(phase)), 0, omega, Wave::sine}});
}

void TrigPolynomial::normalise() {
  for (TrigTerm& t : terms_) {
    if (t.omega < 0.0) {
      t.omega = -t.omega;
      if (t.wave == Wave::sine) t.coefficient = -t.coefficient;
    }
  }
  std::erase_if(terms_,
                [](const TrigTerm& t) { return t.coefficient == 0.0 || (t.wave == Wave::sine && t.omega == 0.0); });
  // Cluster nearly equal frequencies onto the smallest of the cluster.
  std::sort(terms_.begin(), terms_.end(), [](const TrigTerm& a, const TrigTerm& b) { return a.omega < b.omega; });
  for (std::size_t i = 1; i < terms_.size(); ++i) {
    const double reference = terms_[i - 1].omega;
    if (terms_[i].omega - reference <= same_frequency * terms_[i].omega) terms_[i].omega = reference;
  }
  std::erase_if(terms_, [](const TrigTerm& t) { return t.wave == Wave::sine && t.omega == 0.0; });
  auto key = [](const TrigTerm& t) { return std::make_tuple(t.wave, t.omega, t.power); };
  std::sort(terms_.begin(), terms_.end(), [&](const TrigTerm& a, const TrigTerm& b) { return key(a) < key(b); });
  std::vector<TrigTerm> merged;
  merged.reserve(terms_.size());
  for (const TrigTerm& t : terms_) {
    if (!merged.empty() && key(merged.back()) == key(t))
      merged.back().coefficient += t.coefficient;
    else
      merged.push_back(t);
  }
  std::erase_if(merged, [](const TrigTerm& t) { return t.coefficient == 0.0; });
  terms_ = std::move(merged);
}

double TrigPolynomial::value(double s) const {
  double sum = 0.0;
  for (const TrigTerm& t : terms_) {
    const double power = t.power == 0 ? 1.0 : std::pow(s, t.power);
    const double wave = t.omega == 0.0 ? 1.0 : (t.wave == Wave::cosine ? std::cos(t.omega * s) : std::sin(t.omega * s));
    sum += t.coefficient * power * wave;
  }
  return sum;
}

void add_on_grid(const TrigTerm* terms, const double* factors, int term_count, double s0, double h, int count,
                 double* out, const int* rows) {
  constexpr int run = 32;
  // Four terms at a time: their rotations are independent, so they overlap in the pipeline
  // (one term's rotation is a chain of dependent multiplications).
  constexpr int block = 4;
  for (int t0 = 0; t0 < term_count; t0 += block) {
    const int terms_here = std::min(block, term_count - t0);
    double c_cos[block] = {}, c_sin[block] = {}, cos_h[block] = {1.0, 1.0, 1.0, 1.0}, sin_h[block] = {};
    int power[block] = {};
    bool any_power = false;
    for (int j = 0; j < terms_here; ++j) {
      const TrigTerm& t = terms[t0 + j];
      const double c = factors[t0 + j] * t.coefficient;
      (t.wave == Wave::cosine ? c_cos : c_sin)[j] = c;
      power[j] = t.power;
      any_power = any_power || t.power > 0;
      if (t.omega != 0.0) cos_h[j] = std::cos(t.omega * h), sin_h[j] = std::sin(t.omega * h);
    }
    for (int first = 0; first < count; first += run) {
      const int last = std::min(count, first + run);
      const double start = s0 + first * h;
      double cos_s[block] = {1.0, 1.0, 1.0, 1.0}, sin_s[block] = {};
      for (int j = 0; j < terms_here; ++j) {
        const double omega = terms[t0 + j].omega;
        if (omega != 0.0) cos_s[j] = std::cos(omega * start), sin_s[j] = std::sin(omega * start);
      }
      for (int k = first; k < last; ++k) {
        const double s = s0 + k * h;
        double value[block];
        for (int j = 0; j < block; ++j) value[j] = c_cos[j] * cos_s[j] + c_sin[j] * sin_s[j];
        if (any_power)
          for (int j = 0; j < block; ++j)
            for (int q = 0; q < power[j]; ++q) value[j] *= s;
        if (rows) {  // each term into its function's row
          for (int j = 0; j < terms_here; ++j) out[static_cast<std::size_t>(rows[t0 + j]) * count + k] += value[j];
        } else {
          out[k] += (value[0] + value[1]) + (value[2] + value[3]);
        }
        for (int j = 0; j < block; ++j) {
          const double next_cos = cos_s[j] * cos_h[j] - sin_s[j] * sin_h[j];
          sin_s[j] = sin_s[j] * cos_h[j] + cos_s[j] * sin_h[j];
          cos_s[j] = next_cos;
        }
      }
    }
  }
}

std::vector<double> TrigPolynomial::values_on_grid(double a, double b, int n) const {
  std::vector<double> values(n + 1, 0.0);
  const std::vector<double> ones(terms_.size(), 1.0);
  add_on_grid(terms_.data(), ones.data(), static_cast<int>(terms_.size()), a, (b - a) / n, n + 1, values.data());
  return values;
}

// d/ds c s^p cos(w s) = c p s^(p-1) cos(w s) - c w s^p sin(w s)
// d/ds c s^p sin(w s) = c p s^(p-1) sin(w s) + c w s^p cos(w s)
TrigPolynomial TrigPolynomial::derivative(int order) const {
  if (order < 0) throw std::invalid_argument("TrigPolynomial::derivative: negative order");
  TrigPolynomial result = *this;
  for (int n = 0; n < order; ++n) {
    std::vector<TrigTerm> d;
    d.reserve(2 * result.terms_.size());
    for (const TrigTerm& t : result.terms_) {
      if (t.power > 0) d.push_back({t.coefficient * t.power, t.power - 1, t.omega, t.wave});
      if (t.omega != 0.0) {
        if (t.wave == Wave::cosine)
          d.push_back({-t.coefficient * t.omega, t.power, t.omega, Wave::sine});
        else
          d.push_back({t.coefficient * t.omega, t.power, t.omega, Wave::cosine});
      }
    }
    result = TrigPolynomial(std::move(d));
  }
  return result;
}

TrigPolynomial TrigPolynomial::antiderivative() const {
  std::vector<TrigTerm> out;
  for (const TrigTerm& t : terms_) {
    if (t.omega == 0.0) {
      out.push_back({t.coefficient / (t.power + 1), t.power + 1, 0.0, Wave::cosine});
      continue;
    }
    // F = e^{iws} sum_k d_k i^{-(k+1)} s^(p-k), d_k = (-1)^k p!/(p-k)! w^-(k+1) (see
    // closed_form_integral); cos term: Re F, sin term: Im F.
    double d = 1.0 / t.omega;
    for (int k = 0; k <= t.power; ++k) {
      static constexpr double re_of[4] = {1.0, 0.0, -1.0, 0.0};  // i^{-(k+1)} by (k+1) mod 4
      static constexpr double im_of[4] = {0.0, -1.0, 0.0, 1.0};
      const double re = re_of[(k + 1) % 4], im = im_of[(k + 1) % 4];
      const int power = t.power - k;
      const double c = t.coefficient * d;
      if (t.wave == Wave::cosine) {  // Re[(re + i im)(cos + i sin)] = re cos - im sin
        out.push_back({c * re, power, t.omega, Wave::cosine});
        out.push_back({-c * im, power, t.omega, Wave::sine});
      } else {  // Im[...] = re sin + im cos
        out.push_back({c * re, power, t.omega, Wave::sine});
        out.push_back({c * im, power, t.omega, Wave::cosine});
      }
      d *= -static_cast<double>(t.power - k) / t.omega;
    }
  }
  return TrigPolynomial(std::move(out));
}

double TrigPolynomial::integral(double a, double b) const {
  double sum = 0.0;
  for (const TrigTerm& t : terms_) sum += ritz::integral(t, a, b);
  return sum;
}

// c (alpha s + beta)^p trig(w alpha s + w beta), expanded binomially and by the addition
// theorems with A = w alpha, B = w beta.
TrigPolynomial TrigPolynomial::composed_affine(double alpha, double beta) const {
  std::vector<TrigTerm> out;
  for (const TrigTerm& t : terms_) {
    const double big_a = t.omega * alpha, big_b = t.omega * beta;
    const double cb = snap(std::cos(big_b)), sb = snap(std::sin(big_b));
    double binomial = 1.0;
    for (int k = 0; k <= t.power; ++k) {
      // C(p, k) alpha^k beta^(p-k) s^k
      const double c = t.coefficient * binomial * std::pow(alpha, k) * std::pow(beta, t.power - k);
      binomial = binomial * (t.power - k) / (k + 1);
      if (c == 0.0) continue;
      if (t.omega == 0.0) {
        out.push_back({c, k, 0.0, Wave::cosine});
      } else if (t.wave == Wave::cosine) {  // cos(A s + B) = cos B cos(A s) - sin B sin(A s)
        out.push_back({c * cb, k, big_a, Wave::cosine});
        out.push_back({-c * sb, k, big_a, Wave::sine});
      } else {  // sin(A s + B) = sin B cos(A s) + cos B sin(A s)
        out.push_back({c * sb, k, big_a, Wave::cosine});
        out.push_back({c * cb, k, big_a, Wave::sine});
      }
    }
  }
  return TrigPolynomial(std::move(out));
}

TrigPolynomial& TrigPolynomial::operator+=(const TrigPolynomial& other) {
  terms_.insert(terms_.end(), other.terms_.begin(), other.terms_.end());
  normalise();
  return *this;
}

TrigPolynomial& TrigPolynomial::operator-=(const TrigPolynomial& other) { return *this += -1.0 * other; }

TrigPolynomial& TrigPolynomial::operator*=(double factor) {
  if (!std::isfinite(factor)) throw std::invalid_argument("TrigPolynomial: non-finite factor");
  for (TrigTerm& t : terms_) t.coefficient *= factor;
  normalise();
  return *this;
}

TrigPolynomial operator*(const TrigPolynomial& a, const TrigPolynomial& b) {
  std::vector<TrigTerm> out;
  out.reserve(2 * a.terms_.size() * b.terms_.size());
  for (const TrigTerm& x : a.terms_) {
    for (const TrigTerm& y : b.terms_) {
      const int p = x.power + y.power;
      const double c = 0.5 * x.coefficient * y.coefficient;
      const double sum = x.omega + y.omega;
      double difference = x.omega - y.omega;  // x - y, may be negative: normalise() folds it
      if (std::abs(difference) <= same_frequency * sum) difference = 0.0;
      if (x.omega == 0.0 || y.omega == 0.0) {  // one factor is a plain power: no product-to-sum
        const double omega = x.omega == 0.0 ? y.omega : x.omega;
        const Wave wave = x.omega == 0.0 ? y.wave : x.wave;
        out.push_back({2.0 * c, p, omega, wave});
      } else if (x.wave == Wave::cosine && y.wave == Wave::cosine) {
        // cos x cos y = (cos(x - y) + cos(x + y))/2
        out.push_back({c, p, difference, Wave::cosine});
        out.push_back({c, p, sum, Wave::cosine});
      } else if (x.wave == Wave::sine && y.wave == Wave::sine) {
        // sin x sin y = (cos(x - y) - cos(x + y))/2
        out.push_back({c, p, difference, Wave::cosine});
        out.push_back({-c, p, sum, Wave::cosine});
      } else if (x.wave == Wave::sine) {
        // sin x cos y = (sin(x + y) + sin(x - y))/2
        out.push_back({c, p, sum, Wave::sine});
        out.push_back({c, p, difference, Wave::sine});
      } else {
        // cos x sin y = (sin(x + y) - sin(x - y))/2
        out.push_back({c, p, sum, Wave::sine});
        out.push_back({-c, p, difference, Wave::sine});
      }
    }
  }
  return TrigPolynomial(std::move(out));
}

std::string TrigPolynomial::to_string() const {
  if (terms_.empty()) return "0";
  std::string text;
  for (const TrigTerm& t : terms_) {
    std::string factor;
    if (t.power == 1) factor += " s";
    if (t.power > 1) factor += fmt::format(" s^{}", t.power);
    if (t.omega != 0.0) factor += fmt::format(" {}({:.6g} s)", t.wave == Wave::cosine ? "cos" : "sin", t.omega);
    const double c = t.coefficient;
    if (text.empty())
      text = fmt::format("{:.6g}{}", c, factor);
    else
      text += fmt::format(" {} {:.6g}{}", c < 0 ? '-' : '+', std::abs(c), factor);
  }
  return text;
}

}  // namespace liftoff::ritz
