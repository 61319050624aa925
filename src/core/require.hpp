#pragma once
// The one shape of a check in an options struct's validate(): the field and what it must be,
// thrown as std::invalid_argument("RitzOptions::modes must be >= 0 (0: automatic)") when the
// condition fails. Misuse by a caller, not bad input from a file (core/error.hpp): the scene
// reader checks the file's keys before any options are built.

#include <fmt/format.h>

#include <stdexcept>
#include <string_view>
#include <utility>

namespace liftoff {

// Throws std::invalid_argument("<field> <expectation>") unless `holds`. `expectation` is a fmt
// format string over `args`, formatted only on failure.
template <class... Args>
void require(bool holds, std::string_view field, fmt::format_string<Args...> expectation, Args&&... args) {
  if (!holds)
    throw std::invalid_argument(fmt::format("{} {}", field, fmt::format(expectation, std::forward<Args>(args)...)));
}

}  // namespace liftoff
