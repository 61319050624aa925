#pragma once
// The units of a result file, for the writers that talk to HDF5 (solve, sweep, envelope).

#include <hdf5.h>

#include "scene/units.hpp"

namespace liftoff::io {

// Attributes units_system and units_<name> for every label of scene::unit_labels (units_length,
// units_force, ...) on an HDF5 object; empty strings when the scene states no units: what plots
// label their axes with. Every result file stores them on its root.
void write_units(hid_t object, const scene::Units& units);

}  // namespace liftoff::io
