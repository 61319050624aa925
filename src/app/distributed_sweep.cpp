#include "app/distributed_sweep.hpp"

#include <fmt/format.h>
#include <mpi.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <limits>
#include <mutex>
#include <thread>

#include "core/error.hpp"
#include "io/hdf5_writer.hpp"

namespace liftoff::app::mpi {

namespace {

bool initialised = false;

// Set by mpirun/mpiexec (Open MPI, MPICH/Hydra) or srun --mpi=pmix|pmi2 in every rank's environment;
// not SLURM_PROCID, which a batch script's own single process has too.
bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "PMI_RANK"})
    if (std::getenv(name) != nullptr) return true;
  return false;
}

// A failure of the distribution itself: every rank stops (no rank may wait for a message that
// will never come).
[[noreturn]] void abort_all(const std::string& why) {
  std::cerr << "liftoff: internal error: distributed sweep, rank " << rank() << ": " << why << "\n" << std::flush;
  MPI_Abort(MPI_COMM_WORLD, static_cast<int>(ExitCode::internal_error));
  std::abort();
}

void checked(int status, const char* what) {
  if (status != MPI_SUCCESS) abort_all(fmt::format("{} failed (MPI error {})", what, status));
}

// One case's result as bytes: what rank 0 needs of it (DistributedSweep).
class Writer {
 public:
  void number(std::uint64_t v) { bytes(&v, sizeof v); }
  void text(const std::string& s) {
    number(s.size());
    bytes(s.data(), s.size());
  }
  void block(const std::vector<char>& b) {
    number(b.size());
    bytes(b.data(), b.size());
  }
  std::vector<char> buffer;

 private:
  void bytes(const void* p, std::size_t n) {
    const char* c = static_cast<const char*>(p);
    buffer.insert(buffer.end(), c, c + n);
  }
};

class Reader {
 public:
  explicit Reader(const std::vector<char>& b) : buffer_(b) {}
  std::uint64_t number() {
    std::uint64_t v = 0;
    std::memcpy(&v, take(sizeof v), sizeof v);
    return v;
  }
  std::string text() {
    const std::size_t n = number();
    return {take(n), n};
  }
  std::vector<char> block() {
    const std::size_t n = number();
    const char* p = take(n);
    return {p, p + n};
  }

 private:
  const char* take(std::size_t n) {
    if (n > buffer_.size() - at_) abort_all("a case's message is shorter than its contents");
    const char* p = buffer_.data() + at_;
    at_ += n;
    return p;
  }
  const std::vector<char>& buffer_;
  std::size_t at_ = 0;
};

std::string csv_rows(const std::vector<std::string>& keys, const io::SweepCase& c) {
  const std::string csv = io::sweep_csv(keys, {c});
  return csv.substr(csv.find('\n') + 1);  // without the header
}

std::vector<char> pack(std::size_t index, const io::SweepCase& c, const std::vector<std::string>& keys,
                       const std::vector<char>& image) {
  Writer w;
  w.number(index);
  w.text(c.error);
  w.number(c.reports.size());
  for (const io::SolveReport& r : c.reports) {
    w.text(r.scene_name);
    w.text(r.termination);
    w.number(r.usable ? 1 : 0);
    w.number(r.outcome == io::SolveOutcome::refused ? 1 : 0);
    w.number(r.warnings.size());
    for (const std::string& warning : r.warnings) w.text(warning);
  }
  w.text(csv_rows(keys, c));
  w.block(image);
  return w.buffer;
}

// Fills case `index` of `out` from a message; returns the index.
std::size_t unpack(const std::vector<char>& message, const scene::Units& units, DistributedSweep& out,
                   std::vector<std::string>& rows) {
  Reader r(message);
  const std::size_t index = r.number();
  if (index >= out.cases.size() || !rows[index].empty()) abort_all(fmt::format("case {} received twice", index));
  io::SweepCase& c = out.cases[index];
  c.error = r.text();
  c.reports.resize(r.number());
  for (io::SolveReport& report : c.reports) {
    report.scene_name = r.text();
    report.termination = r.text();
    report.usable = r.number() != 0;
    report.outcome = r.number() != 0 ? io::SolveOutcome::refused : io::SolveOutcome::ran;
    report.warnings.resize(r.number());
    for (std::string& warning : report.warnings) warning = r.text();
    report.units = units;  // labels from the scene, the same for every case
  }
  rows[index] = r.text();
  if (rows[index].empty()) abort_all(fmt::format("case {} has no CSV row", index));
  out.images[index] = r.block();
  return index;
}

constexpr int tag_count = 1, tag_case = 2;

}  // namespace

Session::Session(int& argc, char**& argv) {
  if (!launched_by_mpi()) return;
  int provided = 0;
  // Serialized: a rank's threads take turns at MPI (the counter), each under one lock.
  if (MPI_Init_thread(&argc, &argv, MPI_THREAD_SERIALIZED, &provided) != MPI_SUCCESS) {
    std::cerr << "liftoff: internal error: MPI_Init_thread failed\n";
    std::exit(static_cast<int>(ExitCode::internal_error));
  }
  initialised = true;
  if (provided < MPI_THREAD_SERIALIZED) abort_all("the MPI library does not provide MPI_THREAD_SERIALIZED");
}

Session::~Session() {
  if (initialised) MPI_Finalize();
}

int Session::agreed_exit_code(int code) const {
  if (!initialised) return code;
  checked(MPI_Bcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Bcast of the exit code");
  return code;
}

bool active() { return initialised; }

int rank() {
  int r = 0;
  if (initialised) MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

int size() {
  int s = 1;
  if (initialised) MPI_Comm_size(MPI_COMM_WORLD, &s);
  return s;
}

bool all_ready(bool ok) {
  if (!initialised) return ok;
  int mine = ok ? 1 : 0, all = 0;
  checked(MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD), "MPI_Allreduce of the start");
  return all == 1;
}

DistributedSweep run_distributed_sweep(SweepGrid grid, const std::vector<std::string>& keys,
                                       const SolveRequest& request, bool all, int threads, bool images,
                                       const std::function<void(int, int)>& progress) {
  const std::size_t total = grid.cases.size();
  const bool leader = rank() == 0;

  // The shared counter: one long on rank 0, read and incremented atomically by MPI_Fetch_and_op.
  long* counter = nullptr;
  MPI_Win window = MPI_WIN_NULL;
  checked(MPI_Win_allocate(leader ? sizeof(long) : 0, sizeof(long), MPI_INFO_NULL, MPI_COMM_WORLD, &counter, &window),
          "MPI_Win_allocate");
  if (leader) *counter = 0;
  checked(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier");  // the counter is 0 before anyone takes a case
  checked(MPI_Win_lock_all(0, window), "MPI_Win_lock_all");

  std::mutex mpi_lock;      // MPI_THREAD_SERIALIZED: one thread of the rank in MPI at a time
  std::mutex results_lock;  // messages, and HDF5 (not thread-safe) for the images
  std::vector<std::vector<char>> messages;
  auto next_case = [&] {
    const std::lock_guard<std::mutex> lock(mpi_lock);
    const long one = 1;
    long taken = 0;
    checked(MPI_Fetch_and_op(&one, &taken, MPI_LONG, 0, 0, MPI_SUM, window), "MPI_Fetch_and_op");
    checked(MPI_Win_flush(0, window), "MPI_Win_flush");
    return static_cast<std::size_t>(taken);
  };
  auto worker = [&] {
    try {
      for (std::size_t i = next_case(); i < total; i = next_case()) {
        solve_sweep_case(grid, i, request, all);
        const std::lock_guard<std::mutex> lock(results_lock);
        messages.push_back(
            pack(i, grid.cases[i], keys, images ? io::sweep_case_image(grid.cases[i]) : std::vector<char>{}));
        grid.cases[i].reports.clear();  // packed: its memory is the message's now
        if (leader && progress) progress(static_cast<int>(std::min(i + 1, total - 1)), static_cast<int>(total));
      }
    } catch (const std::exception& e) {  // not a case's failure (solve_sweep_case keeps those): ours
      abort_all(e.what());
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < std::max(1, threads); ++t) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  checked(MPI_Win_unlock_all(window), "MPI_Win_unlock_all");
  checked(MPI_Win_free(&window), "MPI_Win_free");

  DistributedSweep out;
  if (!leader) {  // to rank 0: the count, then one message per case
    const std::uint64_t count = messages.size();
    checked(MPI_Send(&count, 1, MPI_UINT64_T, 0, tag_count, MPI_COMM_WORLD), "MPI_Send");
    for (const auto& m : messages) {
      if (m.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
        abort_all("a case's result is larger than 2 GiB, more than one MPI message holds");
      checked(MPI_Send(m.data(), static_cast<int>(m.size()), MPI_BYTE, 0, tag_case, MPI_COMM_WORLD), "MPI_Send");
    }
    return out;
  }
  out.cases.resize(total);
  out.images.resize(total);
  for (std::size_t i = 0; i < total; ++i) out.cases[i].values = grid.cases[i].values;
  const scene::Units units = grid.scenes.empty() ? scene::Units{} : grid.scenes.front().units;
  std::vector<std::string> rows(total);
  std::size_t received = 0;
  for (const auto& m : messages) unpack(m, units, out, rows), ++received;
  for (int source = 1; source < size(); ++source) {
    std::uint64_t count = 0;
    checked(MPI_Recv(&count, 1, MPI_UINT64_T, source, tag_count, MPI_COMM_WORLD, MPI_STATUS_IGNORE), "MPI_Recv");
    for (std::uint64_t k = 0; k < count; ++k) {
      MPI_Status status;
      checked(MPI_Probe(source, tag_case, MPI_COMM_WORLD, &status), "MPI_Probe");
      int bytes = 0;
      checked(MPI_Get_count(&status, MPI_BYTE, &bytes), "MPI_Get_count");
      std::vector<char> message(static_cast<std::size_t>(bytes));
      checked(MPI_Recv(message.data(), bytes, MPI_BYTE, source, tag_case, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
              "MPI_Recv");
      unpack(message, units, out, rows);
      ++received;
    }
  }
  if (received != total) abort_all(fmt::format("{} of {} cases received", received, total));
  out.csv = io::sweep_csv(keys, {});
  for (const std::string& row : rows) out.csv += row;
  if (!images) out.images.clear();
  if (progress) progress(static_cast<int>(total), static_cast<int>(total));
  return out;
}

}  // namespace liftoff::app::mpi
