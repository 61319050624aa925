#pragma once
// Random scenes for the fuzzer, reproducible from a seed: valid ones across the whole scene schema
// of src/scene/README.md (beams and arches, every support, foundation k or modulus over all or part of the
// member, tensionless or not, force / moment / uniform loads of both cases, [solve], [ritz],
// [trace]) and malformed ones made from a valid one by one mutation (a missing, unknown or
// mistyped key, an out-of-range, non-finite, huge or inexact number, a TOML syntax error, junk).
//
// A scene is kept as tables of (key, TOML text) entries, so a mutation edits it the way a user's
// mistake would, and each mutation says whether the result is certainly invalid (liftoff must
// answer exit 2) or only possibly so (any documented exit but 1).

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace liftoff::fuzz {

// splitmix64: the same stream on every platform (the <random> distributions are not).
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next();
  double uniform();                        // [0, 1)
  double uniform(double a, double b);      // [a, b)
  double log_uniform(double a, double b);  // a, b > 0
  int integer(int lo, int hi);             // [lo, hi]
  bool chance(double p) { return uniform() < p; }
  template <class T>
  const T& pick(const std::vector<T>& items) {
    return items[next() % items.size()];
  }

 private:
  std::uint64_t state_;
};

// What a key holds, so that a mutation knows what a wrong type is.
enum class Type { number, integer, name, flag, positions, modes, pieces };

struct Entry {
  std::string key;
  std::string value;  // TOML text
  Type type = Type::number;
};

struct Table {
  std::string name;    // "structure", "loads"
  bool array = false;  // [[loads]]
  std::vector<Entry> entries;
};

// Choices the command makes before the scene is drawn, so that the scene stays cheap to solve.
struct SceneLimits {
  int max_elements = 100;   // [solve] elements
  bool ritz_cheap = true;   // [ritz]: explicit modes <= 16 or auto with max_modes <= 32
  bool trace = false;       // a [trace] table (required by `liftoff trace`)
  bool ritz_trace = false;  // the trace may take the Ritz path: few steps
};

struct Draft {
  bool arch = false;
  double begin = 0.0, end = 1.0;  // the member in the user's coordinate
  std::vector<Table> tables;

  Table* find(std::string_view name);
  Entry* find(std::string_view table, std::string_view key);
  bool has(std::string_view table, std::string_view key = {}) const;
  std::string text() const;
};

std::string toml_number(double x);  // a TOML float (200.0, not 200)

Draft valid_scene(Random& random, const SceneLimits& limits);

// One mutation of a valid scene: the TOML text and whether liftoff must refuse it (exit 2).
struct Mutant {
  std::string kind;  // what was done, for the report
  std::string text;
  bool certainly_invalid = false;
};
Mutant mutate(Random& random, Draft draft);

}  // namespace liftoff::fuzz
