// The options check: silent when the condition holds, one std::invalid_argument naming the field
// and its expectation when it fails, with the arguments formatted into the message.
#include "core/require.hpp"

#include <catch2/catch.hpp>
#include <stdexcept>

using namespace liftoff;

TEST_CASE("require: passes silently, or throws the field and what it must be", "[core]") {
  CHECK_NOTHROW(require(true, "RitzOptions::modes", "must be >= 0 (0: automatic)"));
  CHECK_THROWS_MATCHES(require(false, "RitzOptions::modes", "must be >= 0 (0: automatic)"), std::invalid_argument,
                       Catch::Message("RitzOptions::modes must be >= 0 (0: automatic)"));
  CHECK_THROWS_MATCHES(require(false, "X::y", "must be in [0, {}), got {}", 1e-3, -1), std::invalid_argument,
                       Catch::Message("X::y must be in [0, 0.001), got -1"));
}
