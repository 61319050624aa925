#pragma once
// Scene text shared by the tests that read a scene as a user writes it (TOML): the tables every
// beam fixture begins with. Numbers are text, so that the scene reads exactly as written.

#include <string>

namespace liftoff::test {

// The first tables of a beam's scene text, one key a line: [structure] (kind, length, EI), [supports]
// (left and right as TOML values, e.g. "\"pinned\"") and the [foundation] header; the caller's
// foundation keys, loads and other tables follow.
inline std::string beam_text(const std::string& length, const std::string& bending_stiffness,
                             const std::string& left = "\"pinned\"", const std::string& right = "\"pinned\"") {
  return "[structure]\nkind = \"beam\"\nlength = " + length + "\nEI = " + bending_stiffness +
         "\n[supports]\nleft = " + left + "\nright = " + right + "\n[foundation]\n";
}

}  // namespace liftoff::test
