#pragma once
// `liftoff solve` for a von Karman beam or circular arch ([structure] theory = "von_karman"), FE:
// the member on the scene's mesh (fe::discretise), its von Karman system
// (contact/von_karman_solve.hpp; arches: the Marguerre/Donnell element), the whole
// load reached from zero along the load path (contact/von_karman_loading.hpp: dead loads first,
// then the live load), the answer certified from its fields (certify::certify of a
// VonKarmanAnswer) and reported with its membrane force, axial displacement, stability and axial
// support reactions (io/report.hpp). A path that meets a limit point before the whole load is
// refused: termination "limit_point", the load factor reached in the message (a snap-through is
// not a static answer; `liftoff trace --path ritz` follows it). Arches take the same load path
// rather than one solve at the whole load: past a limit point a solve from zero may land on any
// equilibrium of the load, and the path is what tells the loading's own branch (and refuses a
// snap-through); on the seed's arch it costs a few tens of solves. Their membrane force is reported
// per element as its mean (N varies along an arch), in the fields at every sample, and u at the
// nodes and samples. Internal to app/solve_command.cpp.

#include <optional>
#include <vector>

#include "app/solve_command.hpp"
#include "core/contact_region.hpp"
#include "io/report.hpp"
#include "scene/scene.hpp"

namespace liftoff::app {

// method_requested: "auto" or "fast" (both run this). Throws InputError for a scene it cannot
// take (settled supports: the load path would apply them at once), MechanismError for a
// mechanism, with the scene's name.
io::SolveReport von_karman_fe_report(const scene::Scene& scene, const SolveRequest& request,
                                     std::string_view method_requested);

// The contact regions (user coordinate) of the von Karman FE answer on the scene's mesh: the
// Ritz model's topology and initial limits when the scene does not give them (a linear answer's
// contact pattern may not be the von Karman one). Throws SolverFailure when there is no answer.
std::vector<ContactRegion> von_karman_fe_regions(const scene::Scene& scene, int elements);

}  // namespace liftoff::app
