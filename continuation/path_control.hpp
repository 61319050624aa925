#pragma once
// How a load history is followed: pseudo-arc-length (default: through folds) or plain load control
// (lambda stepped directly). Its own header so that the path follower (arclength.hpp) and the
// trace options that nest its options (trace.hpp) share it without including each other.

namespace liftoff::continuation {

enum class PathControl { arc_length, load };

}  // namespace liftoff::continuation
