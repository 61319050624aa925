#pragma once
// Changing one value of a scene's TOML text, for parameter sweeps: the edited text is parsed
// and validated again like any scene, and is what the case's output stores.

#include <string>
#include <string_view>

namespace liftoff::scene {

// Sets the number at `key` ("foundation.modulus", "loads[1].value", "solve.elements") in the TOML
// text and returns the new text (comments are not kept). The tables on the path must exist; the
// last key may be new. An integer stays an integer when the new value is integral. Throws
// InputError ("SOURCE: key 'KEY': ...") for a path that does not exist or is not a table.
std::string with_value(std::string_view toml_text, std::string_view key, double value, const std::string& source);

}  // namespace liftoff::scene
