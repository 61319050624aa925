#include "continuation/trace.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace liftoff::continuation {

void TraceOptions::validate(double member_begin, double member_end) const {
  const auto fail = [](const std::string& what) { throw std::invalid_argument("TraceOptions." + what); };
  try {
    arc_length.validate();
  } catch (const std::invalid_argument& e) {  // named as a field of the trace's options
    const std::string what = e.what(), prefix = "ArcLengthOptions.";
    fail("arc_length." + (what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what));
  }
  if (!(event_tolerance > 0)) fail(fmt::format("event_tolerance: expected > 0, got {}", event_tolerance));
  if (elements < 1) fail(fmt::format("elements: expected >= 1, got {}", elements));
  if (ritz.modes < 0) fail(fmt::format("ritz.modes: expected >= 0 (0: automatic), got {}", ritz.modes));
  if (ritz.max_modes < 1) fail(fmt::format("ritz.max_modes: expected >= 1, got {}", ritz.max_modes));
  if (!(ritz.mode_tolerance > 0)) fail(fmt::format("ritz.mode_tolerance: expected > 0, got {}", ritz.mode_tolerance));
  if (!ritz.topology.empty() && !ritz.limits.empty() && ritz.limits.size() + 1 != ritz.topology.size())
    fail(fmt::format("ritz.limits: expected none or {} (one per change of piece), got {}", ritz.topology.size() - 1,
                     ritz.limits.size()));
  const double lo = std::min(member_begin, member_end), hi = std::max(member_begin, member_end);
  for (double p : sample_points)
    if (!(p >= lo && p <= hi)) fail(fmt::format("sample_points: expected positions in [{}, {}], got {}", lo, hi, p));
  if (!(monitor >= lo && monitor <= hi))
    fail(fmt::format("monitor: expected a position in [{}, {}], got {}", lo, hi, monitor));
  if (max_amplitude && !(*max_amplitude > 0.0))
    fail(fmt::format("max_amplitude: expected a length > 0, got {}", *max_amplitude));
  for (double lambda : report_at)
    if (!(lambda >= std::min(arc_length.lambda_min, arc_length.lambda_max) &&
          lambda <= std::max(arc_length.lambda_min, arc_length.lambda_max)))
      fail(fmt::format("report_at: expected load factors in [{}, {}], got {}", arc_length.lambda_min,
                       arc_length.lambda_max, lambda));
  if (physical_load && !(std::isfinite(physical_load->reference) && physical_load->reference != 0.0))
    fail(fmt::format("physical_load.reference: expected a finite nonzero value, got {}", physical_load->reference));
  if (resume_from && !std::isfinite(resume_from->load_factor))
    fail("resume_from: the step's load factor must be finite");
}

}  // namespace liftoff::continuation
