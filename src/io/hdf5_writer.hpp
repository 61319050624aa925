#pragma once
// The one place that talks to HDF5. A result file is written under a temporary name and
// renamed when complete, so a failed run never leaves a half-written file (OutputError).
//
// Layout (src/io/README.md, "`liftoff solve`", HDF5):
//   /                 attributes: liftoff_version, scene_name, structure, method, method_requested,
//                     termination, message, coordinate, sign_convention, tensionless, k
//   /scene            the scene's TOML text
//   /contact_regions  n x 2, [begin, end] in the user's coordinate
//   /fields/*         coordinate, w, rotation, bending_moment, shear_force, reaction
//                     (+ u, normal_force for arches), sampled inside every element
//   /nodes/*          coordinate, w, rotation, reaction (+ u) at the mesh nodes (FE only); beams
//                     with an initial shape also w_initial, under an axial force buckling_mode
//                     (max |w| = 1, w > 0 into the foundation)
//   /stability        beams under an axial force: attributes stability, critical_load_factor,
//                     critical_axial_force (NaN: none), lower_bound, upper_bound, method,
//                     termination, message, warning (io/report.hpp's StabilityTable)
//   /certificate      attributes: passed, message, foundation_resultant, foundation_centroid,
//                     applied_force, applied_moment (arches also the _x components), and per check
//                     <name> and <name>_tolerance (certify/certificate.hpp)
//   /no_equilibrium_certificate  a Lemke ray's no_equilibrium only: attributes kind ("lemke_ray"),
//                     formulation, q_dot_ray; dataset ray (io/report.hpp's RayCertificate)
//   /support_reactions  n x 3: at, force, moment (arches n x 6: + tangential, horizontal, vertical), the user's units
//   /design           attributes: moment_max, moment_min, shear_max_abs, pressure_max, uplift_max and
//                     each's <name>_at (NaN: no such point), from_statics, shear_closure,
//                     moment_closure (io/report.hpp's DesignTable, post/design.hpp)
//   /solver           attributes: residual, time_s, method_reason; FE: elements, pivots,
//                     lcp_size; Ritz: modes, newton_iterations, estimated_limit_error, topology,
//                     and datasets amplitudes, residual_history

#include <filesystem>

#include "io/report.hpp"

namespace liftoff::io {

// PATH.tmp: where write_hdf5 and write_sweep_hdf5 write before renaming onto PATH (the front end
// checks that it is no input of the run either).
std::filesystem::path temporary_path(const std::filesystem::path& path);

void write_hdf5(const SolveReport& report, const std::filesystem::path& path, const std::string& version);

// A sweep: root attributes liftoff_version, keys (the swept scene keys, comma-separated);
// /values (cases x keys); /cases/NNNN/METHOD/ (METHOD as requested) with the layout above for every case and method
// (and an attribute `error` on /cases/NNNN when the case failed).
void write_sweep_hdf5(const std::vector<std::string>& keys, const std::vector<SweepCase>& cases,
                      const std::filesystem::path& path, const std::string& version);

// The distributed sweep (src/mpi/): a case solved on another process travels as the image of an
// in-memory HDF5 file whose group /case holds what /cases/NNNN holds; write_sweep_hdf5 with the
// images writes the root from `cases` (values, and the units from any case's first report) and
// copies image i's /case to /cases/NNNN (H5Ocopy): the same file as write_sweep_hdf5 above.
std::vector<char> sweep_case_image(const SweepCase& c);
void write_sweep_hdf5(const std::vector<std::string>& keys, const std::vector<SweepCase>& cases,
                      const std::vector<std::vector<char>>& images, const std::filesystem::path& path,
                      const std::string& version);

}  // namespace liftoff::io
