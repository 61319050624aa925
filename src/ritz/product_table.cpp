#include "ritz/product_table.hpp"

#include <algorithm>
#include <cmath>

namespace liftoff::ritz {

namespace {

constexpr double same_frequency = 1e-13;  // as in trig_polynomial.cpp

struct RawTerm {
  int pair = 0;
  TrigTerm term;
  int atom = -1;
};

// The product-to-sum terms of x * y, exactly as TrigPolynomial's operator* makes them, folded to
// omega >= 0 as its normalise() does.
void push_product(int pair, const TrigTerm& x, const TrigTerm& y, std::vector<RawTerm>& out) {
  auto push = [&](double c, int p, double omega, Wave wave) {
    if (omega < 0.0) {
      omega = -omega;
      if (wave == Wave::sine) c = -c;
    }
    if (c == 0.0 || (wave == Wave::sine && omega == 0.0)) return;
    out.push_back({pair, {c, p, omega, wave}});
  };
  const int p = x.power + y.power;
  const double c = 0.5 * x.coefficient * y.coefficient;
  const double sum = x.omega + y.omega;
  double difference = x.omega - y.omega;
  if (std::abs(difference) <= same_frequency * sum) difference = 0.0;
  if (x.omega == 0.0 || y.omega == 0.0) {
    push(2.0 * c, p, x.omega == 0.0 ? y.omega : x.omega, x.omega == 0.0 ? y.wave : x.wave);
  } else if (x.wave == Wave::cosine && y.wave == Wave::cosine) {
    push(c, p, difference, Wave::cosine);
    push(c, p, sum, Wave::cosine);
  } else if (x.wave == Wave::sine && y.wave == Wave::sine) {
    push(c, p, difference, Wave::cosine);
    push(-c, p, sum, Wave::cosine);
  } else if (x.wave == Wave::sine) {
    push(c, p, sum, Wave::sine);
    push(c, p, difference, Wave::sine);
  } else {
    push(c, p, sum, Wave::sine);
    push(-c, p, difference, Wave::sine);
  }
}

}  // namespace

ProductTable::ProductTable(const std::vector<TrigPolynomial>& left, const std::vector<TrigPolynomial>& right) {
  build(left, right);
}

ProductTable::ProductTable(const std::vector<TrigPolynomial>& f) {
  symmetric_ = true;
  build(f, f);
}

void ProductTable::build(const std::vector<TrigPolynomial>& left, const std::vector<TrigPolynomial>& right) {
  rows_ = static_cast<int>(left.size());
  cols_ = static_cast<int>(right.size());
  std::vector<RawTerm> raw;
  int pairs = 0;
  for (int i = 0; i < rows_; ++i)
    for (int j = symmetric_ ? i : 0; j < cols_; ++j, ++pairs)
      for (const TrigTerm& x : left[i].terms())
        for (const TrigTerm& y : right[j].terms()) push_product(pairs, x, y, raw);

  // Atoms: sort by (wave, power, omega), cluster nearly equal frequencies onto the smallest.
  struct Key {
    int kind;  // wave and power
    double omega;
    int raw;
  };
  std::vector<Key> keys(raw.size());
  for (std::size_t k = 0; k < raw.size(); ++k)
    keys[k] = {2 * raw[k].term.power + (raw[k].term.wave == Wave::sine), raw[k].term.omega, static_cast<int>(k)};
  std::sort(keys.begin(), keys.end(),
            [](const Key& a, const Key& b) { return a.kind != b.kind ? a.kind < b.kind : a.omega < b.omega; });
  int last_kind = -1;
  for (const Key& key : keys) {
    const TrigTerm& t = raw[key.raw].term;
    if (key.kind != last_kind || t.omega - atoms_.back().omega > same_frequency * t.omega)
      atoms_.push_back({1.0, t.power, t.omega, t.wave});
    last_kind = key.kind;
    raw[key.raw].atom = static_cast<int>(atoms_.size()) - 1;
  }

  // Per pair, the coefficients of its atoms, like terms merged (raw is in pair order).
  begin_.assign(pairs + 1, 0);
  std::size_t k = 0;
  for (int pair = 0; pair < pairs; ++pair) {
    const int first = static_cast<int>(atom_.size());
    for (; k < raw.size() && raw[k].pair == pair; ++k) {
      int m = first;
      while (m < static_cast<int>(atom_.size()) && atom_[m] != raw[k].atom) ++m;
      if (m < static_cast<int>(atom_.size())) {
        coefficient_[m] += raw[k].term.coefficient;
      } else {
        atom_.push_back(raw[k].atom);
        coefficient_.push_back(raw[k].term.coefficient);
      }
    }
    begin_[pair + 1] = static_cast<int>(atom_.size());
  }
}

void ProductTable::add_integrals(double a, double b, double factor, Eigen::MatrixXd& g) const {
  std::vector<double> value(atoms_.size());
  for (std::size_t k = 0; k < atoms_.size(); ++k) value[k] = integral(atoms_[k], a, b);
  int pair = 0;
  for (int i = 0; i < rows_; ++i)
    for (int j = symmetric_ ? i : 0; j < cols_; ++j, ++pair) {
      double sum = 0.0;
      for (int k = begin_[pair]; k < begin_[pair + 1]; ++k) sum += coefficient_[k] * value[atom_[k]];
      g(i, j) += factor * sum;
    }
}

}  // namespace liftoff::ritz
