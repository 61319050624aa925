// The incremental HDF5 trace: what is appended reads back exactly, an interrupted step's rows
// are dropped on resume, and a resumed file continues where it stopped.
#include "io/trace_writer.hpp"

#include <hdf5.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "support/scratch.hpp"

using namespace liftoff;
using continuation::EventKind;
using continuation::TraceEvent;
using continuation::TraceStep;
namespace fs = std::filesystem;

using namespace liftoff::test;  // support/: the scratch directory

namespace {

io::TraceFileInfo info() {
  io::TraceFileInfo i;
  i.version = "test";
  i.scene_name = "scene.toml";
  i.scene_text = "[structure]\nkind = \"beam\"\n";
  i.coordinate = "x";
  i.options = R"({"method":"dual"})";
  i.paths = {"fe", "ritz"};
  i.sample_points = {0.0, 0.5, 1.0};
  return i;
}

// Step i: distinct values everywhere, a number of contact regions and of state values that
// varies from step to step (as the Ritz topology does).
TraceStep step(int i) {
  TraceStep s;
  s.load_factor = 0.25 * i;
  s.monitor_deflection = -0.01 * i;
  s.deflection = {1.0 + i, 2.0 + i, 3.0 + i};
  s.reaction = {10.0 * i, 20.0 * i, 30.0 * i};
  s.iterations = i + 2;
  for (int r = 0; r <= i % 3; ++r) s.contact_regions.push_back({0.1 * r, 0.1 * r + 0.05});
  // Each kind of topology in turn: Ritz, Ritz at an event, FE, none.
  if (i % 4 == 0) s.state_topology = continuation::RitzTopology{i % 8 == 0, i % 3, 8 + i, std::nullopt};
  if (i % 4 == 1)
    s.state_topology = continuation::RitzTopology{true, 2, 16, continuation::RitzOpening{-1.0, 1e-3 / (i + 3)}};
  if (i % 4 == 2) s.state_topology = continuation::FeContactSet{};
  for (int k = 0; k < i % 4; ++k) s.state.push_back(i + 0.5 * k);
  return s;
}

void check_equal(const TraceStep& a, const TraceStep& b) {
  CHECK(a.load_factor == b.load_factor);
  CHECK(a.monitor_deflection == b.monitor_deflection);
  CHECK(a.deflection == b.deflection);
  CHECK(a.reaction == b.reaction);
  CHECK(a.iterations == b.iterations);
  CHECK(a.contact_regions == b.contact_regions);
  CHECK(a.state_topology == b.state_topology);
  CHECK(a.state == b.state);
}

// Step i with the whole state a path records (continuation/step_state.hpp): fields at four nodes
// (u too), design values (none at step 1, no uplift point at step 3), two supports, the physical
// load; step 2 is a requested one.
TraceStep whole_step(int i) {
  TraceStep s = step(i);
  s.load = 1e6 * s.load_factor;
  s.requested = i == 2;
  post::FieldTable& f = s.fields;
  f.coordinate = {0.0, 1.0, 2.5, 3.0};
  for (int k = 0; k < 4; ++k) {
    f.w.push_back(1e-3 * (i + 1) * (k - 1.5));
    f.u.push_back(-1e-5 * i * k);
    f.rotation.push_back(1e-4 * (k + i));
    f.bending_moment.push_back(1e3 * i * (k % 2 == 0 ? 1.0 : -1.0));
    f.shear_force.push_back(50.0 * (k - i));
    f.normal_force.push_back(-1e6 * s.load_factor);
    f.reaction.push_back(k < 2 ? 0.0 : 2e3 * i);
    f.gap.push_back(k < 2 ? 1e-3 * k : 0.0);
  }
  if (i != 1) {
    post::DesignTable d;
    d.moment_max = {1e3 * i, 2.5};
    d.moment_min = {-1e3 * i, 1.0};
    d.shear_max_abs = {50.0 * (3 + i), 3.0};
    d.pressure_max = {2e3 * i, 2.5};
    d.uplift_max = i == 3 ? post::DesignValue{0.0, std::nullopt} : post::DesignValue{1e-3, 1.0};
    d.shear_closure = 1e-16 * i;
    d.moment_closure = 2e-16 * i;
    d.from_statics = true;
    s.design = d;
  }
  s.supports = {{0.0, 10.0 * i, -2.0 * i, 0.0, false, 0.0}, {3.0, 5.0 * i, 0.0, 0.5, true, 0.01}};
  return s;
}

void check_whole_equal(const TraceStep& a, const TraceStep& b) {
  check_equal(a, b);
  CHECK(a.load == b.load);
  CHECK(a.requested == b.requested);
  for (auto field : {&post::FieldTable::coordinate, &post::FieldTable::w, &post::FieldTable::u,
                     &post::FieldTable::rotation, &post::FieldTable::bending_moment, &post::FieldTable::shear_force,
                     &post::FieldTable::normal_force, &post::FieldTable::reaction, &post::FieldTable::gap})
    CHECK(a.fields.*field == b.fields.*field);
  REQUIRE(a.design.has_value() == b.design.has_value());
  if (a.design) {
    for (auto value :
         {&post::DesignTable::moment_max, &post::DesignTable::moment_min, &post::DesignTable::shear_max_abs,
          &post::DesignTable::pressure_max, &post::DesignTable::uplift_max}) {
      CHECK(((*a.design).*value).value == ((*b.design).*value).value);
      CHECK(((*a.design).*value).at == ((*b.design).*value).at);
    }
    CHECK(a.design->shear_closure == b.design->shear_closure);
    CHECK(a.design->moment_closure == b.design->moment_closure);
    CHECK(a.design->from_statics == b.design->from_statics);
  }
  CHECK(a.supports == b.supports);
}

// The dimensions of a dataset of the file (empty if there is none), and whether it is chunked.
std::vector<hsize_t> dims_of(const fs::path& path, const std::string& name, bool* chunked = nullptr) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  std::vector<hsize_t> dims;
  if (file < 0) return dims;
  if (H5Oexists_by_name(file, name.c_str(), H5P_DEFAULT) > 0) {
    const hid_t dataset = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
    const hid_t space = H5Dget_space(dataset);
    dims.resize(H5Sget_simple_extent_ndims(space));
    H5Sget_simple_extent_dims(space, dims.data(), nullptr);
    const hid_t plist = H5Dget_create_plist(dataset);
    if (chunked) *chunked = H5Pget_layout(plist) == H5D_CHUNKED;
    H5Pclose(plist);
    H5Sclose(space);
    H5Dclose(dataset);
  }
  H5Fclose(file);
  return dims;
}

}  // namespace

TEST_CASE("trace writer: the whole state of every step reads back, laid out steps x nodes", "[io][trace]") {
  Scratch scratch;
  const fs::path path = scratch.dir / "trace.h5";
  io::TraceFileInfo with_load = info();
  with_load.physical_load = continuation::PhysicalLoad{"axial force", "N", 1e6, "N", "the live axial force (loads[1])"};
  {
    io::TraceWriter writer(path, with_load);
    writer.begin_path("fe", 0.5);
    for (int i = 0; i < 4; ++i) writer.append_step("fe", whole_step(i));
  }
  const io::TraceFileRecord file = io::read_trace_file(path);
  REQUIRE(file.info.physical_load.has_value());
  CHECK(file.info.physical_load->quantity == "axial force");
  CHECK(file.info.physical_load->symbol == "N");
  CHECK(file.info.physical_load->reference == 1e6);
  CHECK(file.info.physical_load->unit == "N");
  CHECK(file.info.physical_load->definition == "the live axial force (loads[1])");
  const io::TracePathRecord& fe = file.paths.at(0).second;
  REQUIRE(fe.steps.size() == 4);
  for (int i = 0; i < 4; ++i) check_whole_equal(fe.steps[i], whole_step(i));
  CHECK(fe.steps[2].requested);  // the requested step is told from the others
  CHECK_FALSE(fe.steps[1].design.has_value());
  CHECK_FALSE(fe.steps[3].design->uplift_max.at.has_value());

  // The layout src/io/README.md gives: per field steps x nodes, chunked; the coordinate once.
  bool chunked = false;
  for (const char* field : {"w", "u", "rotation", "bending_moment", "shear_force", "normal_force", "reaction", "gap"}) {
    CHECK(dims_of(path, std::string("fe/steps/fields/") + field, &chunked) == std::vector<hsize_t>{4, 4});
    CHECK(chunked);
  }
  CHECK(dims_of(path, "fe/steps/fields/coordinate") == std::vector<hsize_t>{4});
  for (const char* one : {"load", "requested", "design/moment_max", "design/moment_max_at", "design/uplift_max_at",
                          "design/from_statics"})
    CHECK(dims_of(path, std::string("fe/steps/") + one) == std::vector<hsize_t>{4});
  CHECK(dims_of(path, "fe/steps/supports") == std::vector<hsize_t>{8, 7});  // two rows per step
}

TEST_CASE("trace writer: a resumed trace appends the whole state's rows the same way", "[io][trace]") {
  Scratch scratch;
  const fs::path path = scratch.dir / "trace.h5";
  {
    io::TraceWriter writer(path, info());
    writer.begin_path("fe", 0.5);
    for (int i = 0; i < 3; ++i) writer.append_step("fe", whole_step(i));
  }
  {
    io::TraceWriter writer = io::TraceWriter::resume(path);
    check_whole_equal(writer.read_path("fe")->steps.back(), whole_step(2));
    for (int i = 3; i < 5; ++i) writer.append_step("fe", whole_step(i));
  }
  const io::TracePathRecord fe = io::read_trace_file(path).paths.at(0).second;
  REQUIRE(fe.steps.size() == 5);
  for (int i = 0; i < 5; ++i) check_whole_equal(fe.steps[i], whole_step(i));
  CHECK(dims_of(path, "fe/steps/fields/bending_moment") == std::vector<hsize_t>{5, 4});
}

// A file written before the whole state was recorded: its steps have no load, requested, design,
// supports or fields datasets. It reads back, and resumes: the columns are made, its steps
// recording none of them, and the fields begin with the first new step.
TEST_CASE("trace writer: a file of an older liftoff reads back and resumes with the whole state", "[io][trace]") {
  Scratch scratch;
  const fs::path path = scratch.dir / "old.h5";
  {
    io::TraceWriter writer(path, info());
    writer.begin_path("fe", 0.5);
    for (int i = 0; i < 2; ++i) writer.append_step("fe", step(i));
  }
  for (const fs::path& copy : {path, io::trace_backup_path(path)}) {
    if (!fs::exists(copy)) continue;
    const hid_t file = H5Fopen(copy.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    REQUIRE(file >= 0);
    for (const char* name : {"fe/steps/load", "fe/steps/requested", "fe/steps/supports", "fe/steps/design"})
      REQUIRE(H5Ldelete(file, name, H5P_DEFAULT) >= 0);
    H5Fclose(file);
  }
  const io::TracePathRecord old = io::read_trace_file(path).paths.at(0).second;
  REQUIRE(old.steps.size() == 2);
  for (int i = 0; i < 2; ++i) check_whole_equal(old.steps[i], step(i));
  {
    io::TraceWriter writer = io::TraceWriter::resume(path);
    for (int i = 2; i < 4; ++i) writer.append_step("fe", whole_step(i));
  }
  const io::TracePathRecord fe = io::read_trace_file(path).paths.at(0).second;
  REQUIRE(fe.steps.size() == 4);
  for (int i = 0; i < 2; ++i) check_whole_equal(fe.steps[i], step(i));
  for (int i = 2; i < 4; ++i) check_whole_equal(fe.steps[i], whole_step(i));
  CHECK(dims_of(path, "fe/steps/fields/w") == std::vector<hsize_t>{2, 4});
  CHECK(dims_of(path, "fe/steps/design/moment_max") == std::vector<hsize_t>{4});
}

TEST_CASE("trace writer: a step whose fields do not match its path's earlier steps is refused", "[io][trace]") {
  Scratch scratch;
  io::TraceWriter writer(scratch.dir / "t.h5", info());
  writer.begin_path("fe", 0.0);
  writer.append_step("fe", whole_step(0));
  TraceStep fewer = whole_step(1);
  fewer.fields.w.pop_back();
  CHECK_THROWS_AS(writer.append_step("fe", fewer), OutputError);
  TraceStep elsewhere = whole_step(1);
  elsewhere.fields.coordinate[1] = 1.5;
  CHECK_THROWS_AS(writer.append_step("fe", elsewhere), OutputError);
  TraceStep without = whole_step(1);
  without.fields = {};
  CHECK_THROWS_AS(writer.append_step("fe", without), OutputError);
  writer.append_step("fe", whole_step(1));  // nothing of the refused ones was written
  CHECK(writer.read_path("fe")->steps.size() == 2);
}

TEST_CASE("trace writer: steps and events read back exactly, the file is readable while open", "[io][trace]") {
  Scratch scratch;
  const fs::path path = scratch.dir / "trace.h5";
  io::TraceWriter writer(path, info());
  writer.begin_path("fe", 0.5);
  for (int i = 0; i < 5; ++i) writer.append_step("fe", step(i));
  writer.append_event("fe", {0.8, EventKind::lift_off_opens, 0.5, "a lift-off zone opens at x = 0.5"});

  // What the file holds so far, through the writer's own handle (what a resumed run reads).
  const io::TracePathRecord live = *writer.read_path("fe");
  CHECK(live.steps.size() == 5);
  CHECK_FALSE(live.complete);
  CHECK_FALSE(writer.read_path("ritz").has_value());

  continuation::TraceSummary summary;
  summary.termination = continuation::TraceTermination::completed;
  summary.message = "lambda_max reached";
  writer.end_path("fe", summary);
  writer.begin_path("ritz", 0.5);
  writer.append_step("ritz", step(7));
  writer.end_path("ritz", summary);
  writer.finish();

  const io::TraceFileRecord file = io::read_trace_file(path);
  CHECK(file.complete);
  CHECK(file.info.paths == info().paths);
  CHECK(file.info.scene_text == info().scene_text);
  CHECK(file.info.options == info().options);
  CHECK(file.info.sample_points == info().sample_points);
  REQUIRE(file.paths.size() == 2);
  const io::TracePathRecord& fe = file.paths[0].second;
  CHECK(file.paths[0].first == "fe");
  CHECK(fe.complete);
  CHECK(fe.termination == "completed");
  CHECK(fe.message == "lambda_max reached");
  CHECK(fe.monitor == 0.5);
  REQUIRE(fe.steps.size() == 5);
  for (int i = 0; i < 5; ++i) check_equal(fe.steps[i], step(i));
  REQUIRE(fe.events.size() == 1);
  CHECK(fe.events[0].load_factor == 0.8);
  CHECK(fe.events[0].kind == EventKind::lift_off_opens);
  CHECK(fe.events[0].at == 0.5);
  CHECK(fe.events[0].description == "a lift-off zone opens at x = 0.5");
  REQUIRE(file.paths[1].second.steps.size() == 1);
  check_equal(file.paths[1].second.steps[0], step(7));
}

TEST_CASE("trace writer: resume drops a half-written step and continues the file", "[io][trace]") {
  Scratch scratch;
  const fs::path path = scratch.dir / "trace.h5";
  {
    io::TraceWriter writer(path, info());
    writer.begin_path("fe", 0.5);
    for (int i = 0; i < 3; ++i) writer.append_step("fe", step(i));
    writer.append_event("fe", {0.3, EventKind::contact_opens, 0.25, "after step 2"});
  }
  // A run killed inside step 3's writes: some of its rows are there, lambda's is not. Written
  // here with the C API, as the writer would have left them.
  {
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    REQUIRE(file >= 0);
    for (const char* name : {"fe/steps/contact_regions", "fe/steps/deflection", "fe/events/lambda"}) {
      const hid_t dataset = H5Dopen2(file, name, H5P_DEFAULT);
      const hid_t space = H5Dget_space(dataset);
      hsize_t dims[2] = {0, 0};
      H5Sget_simple_extent_dims(space, dims, nullptr);
      dims[0] += 1;
      REQUIRE(H5Dset_extent(dataset, dims) >= 0);
      H5Sclose(space);
      H5Dclose(dataset);
    }
    H5Fclose(file);
  }
  const io::TraceFileRecord before = io::read_trace_file(path);
  REQUIRE(before.paths[0].second.steps.size() == 3);  // the reader already ignores the partial rows

  {
    io::TraceWriter writer = io::TraceWriter::resume(path);
    CHECK(writer.info().paths == info().paths);
    const io::TracePathRecord record = *writer.read_path("fe");
    REQUIRE(record.steps.size() == 3);
    check_equal(record.steps.back(), step(2));  // what the path resumes from, state included
    CHECK(record.events.size() == 1);
    for (int i = 3; i < 6; ++i) writer.append_step("fe", step(i));
  }
  const io::TracePathRecord after = io::read_trace_file(path).paths[0].second;
  REQUIRE(after.steps.size() == 6);
  for (int i = 0; i < 6; ++i) check_equal(after.steps[i], step(i));  // regions and state rows line up
  REQUIRE(after.events.size() == 1);
  CHECK(after.events[0].description == "after step 2");
}

TEST_CASE("trace writer: a file that is not a trace is refused", "[io][trace]") {
  Scratch scratch;
  const fs::path text = scratch.dir / "not.h5";
  { std::ofstream(text) << "not hdf5"; }
  CHECK_THROWS_AS(io::TraceWriter::resume(text), OutputError);
  CHECK_THROWS_AS(io::read_trace_file(scratch.dir / "missing.h5"), OutputError);
  CHECK_THROWS_AS(io::TraceWriter(scratch.dir / "no" / "such" / "dir.h5", info()), OutputError);
  io::TraceWriter writer(scratch.dir / "t.h5", info());
  writer.begin_path("fe", 0.0);
  TraceStep wrong = step(1);
  wrong.deflection.pop_back();
  CHECK_THROWS_AS(writer.append_step("fe", wrong), OutputError);
}

// The text of /PATH/steps/state_topology is what liftoff wrote before the topology was typed, so
// that older files resume: it is checked here word for word, both ways.
TEST_CASE("state topologies are stored as the text older files hold") {
  const std::vector<std::pair<continuation::StateTopology, std::string>> cases{
      {continuation::RitzTopology{true, 2, 32, std::nullopt}, "1 2 32"},
      {continuation::RitzTopology{false, 0, 8, continuation::RitzOpening{-1.0, 0.0625}}, "0 0 8 event -1 0.0625"},
      {continuation::RitzTopology{true, 1, 16, continuation::RitzOpening{1.0, 1.2345678901234568e-05}},
       "1 1 16 event 1 1.2345678901234568e-05"},
      {continuation::FeContactSet{}, "fe contact set"},
      {std::monostate{}, ""},
  };
  for (const auto& [topology, text] : cases) {
    CHECK(io::state_topology_text(topology) == text);
    CHECK(io::parse_state_topology(text) == topology);
  }
  for (const char* bad : {"contact lift_off", "2 0 8", "1 0", "1 0 8 event 1", "1 0 8 later 1 2", "fe contact"})
    CHECK_THROWS_AS(io::parse_state_topology(bad), OutputError);
}
