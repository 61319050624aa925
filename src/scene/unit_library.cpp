#include "scene/unit_library.hpp"

#include <udunits2.h>

#include <charconv>
#include <cmath>
#include <memory>
#include <mutex>

#include "core/error.hpp"

namespace liftoff::scene::unit_library {
namespace {

// UDUNITS-2's parser keeps global state (a flex/bison scanner), and sweeps read scenes on several
// threads: every call into the library holds this lock.
std::mutex library;

// The unit system, read once and kept for the life of the process.
ut_system* unit_system() {
  static ut_system* system = [] {
    ut_set_error_message_handler(ut_ignore);  // failures are reported by our own messages
    ut_system* s = ut_read_xml(nullptr);
    if (s == nullptr)
      throw InputError("the units database of UDUNITS-2 cannot be read (libudunits2-data; UDUNITS2_XML_PATH)");
    return s;
  }();
  return system;
}

struct UnitDeleter {
  void operator()(ut_unit* u) const { ut_free(u); }
};
struct ConverterDeleter {
  void operator()(cv_converter* c) const { cv_free(c); }
};
using Unit = std::unique_ptr<ut_unit, UnitDeleter>;
using Converter = std::unique_ptr<cv_converter, ConverterDeleter>;

Unit parse(std::string_view text) {
  const std::string trimmed(text);
  // ut_parse reads no surrounding blanks; an empty unit is the number 1.
  if (trimmed.empty()) return Unit(ut_clone(ut_get_dimensionless_unit_one(unit_system())));
  return Unit(ut_parse(unit_system(), trimmed.c_str(), UT_UTF8));
}

std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t");
  return s.substr(first, last - first + 1);
}

bool integral(double x) { return std::isfinite(x) && x != 0.0 && std::trunc(x) == x; }

}  // namespace

std::optional<Quantity> split(std::string_view text) {
  const std::string_view s = trim(text);
  const char* begin = s.data();
  const char* end = s.data() + s.size();
  if (begin != end && *begin == '+') ++begin;  // from_chars reads no '+'
  double number = 0.0;
  const auto [stop, error] = std::from_chars(begin, end, number);
  if (error != std::errc() || !std::isfinite(number)) return std::nullopt;
  const std::string_view rest(stop, static_cast<std::size_t>(end - stop));
  // "1800mm" reads; "1e" or "1.5.2" would leave a unit starting with '.' or a letter glued to an
  // exponent, which UDUNITS then refuses as a unit.
  return Quantity{number, std::string(trim(rest))};
}

bool known(std::string_view unit) {
  const std::lock_guard<std::mutex> lock(library);
  return parse(unit) != nullptr;
}

// Of one dimension: UDUNITS also calls a unit and its reciprocal convertible (m and 1/m, by
// x -> 1/x); their quotient is a pure number only when they share a dimension.
bool same_dimension(const ut_unit* a, const ut_unit* b) {
  const Unit ratio(ut_divide(a, b));
  return ratio && ut_are_convertible(ratio.get(), ut_get_dimensionless_unit_one(unit_system())) != 0 &&
         ut_are_convertible(a, b) != 0;
}

bool convertible(std::string_view from, std::string_view to) {
  const std::lock_guard<std::mutex> lock(library);
  const Unit a = parse(from), b = parse(to);
  return a && b && same_dimension(a.get(), b.get());
}

bool dimensionless(std::string_view unit) {
  const std::lock_guard<std::mutex> lock(library);
  const Unit a = parse(unit);
  return a && ut_are_convertible(a.get(), ut_get_dimensionless_unit_one(unit_system())) != 0;
}

Conversion convert(double number, std::string_view from, std::string_view to, bool difference) {
  const std::lock_guard<std::mutex> lock(library);
  const Unit a = parse(from), b = parse(to);
  if (!a) return {Outcome::unknown_unit};
  if (!b) return {Outcome::unknown_target};
  if (!same_dimension(a.get(), b.get())) return {Outcome::wrong_dimension};
  Converter forward(ut_get_converter(a.get(), b.get())), backward(ut_get_converter(b.get(), a.get()));
  if (!forward || !backward) return {Outcome::wrong_dimension};
  if (cv_convert_double(forward.get(), 0.0) != 0.0) {  // an offset (degF to K)
    if (!difference) return {Outcome::converted, cv_convert_double(forward.get(), number)};
    // A difference goes by the slope alone: the reciprocal units have no offset (1/K to 1/degF is
    // the slope from degF to K), which avoids the cancellation of f(1) - f(0).
    const Unit inverse_a(ut_invert(a.get())), inverse_b(ut_invert(b.get()));
    if (!inverse_a || !inverse_b) return {Outcome::wrong_dimension};
    forward.reset(ut_get_converter(inverse_b.get(), inverse_a.get()));
    backward.reset(ut_get_converter(inverse_a.get(), inverse_b.get()));
    if (!forward || !backward) return {Outcome::wrong_dimension};
  }
  // A scale: by the integer factor where one way is an integer (one rounding), else UDUNITS' own.
  const double factor = cv_convert_double(forward.get(), 1.0);
  const double inverse = cv_convert_double(backward.get(), 1.0);
  if (integral(inverse) && !integral(factor)) return {Outcome::converted, number / inverse};
  return {Outcome::converted, number * factor};
}

}  // namespace liftoff::scene::unit_library
