#pragma once
// Quantities written with their unit ("3.12e7 N m^2", "30 MN/m^2", "1800 mm"): the one place that
// knows UDUNITS-2 (Debian libudunits2-dev), so nothing else in liftoff sees it.
//
// A quantity is a number (as C++'s from_chars reads a double: "1800", "3.12e7", "-2.5") then a
// unit in UDUNITS-2's syntax ("N m^2", "N.m2", "kN*m", "MN/m^2", "kip ft^2", "degF", "1/K"):
// products by space, '.' or '*', powers by '^' or a trailing digit, quotients by '/', SI prefixes,
// and the common US customary units (lbf, kip, ft, in, psi). The unit database is read once, on
// the first call (about 10 ms), so scenes of plain numbers never pay for it. Safe to call from
// several threads (one lock around UDUNITS, whose parser is not reentrant).
//
// convert() changes the number into another unit of the same dimension. Between units whose
// ratio is an exact integer one way (N m^2 to kN m^2: 1000), it divides or multiplies by that
// integer, one correctly rounded operation, so "5.4e8 N m^2" gives exactly the double of
// 5.4e5 and "1800 mm" exactly 1.8: a value with its unit reads as the same value written in
// the scene's units. Otherwise it multiplies by UDUNITS' factor. `difference` converts a
// difference (a temperature rise: 36 degF is 20 K) by the slope alone, without the offset.

#include <optional>
#include <string>
#include <string_view>

namespace liftoff::scene::unit_library {

struct Quantity {
  double number = 0.0;
  std::string unit;  // trimmed; empty for a bare number
};
// The number and the unit of a text, or nullopt when it does not start with a finite number.
std::optional<Quantity> split(std::string_view text);

// Whether UDUNITS-2 reads `unit` as a unit.
bool known(std::string_view unit);
// Whether `from` and `to` are known units of the same dimension.
bool convertible(std::string_view from, std::string_view to);
// Whether `unit` is a pure number (no dimension, e.g. "", "1", "percent"; radians count too).
bool dimensionless(std::string_view unit);

enum class Outcome { converted, unknown_unit, unknown_target, wrong_dimension };
struct Conversion {
  Outcome outcome = Outcome::unknown_unit;
  double value = 0.0;  // in `to`, when converted
};
Conversion convert(double number, std::string_view from, std::string_view to, bool difference = false);

}  // namespace liftoff::scene::unit_library
