// The fields CSV: its columns for beams and arches, and no file after a failure.
#include "io/csv_writer.hpp"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "io/hdf5_writer.hpp"
#include "support/scratch.hpp"

using namespace liftoff;

namespace {
io::SolveReport two_points(scene::StructureKind kind) {
  io::SolveReport r;
  r.kind = kind;
  io::FieldTable& f = r.fields;
  f.coordinate = {0.0, 1.5};
  f.w = {1e-3, -2e-3};
  f.rotation = {0.1, 0.2};
  f.bending_moment = {0.0, -7.25};
  f.shear_force = {3.0, 0.0};
  f.reaction = {10.0, 0.0};
  if (kind == scene::StructureKind::arch) f.u = {0.5, 0.25}, f.normal_force = {-4.0, -5.0};
  return r;
}
}  // namespace

TEST_CASE("fields CSV: a header and one row per sample, every digit kept", "[io][csv]") {
  const std::string beam = io::fields_csv(two_points(scene::StructureKind::beam));
  CHECK(beam ==
        "x,w,rotation,moment,shear,reaction\n0,0.001,0.10000000000000001,0,3,10\n"
        "1.5,-0.002,0.20000000000000001,-7.25,0,0\n");
  const std::string arch = io::fields_csv(two_points(scene::StructureKind::arch));
  CHECK(arch.substr(0, arch.find('\n')) == "theta_deg,w,rotation,moment,shear,reaction,u,normal_force");
  CHECK(arch.find("1.5,-0.002,0.20000000000000001,-7.25,0,0,0.25,-5\n") != std::string::npos);
}

TEST_CASE("fields CSV: written whole or not at all", "[io][csv]") {
  namespace fs = std::filesystem;
  const test::Scratch scratch("liftoff_csv_test");
  const fs::path path = scratch.dir / "fields.csv";
  io::write_fields_csv(two_points(scene::StructureKind::beam), path);
  CHECK(fs::exists(path));
  CHECK_FALSE(fs::exists(io::temporary_path(path)));
  const fs::path missing = scratch.dir / "no_such_dir" / "fields.csv";
  CHECK_THROWS_AS(io::write_fields_csv(two_points(scene::StructureKind::beam), missing), OutputError);
  CHECK_FALSE(fs::exists(missing));
  CHECK_FALSE(fs::exists(io::temporary_path(missing)));
}
