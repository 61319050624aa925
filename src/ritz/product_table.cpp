#include "ritz/product_table.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <unordered_map>

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
  raw.reserve(2 * static_cast<std::size_t>(rows_) * cols_);
  int pairs = 0;
  for (int i = 0; i < rows_; ++i)
    for (int j = symmetric_ ? i : 0; j < cols_; ++j, ++pairs)
      for (const TrigTerm& x : left[i].terms())
        for (const TrigTerm& y : right[j].terms()) push_product(pairs, x, y, raw);

  // Atoms. Most raw terms repeat a frequency exactly, so first the distinct (wave, power, omega)
  // by hashing, then those few sorted by (wave, power, omega) and nearly equal frequencies
  // clustered onto the smallest.
  struct Distinct {
    int kind;  // wave and power
    double omega;
    int atom = -1;
  };
  std::vector<Distinct> distinct;
  std::unordered_map<std::uint64_t, int> index;  // omega's bits and kind -> distinct entry
  index.reserve(raw.size() / 4 + 16);
  std::vector<int> distinct_of(raw.size());
  for (std::size_t k = 0; k < raw.size(); ++k) {
    const TrigTerm& t = raw[k].term;
    const int kind = 2 * t.power + (t.wave == Wave::sine);
    const std::uint64_t key = std::bit_cast<std::uint64_t>(t.omega) * 1000003u + static_cast<std::uint64_t>(kind);
    auto [it, inserted] = index.try_emplace(key, static_cast<int>(distinct.size()));
    if (inserted) {
      distinct.push_back({kind, t.omega});
    } else if (distinct[it->second].kind != kind || distinct[it->second].omega != t.omega) {
      // Two different keys hashed alike: this term gets an entry of its own.
      distinct.push_back({kind, t.omega});
      distinct_of[k] = static_cast<int>(distinct.size()) - 1;
      continue;
    }
    distinct_of[k] = it->second;
  }
  std::vector<int> order(distinct.size());
  for (std::size_t d = 0; d < distinct.size(); ++d) order[d] = static_cast<int>(d);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return distinct[a].kind != distinct[b].kind ? distinct[a].kind < distinct[b].kind
                                                : distinct[a].omega < distinct[b].omega;
  });
  int last_kind = -1;
  for (int d : order) {
    const double omega = distinct[d].omega;
    if (distinct[d].kind != last_kind || omega - atoms_.back().omega > same_frequency * omega)
      atoms_.push_back({1.0, distinct[d].kind / 2, omega, distinct[d].kind % 2 ? Wave::sine : Wave::cosine});
    last_kind = distinct[d].kind;
    distinct[d].atom = static_cast<int>(atoms_.size()) - 1;
  }
  for (std::size_t k = 0; k < raw.size(); ++k) raw[k].atom = distinct[distinct_of[k]].atom;

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
