// The scene fuzzer: random valid and malformed scenes from a fixed seed, fed to the real `liftoff`
// executable (solve, sweep, trace; several methods; with and without --json and --output), each
// run in a directory of its own with a time limit. Whatever the scene, liftoff must:
//   - end by itself with a documented exit code (0, 2, 3, 4): never 1 (a bug), a signal or a hang,
//     and never with a sanitizer report on stderr (in the sanitizer build);
//   - refuse a certainly invalid scene with exit 2 and one line on stderr naming the file;
//   - with --json print exactly one JSON object on stdout, also on failure (then with
//     `termination`, `message` and `exit_code`);
//   - on failure leave no output file (nor FILE.tmp or FILE.backup) and never change the scene;
//     on success leave exactly the outputs asked for;
//   - certify every answer it calls solved: `certificate.passed` on every object whose
//     termination is `solved` or `converged`, the sweep CSV's `certified` column likewise, and for
//     beams a certificate whose applied force equals the loads of the scene as toml++ reads them
//     (the oracle that catches a number misread on the way in).
//
// Environment: LIFTOFF_FUZZ_SEED (default 20240610), LIFTOFF_FUZZ_SCALE (cases = scale x the
// counts below), LIFTOFF_FUZZ_TIMEOUT (seconds per run, default 60), LIFTOFF_FUZZ_CASE (run
// that case number only), LIFTOFF_FUZZ_EXECUTABLE (fuzz another liftoff binary), LIFTOFF_FUZZ_WRITE=DIR (write
// every case to DIR/<family>-<case>/ (files and command.txt) and run none: the scenes for
// verification/bench/trace_bench.py). Every case that breaks a rule is kept
// under build/fuzz-failures/<family>-<case>/ (scene, command, stdout, stderr) to be rerun by hand.

#include <fmt/format.h>
#include <toml++/toml.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "fuzz/process.hpp"
#include "fuzz/scene_generator.hpp"
#include "support/scene_text.hpp"
#include "support/scratch.hpp"

namespace fs = std::filesystem;
using liftoff::fuzz::Draft;
using liftoff::fuzz::Ended;
using liftoff::fuzz::Random;
using liftoff::fuzz::SceneLimits;

namespace {

// ---------------------------------------------------------------------------------------------
// Settings

double env_number(const char* name, double fallback) {
  const char* text = std::getenv(name);
  return text != nullptr && *text != '\0' ? std::strtod(text, nullptr) : fallback;
}

std::uint64_t seed() { return static_cast<std::uint64_t>(env_number("LIFTOFF_FUZZ_SEED", 20240610)); }
int cases(int base) { return std::max(1, static_cast<int>(std::lround(base * env_number("LIFTOFF_FUZZ_SCALE", 1.0)))); }
double timeout() { return env_number("LIFTOFF_FUZZ_TIMEOUT", 60.0); }
// LIFTOFF_FUZZ_EXECUTABLE: another liftoff to fuzz (a branch's build), instead of this build's.
std::string executable() {
  const char* other = std::getenv("LIFTOFF_FUZZ_EXECUTABLE");
  return other != nullptr && *other != '\0' ? other : LIFTOFF_EXECUTABLE;
}
// LIFTOFF_FUZZ_WRITE: where to write the cases instead of running them.
std::optional<fs::path> write_only_dir() {
  const char* dir = std::getenv("LIFTOFF_FUZZ_WRITE");
  return dir != nullptr && *dir != '\0' ? std::optional<fs::path>(dir) : std::nullopt;
}
std::optional<int> only_case() {
  const double c = env_number("LIFTOFF_FUZZ_CASE", -1);
  return c >= 0 ? std::optional<int>(static_cast<int>(c)) : std::nullopt;
}

// ---------------------------------------------------------------------------------------------
// A case: the files and the command line, and what its outcome may be.

enum class Command { solve, sweep, trace, other };

struct Case {
  std::string description;
  std::map<std::string, std::string> files;  // written into the case's directory; never to change
  std::vector<std::string> args;
  Command command = Command::solve;
  bool json = false;
  std::vector<std::string> outputs;   // files asked for (HDF5 unless they end in .csv)
  bool certainly_invalid = false;     // exit 2 and a message naming `scene`
  std::set<int> allowed{0, 2, 3, 4};  // the exit codes this case may end with
  std::string scene = "scene.toml";
  bool member_known = false;  // a valid scene: contact regions inside [begin, end]
  double begin = 0.0, end = 0.0;
};

// The loads' resultant as the scene says (force > 0 toward the foundation; live loads at lambda
// = 1), read with toml++ alone; for beams only (an arch's radial forces have no single resultant).
struct Resultant {
  double force = 0.0;
  double scale = 0.0;  // sum of the magnitudes: the round-off scale of the sum
};

std::optional<Resultant> beam_resultant(const std::string& text) {
  try {
    const toml::table doc = toml::parse(text);
    if (doc["structure"]["kind"].value_or(std::string()) != "beam") return std::nullopt;
    auto number = [](toml::node_view<const toml::node> v) -> std::optional<double> {
      if (const auto i = v.value_exact<std::int64_t>()) return static_cast<double>(*i);
      return v.value_exact<double>();
    };
    const auto length = number(doc["structure"]["length"]);
    if (!length) return std::nullopt;
    Resultant r;
    if (const toml::array* loads = doc["loads"].as_array()) {
      for (const toml::node& node : *loads) {
        const toml::node_view<const toml::node> load(node);
        const auto value = number(load["value"]);
        const std::string kind = load["kind"].value_or(std::string());
        if (!value) return std::nullopt;
        double term = 0.0;
        if (kind == "force") term = *value;
        if (kind == "uniform")
          term = *value * (number(load["to"]).value_or(*length) - number(load["from"]).value_or(0.0));
        r.force += term;
        r.scale += std::abs(term);
      }
    }
    return r;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// ---------------------------------------------------------------------------------------------
// The rules. Each broken rule is a finding: (rule, detail).

struct Finding {
  std::string rule, detail;
};

bool is_hdf5(const fs::path& path) {
  const std::string head = liftoff::fuzz::read_all(path).substr(0, 8);
  return head == std::string("\x89HDF\r\n\x1a\n", 8);
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    std::string line = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
    const std::size_t cr = line.rfind('\r');  // a progress bar rewrites its line with \r
    if (cr != std::string::npos) line = line.substr(cr + 1);
    if (!line.empty()) out.push_back(line);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return out;
}

// Every object that calls itself solved or converged carries a passing certificate.
void check_certificates(const nlohmann::json& j, const Case& c, std::vector<Finding>& found, bool& any) {
  if (j.is_array()) {
    for (const auto& item : j) check_certificates(item, c, found, any);
    return;
  }
  if (!j.is_object()) return;
  const auto termination = j.find("termination");
  const bool answer = !j.contains("methods");  // `--method all` gathers answers; it is none itself
  if (answer && termination != j.end() && termination->is_string() &&
      (*termination == "solved" || *termination == "converged")) {
    any = true;
    const auto certificate = j.find("certificate");
    if (certificate == j.end() || !certificate->is_object()) {
      found.push_back(
          {"certificate_missing", fmt::format("method {} says {} without a certificate",
                                              j.value("method", std::string("?")), termination->get<std::string>())});
    } else if (!certificate->value("passed", false)) {
      found.push_back({"certificate_failed",
                       fmt::format("method {} says {} but its certificate: {}", j.value("method", std::string("?")),
                                   termination->get<std::string>(), certificate->value("message", std::string("?")))});
    } else if (const auto expected = beam_resultant(c.files.at(c.scene));
               expected && certificate->contains("applied_force")) {
      // Both sides add the same loads in double: their round-off is a few ulps of the sum of
      // magnitudes per term; 1e-10 of it leaves room for a consistent load vector's quadrature.
      const double applied = certificate->value("applied_force", 0.0);
      if (!(std::abs(applied - expected->force) <= 1e-10 * expected->scale + 1e-300))
        found.push_back({"applied_force", fmt::format("certificate applied_force {} but the scene's loads add to {}",
                                                      applied, expected->force)});
    }
    if (c.member_known && j.contains("contact_regions") && j["contact_regions"].is_array()) {
      const double tolerance = 1e-9 * (c.end - c.begin);
      for (const auto& region : j["contact_regions"]) {
        if (!region.is_array() || region.size() != 2 || !region[0].is_number() || !region[1].is_number() ||
            !(region[0].get<double>() >= c.begin - tolerance && region[0].get<double>() <= region[1].get<double>() &&
              region[1].get<double>() <= c.end + tolerance))
          found.push_back(
              {"contact_region", fmt::format("contact region {} outside [{}, {}]", region.dump(), c.begin, c.end)});
      }
    }
    for (const char* key : {"w_max", "w_min", "max_reaction", "residual"})
      if (j.contains(key) && !j[key].is_number())
        found.push_back({"json_non_finite", fmt::format("{} is {}", key, j[key].dump())});
  }
  for (const auto& [key, value] : j.items()) check_certificates(value, c, found, any);
}

// `--method all` (or a sweep of it): the FE methods (primal, dual, fast) solve one discrete LCP,
// whose solution is unique (P = C K^-1 C^T + T is positive definite), so two answers both called
// solved must agree. Round-off may part them by eps cond(P), never by a tenth of the deflection
// scale: beyond that one of them is a wrong answer labelled solved.
struct FeAnswer {
  std::string method;
  double w_max, w_min;
};
void check_agreement(const std::vector<FeAnswer>& answers, const std::string& where, std::vector<Finding>& found) {
  double scale = 0.0;
  for (const auto& a : answers) scale = std::max({scale, std::abs(a.w_max), std::abs(a.w_min)});
  for (std::size_t i = 0; i < answers.size(); ++i)
    for (std::size_t j = i + 1; j < answers.size(); ++j) {
      const double gap =
          std::max(std::abs(answers[i].w_max - answers[j].w_max), std::abs(answers[i].w_min - answers[j].w_min));
      if (gap > 0.1 * scale)
        found.push_back({"fe_methods_disagree", fmt::format("{}{} (w {} .. {}) and {} (w {} .. {}) both solved", where,
                                                            answers[i].method, answers[i].w_min, answers[i].w_max,
                                                            answers[j].method, answers[j].w_min, answers[j].w_max)});
    }
}

bool fe_method(const std::string& m) { return m == "primal" || m == "dual" || m == "fast"; }

void check_agreement(const nlohmann::json& all, std::vector<Finding>& found) {
  std::vector<FeAnswer> answers;
  for (const auto& m : all["methods"])
    if (m.is_object() && m.value("termination", std::string()) == "solved" &&
        fe_method(m.value("method", std::string())) && m.contains("w_max") && m["w_max"].is_number() &&
        m.contains("w_min") && m["w_min"].is_number())
      answers.push_back({m["method"], m["w_max"], m["w_min"]});
  check_agreement(answers, "", found);
}

// The sweep CSV: every solved or converged row certified.
void check_csv(const std::string& csv, std::vector<Finding>& found) {
  auto split = [](const std::string& line) {
    std::vector<std::string> cells(1);
    bool quoted = false;
    for (char ch : line) {
      if (ch == '"')
        quoted = !quoted;
      else if (ch == ',' && !quoted)
        cells.emplace_back();
      else
        cells.back() += ch;
    }
    return cells;
  };
  const auto rows = lines(csv);
  if (rows.empty()) return found.push_back({"csv", "empty CSV"});
  const auto header = split(rows[0]);
  const auto column = [&](const std::string& name) {
    return std::find(header.begin(), header.end(), name) - header.begin();
  };
  const auto termination = column("termination"), certified = column("certified"), method = column("method"),
             w_max = column("w_max"), w_min = column("w_min");
  std::map<std::string, std::vector<FeAnswer>> cases;  // by the swept values (the cells before `method`)
  bool missing_column = false;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    const auto cells = split(rows[r]);
    if (termination >= static_cast<long>(cells.size())) continue;
    if (cells[termination] == "solved" && fe_method(cells[method]) && w_min < static_cast<long>(cells.size())) {
      std::string values;
      for (long i = 0; i < method; ++i) values += cells[i] + " ";
      cases[values].push_back(
          {cells[method], std::strtod(cells[w_max].c_str(), nullptr), std::strtod(cells[w_min].c_str(), nullptr)});
    }
    if (cells[termination] != "solved" && cells[termination] != "converged") continue;
    if (certified >= static_cast<long>(cells.size()))
      missing_column = true;
    else if (cells[certified] != "true")
      found.push_back({"certificate_failed", "sweep CSV row " + rows[r]});
  }
  if (missing_column) found.push_back({"certificate_missing", "the sweep CSV has no 'certified' column"});
  for (const auto& [values, answers] : cases) check_agreement(answers, "case " + values + ": ", found);
}

std::vector<Finding> check(const Case& c, const Ended& e, const fs::path& dir) {
  std::vector<Finding> found;
  if (e.timed_out) found.push_back({"timeout", fmt::format("killed after {:.0f} s", e.seconds)});
  if (e.signal != 0 && !e.timed_out) found.push_back({"signal", fmt::format("ended by signal {}", e.signal)});
  for (const char* report : {"AddressSanitizer", "LeakSanitizer", "UndefinedBehaviorSanitizer", "runtime error:"})
    if (e.err.find(report) != std::string::npos) found.push_back({"sanitizer", report});
  if (e.timed_out || e.signal != 0) return found;

  const int code = e.exit_code;
  if (code != 0 && code != 2 && code != 3 && code != 4) found.push_back({"exit_code", fmt::format("exit {}", code)});
  if (c.certainly_invalid && code != 2)
    found.push_back({"expected_exit_2", fmt::format("exit {} for an invalid scene", code)});
  if (!c.allowed.contains(code) && code != 1)
    found.push_back({"expected_exit", fmt::format("exit {}, expected one of {}", code, fmt::join(c.allowed, ", "))});

  // stderr: the reason, one line per failure, each "liftoff: ..."; exactly one for bad input
  // and for a single solve. (The command line's own parser words its errors itself.)
  const auto err_lines = lines(e.err);
  if (code != 0 && c.command != Command::other) {
    std::vector<std::string> reasons;
    for (const auto& l : err_lines)
      if (l.rfind("liftoff sweep [", 0) != 0) reasons.push_back(l);  // not the progress bar
    // Every method of "all" (asked for by --method, or by the scene's [solve] method with no
    // --method) reports its own failure.
    bool all = std::find(c.args.begin(), c.args.end(), "all") != c.args.end();
    if (!all && std::find(c.args.begin(), c.args.end(), "--method") == c.args.end() && c.files.contains(c.scene)) {
      try {
        all = toml::parse(c.files.at(c.scene))["solve"]["method"].value_or(std::string()) == "all";
      } catch (const toml::parse_error&) {
      }
    }
    const bool single = code == 2 || (c.command == Command::solve && !all);
    if (reasons.empty() || (single && reasons.size() != 1))
      found.push_back({"stderr_lines", fmt::format("{} lines on stderr for exit {}", reasons.size(), code)});
    for (const auto& l : reasons)
      if (l.rfind("liftoff: ", 0) != 0)
        found.push_back({"stderr_form", "stderr line not 'liftoff: ...': " + l.substr(0, 200)});
    if (c.certainly_invalid && code == 2 && e.err.find(c.scene) == std::string::npos)
      found.push_back({"stderr_names_file", "the message does not name " + c.scene});
  }
  if (code != 0 && c.command == Command::other && err_lines.empty())
    found.push_back({"stderr_lines", "nothing on stderr"});

  // stdout: exactly one JSON object with --json.
  if (c.json) {
    nlohmann::json j;
    bool parsed = false;
    try {
      j = nlohmann::json::parse(e.out);
      parsed = j.is_object();
    } catch (const nlohmann::json::exception&) {
    }
    if (!parsed) {
      found.push_back({code == 0 ? "json_one_object" : "json_failure_object",
                       fmt::format("exit {}: stdout is not one JSON object ({} bytes)", code, e.out.size())});
    } else if (code != 0) {
      if (!j.contains("termination") || !j["termination"].is_string() || !j.contains("message") ||
          !j["message"].is_string() || j.value("exit_code", -1) != code)
        found.push_back({"json_failure_object", fmt::format("exit {}: the object lacks termination, message or "
                                                            "exit_code = {}",
                                                            code, code)});
    } else {
      bool any = false;
      check_certificates(j, c, found, any);
    }
    if (parsed && j.contains("methods") && j["methods"].is_array()) check_agreement(j, found);  // any exit
  }
  if ((code == 0 || code == 3) && c.command == Command::sweep) {  // a failed case is in the CSV too
    const auto csv =
        std::find_if(c.outputs.begin(), c.outputs.end(), [](const std::string& o) { return o.ends_with(".csv"); });
    if (csv == c.outputs.end())
      check_csv(e.out, found);
    else if (fs::exists(dir / *csv))
      check_csv(liftoff::fuzz::read_all(dir / *csv), found);
  }

  // Files: the inputs unchanged; the outputs asked for on success, none on failure (a sweep or a
  // trace that stops short keeps what it finished); nothing else, ever.
  for (const auto& [name, text] : c.files)
    if (!fs::exists(dir / name) || liftoff::fuzz::read_all(dir / name) != text)
      found.push_back({"input_changed", name + " changed or vanished"});
  const bool kept = code == 3 && (c.command == Command::sweep || c.command == Command::trace);
  for (const auto& output : c.outputs) {
    const bool exists = fs::exists(dir / output) && !c.files.contains(output);
    if (code == 0 && !exists) found.push_back({"output_missing", output + " not written"});
    if (code == 0 && exists && !output.ends_with(".csv") && !is_hdf5(dir / output))
      found.push_back({"output_not_hdf5", output});
    if (code != 0 && !kept && exists)
      found.push_back({"output_left", fmt::format("{} left after exit {}", output, code)});
  }
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (!c.files.contains(name) && std::find(c.outputs.begin(), c.outputs.end(), name) == c.outputs.end())
      found.push_back({"stray_file", fmt::format("{} left after exit {}", name, code)});
  }
  return found;
}

// ---------------------------------------------------------------------------------------------
// Running a family of cases and reporting

struct Campaign {
  explicit Campaign(std::string name) : family(std::move(name)) {}
  std::string family;
  liftoff::test::Scratch scratch{"liftoff_fuzz_" + family};  // removed with all it holds when the family ends
  std::map<std::string, int> rules, exits;
  std::map<std::string, int> messages;  // first words of exit-2/3 messages of valid scenes, to read
  int failed_cases = 0, run = 0;
  double seconds = 0.0;
  std::string details;

  // The case's files and its command line (command.txt: the command, then the description).
  static std::string write_case(const fs::path& where, const Case& c) {
    fs::remove_all(where);
    fs::create_directories(where);
    for (const auto& [name, text] : c.files) std::ofstream(where / name, std::ios::binary) << text;
    std::string command = "liftoff";
    for (const auto& a : c.args) command += " '" + a + "'";
    std::ofstream(where / "command.txt") << command << "\n" << c.description << "\n";
    return command;
  }

  void execute(int index, const Case& c) {
    if (const auto out = write_only_dir()) {
      write_case(*out / fmt::format("{}-{}", family, index), c);
      return;
    }
    const fs::path dir = scratch.dir / "run", capture = scratch.dir / "capture";
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::create_directories(capture);
    for (const auto& [name, text] : c.files) std::ofstream(dir / name, std::ios::binary) << text;
    const Ended e = liftoff::fuzz::run_program(executable(), c.args, dir, capture, timeout());
    std::vector<Finding> found;
    try {
      found = check(c, e, dir);
    } catch (const std::exception& error) {  // the fuzzer's own fault: say which case
      found.push_back({"fuzzer_error", error.what()});
    }
    ++run;
    seconds += e.seconds;
    ++exits[e.timed_out ? "timeout" : e.signal ? "signal" : std::to_string(e.exit_code)];
    if (c.member_known && (e.exit_code == 2 || e.exit_code == 3)) {
      std::string m = e.err.substr(0, e.err.find('\n'));
      const auto key = m.find("': ");  // drop the file name and key, keep the reason's start
      m = (key != std::string::npos ? m.substr(key + 3) : m.substr(std::min<std::size_t>(m.size(), 9))).substr(0, 70);
      ++messages[std::to_string(e.exit_code) + " " + m];
    }
    if (found.empty()) return;
    ++failed_cases;
    const fs::path keep = fs::path(LIFTOFF_BINARY_DIR) / "fuzz-failures" / fmt::format("{}-{}", family, index);
    const std::string command = write_case(keep, c);
    std::ofstream(keep / "stdout.txt") << e.out;
    std::ofstream(keep / "stderr.txt") << e.err;
    for (const auto& f : found) {
      if (++rules[f.rule] <= 3)
        details += fmt::format("  [{}] case {} ({}): {}\n    cd {} && {}\n    stderr: {}\n", f.rule, index,
                               c.description, f.detail, keep.string(), command, e.err.substr(0, 300));
    }
  }

  void report() const {
    std::string summary = fmt::format("fuzz {}: {} runs in {:.1f} s, exit codes:", family, run, seconds);
    for (const auto& [code, n] : exits) summary += fmt::format(" {}x{}", code, n);
    if (!messages.empty()) {
      summary += "\n  exit 2/3 of valid scenes (for reading):";
      for (const auto& [m, n] : messages) summary += fmt::format("\n    {:3d} x exit {}", n, m);
    }
    if (failed_cases > 0) {
      summary += fmt::format("\n  {} cases broke a rule:", failed_cases);
      for (const auto& [rule, n] : rules) summary += fmt::format(" {}x{}", rule, n);
      summary += "\n" + details;
    }
    WARN(summary);
    CHECK(failed_cases == 0);
  }
};

template <class Make>
void campaign(const std::string& family, std::uint64_t salt, int count, Make make) {
  Campaign campaign(family);
  const auto only = only_case();
  for (int i = 0; i < count; ++i) {
    if (only && *only != i) continue;
    Random random(seed() * 0x100000001b3ULL + salt * 0x9e3779b97f4a7c15ULL + static_cast<std::uint64_t>(i));
    campaign.execute(i, make(random, i));
  }
  campaign.report();
}

// ---------------------------------------------------------------------------------------------
// Command lines

const std::vector<std::string> methods{"dual", "primal", "fast", "auto", "ritz", "all"};

// --method (or none: the scene's), --elements and --modes, keeping every run cheap: dense Lemke
// (primal, all, auto on a member only the foundation holds) gets few elements, and the Ritz model
// few modes unless the scene's [ritz] table already bounds them.
std::vector<std::string> method_options(Random& random, const Draft& d, int max_elements) {
  std::vector<std::string> args;
  if (random.chance(0.75)) args.insert(args.end(), {"--method", random.pick(methods)});
  if (!d.has("solve", "elements") || random.chance(0.3))  // the default 200 is too many for dense Lemke
    args.insert(args.end(), {"--elements", std::to_string(random.integer(1, max_elements))});
  if (!d.has("ritz") || random.chance(0.2)) args.insert(args.end(), {"--modes", std::to_string(random.integer(1, 12))});
  return args;
}

SceneLimits limits(int max_elements, bool trace = false) {
  SceneLimits l;
  l.max_elements = max_elements;
  l.trace = trace;
  l.ritz_trace = trace;
  return l;
}

Case scene_case(const Draft& d, std::string description) {
  Case c;
  c.description = std::move(description);
  c.files[c.scene] = d.text();
  c.member_known = true;
  c.begin = d.begin;
  c.end = d.end;
  return c;
}

Case solve_case(Random& random, int) {
  const Draft d = liftoff::fuzz::valid_scene(random, limits(60));
  Case c = scene_case(d, "valid scene, solve");
  c.args = {"solve", c.scene};
  const auto options = method_options(random, d, 60);
  c.args.insert(c.args.end(), options.begin(), options.end());
  c.json = random.chance(0.85);
  if (c.json) c.args.push_back("--json");
  if (random.chance(0.3)) {
    c.outputs = {"out.h5"};
    c.args.insert(c.args.end(), {"--output", "out.h5"});
  }
  return c;
}

// A sweep over one or two numeric keys of the scene, two or three values each.
Case sweep_case(Random& random, int) {
  const Draft d = liftoff::fuzz::valid_scene(random, limits(40));
  Case c = scene_case(d, "valid scene, sweep");
  c.command = Command::sweep;
  c.args = {"sweep", c.scene};
  // Stiffnesses keep their sign; loads may change theirs; elements stay integers.
  std::vector<std::string> keys{"structure.EI"};
  for (const char* key : {"nondimensional_k", "modulus"})  // (none with [[foundation.segments]])
    if (d.has("foundation", key)) keys.push_back(fmt::format("foundation.{}", key));
  int load = 0;
  for (const auto& t : d.tables)
    if (t.name == "loads") keys.push_back(fmt::format("loads[{}].value", load++));
  if (d.has("solve", "elements")) keys.push_back("solve.elements");
  const int sets = random.integer(1, 2);
  for (int s = 0; s < sets; ++s) {
    const std::string key = random.pick(keys);
    std::string values;
    if (key == "solve.elements")
      values = random.chance(0.5) ? "4,9,30" : "lin:2:40:3";
    else if (key.starts_with("loads"))
      values = fmt::format("{},{}", random.uniform(-2.0, 2.0), random.log_uniform(1e-3, 1e3));
    else if (random.chance(0.5))
      values = fmt::format("log:{}:{}:{}", random.log_uniform(1e-2, 1.0), random.log_uniform(1.0, 1e2),
                           random.integer(2, 3));
    else
      values = fmt::format("{},{}", random.log_uniform(1e-2, 1.0), random.log_uniform(1.0, 1e2));
    c.args.insert(c.args.end(), {"--set", key + "=" + values});
  }
  const auto options = method_options(random, d, 40);
  c.args.insert(c.args.end(), options.begin(), options.end());
  c.args.insert(c.args.end(), {"--jobs", std::to_string(random.integer(1, 2))});
  if (random.chance(0.6)) {
    c.outputs.push_back("out.csv");
    c.args.insert(c.args.end(), {"--csv", "out.csv"});
  }
  if (random.chance(0.4)) {
    c.outputs.push_back("out.h5");
    c.args.insert(c.args.end(), {"--output", "out.h5"});
  }
  return c;
}

Case trace_case(Random& random, int) {
  const Draft d = liftoff::fuzz::valid_scene(random, limits(60, true));
  Case c = scene_case(d, "valid scene, trace");
  c.command = Command::trace;
  c.args = {"trace", c.scene};
  auto options = method_options(random, d, 60);
  c.args.insert(c.args.end(), options.begin(), options.end());
  c.json = random.chance(0.85);
  if (c.json) c.args.push_back("--json");
  if (random.chance(0.4)) {
    c.outputs = {"out.h5"};
    c.args.insert(c.args.end(), {"--output", "out.h5"});
  }
  return c;
}

Case malformed_case(Random& random, int) {
  const bool trace = random.chance(0.15);
  const Draft d = liftoff::fuzz::valid_scene(random, limits(40, trace));
  const auto mutant = liftoff::fuzz::mutate(random, d);
  Case c;
  c.description = "malformed: " + mutant.kind;
  c.files[c.scene] = mutant.text;
  c.certainly_invalid = mutant.certainly_invalid;
  const int command = random.integer(0, 9);
  if (trace) {
    c.command = Command::trace;
    c.args = {"trace", c.scene, "--json"};
    c.json = true;
  } else if (command == 0) {
    c.command = Command::sweep;
    c.args = {"sweep", c.scene, "--set", "structure.EI=1,2", "--jobs", "1"};
  } else {
    c.args = {"solve", c.scene};
    c.json = command > 1;
    if (c.json) c.args.push_back("--json");
  }
  // A cheap method whatever the scene says: a huge number may have made the mesh or the modes big.
  c.args.insert(c.args.end(),
                {"--method", random.pick(std::vector<std::string>{"fast", "dual", "auto", "ritz"}), "--modes",
                 std::to_string(random.integer(1, 8)), "--elements", std::to_string(random.integer(1, 40))});
  if (random.chance(0.3)) {
    c.outputs = {"out.h5"};
    c.args.insert(c.args.end(), {"--output", "out.h5"});
  }
  return c;
}

const std::string small_beam = liftoff::test::beam_text("2.0", "3.0") + R"(k = 1.0e4
[[loads]]
kind = "force"
at = 1.0
value = 1.0
[solve]
elements = 20
[trace]
lambda_max = 1.0
)";

// The command line's own mistakes, and outputs that cannot be or must not be written.
std::vector<Case> command_line_cases() {
  std::vector<Case> list;
  // Each with the exit codes it may end with; --json anywhere means one JSON object on stdout.
  auto add = [&](Command command, std::vector<std::string> args, std::set<int> allowed,
                 std::vector<std::string> outputs = {}) {
    Case c;
    c.description = "command line";
    c.files[c.scene] = small_beam;
    c.command = command;
    c.json = std::find(args.begin(), args.end(), "--json") != args.end();
    c.args = std::move(args);
    c.allowed = std::move(allowed);
    c.outputs = std::move(outputs);
    list.push_back(c);
  };
  const auto solve = Command::solve, sweep = Command::sweep, trace = Command::trace, other = Command::other;
  for (const char* elements : {"0", "-1", "abc", "1e20", "10000001", "99999999999999999999"})
    add(solve, {"solve", "scene.toml", "--json", "--elements", elements}, {2});
  for (const char* modes : {"0", "x", "2000", "-3", "1.5"})
    add(solve, {"solve", "scene.toml", "--json", "--modes", modes}, {2});
  add(solve, {"solve", "scene.toml", "--json", "--method", "nope"}, {2});
  add(solve, {"solve", "no_such_file.toml", "--json"}, {2});
  add(solve, {"solve", ".", "--json"}, {2});  // a directory
  add(solve, {"solve", "scene.toml", "--json", "--bogus"}, {2});
  add(other, {"frobnicate"}, {2});
  add(other, {}, {2});
  // Outputs that cannot be written: exit 4 (or 2 for a path that is no file), nothing left.
  add(solve, {"solve", "scene.toml", "--json", "--output", "no_such_dir/out.h5"}, {2, 4});
  add(solve, {"solve", "scene.toml", "--json", "--output", "."}, {2, 4});
  add(trace, {"trace", "scene.toml", "--json", "--output", "no_such_dir/out.h5"}, {2, 4});
  add(sweep, {"sweep", "scene.toml", "--set", "foundation.k=1,2", "--csv", "no_such_dir/out.csv"}, {2, 4});
  // Outputs that must not replace an input or each other (issue 10, point 6).
  add(solve, {"solve", "scene.toml", "--method", "fast", "--output", "scene.toml"}, {2, 4});
  add(solve, {"solve", "scene.toml", "--method", "fast", "--json", "--output", "./scene.toml"}, {2, 4});
  add(trace, {"trace", "scene.toml", "--output", "scene.toml"}, {2, 4});
  add(sweep, {"sweep", "scene.toml", "--set", "foundation.k=1,2", "--output", "same.out", "--csv", "same.out"}, {2, 4},
      {"same.out"});
  // Sweep values and keys (issue 10, point 6: std::stoi on a huge index, a grid of 1e10 cases).
  for (const char* set : {"loads[99999999999].value=1,2", "loads[-1].value=1,2", "foundation.k=lin:1:2:1",
                          "foundation.k=log:-1:2:3", "foundation.k=nan,1", "foundation.k=", "=1,2", "no_such.key=1,2",
                          "foundation=1,2", "foundation.k=1e400", "solve.elements=0.5,2"})
    add(sweep, {"sweep", "scene.toml", "--set", set}, {2});
  add(sweep, {"sweep", "scene.toml", "--set", "foundation.k=lin:1:2:100000", "--set", "structure.EI=lin:1:2:100000"},
      {2});
  add(trace, {"trace", "scene.toml", "--resume", "--json"}, {2});  // nothing to resume
  return list;
}

// The corpus (tests/fuzz/corpus/): scenes the fuzzer once broke liftoff with, replayed every run.
// Header comments give the command (`# args: solve SCENE --json`) and, where the answer is known,
// the exit codes allowed (`# exit: 0`).
std::vector<Case> corpus_cases() {
  std::vector<fs::path> paths;
  for (const auto& entry : fs::directory_iterator(fs::path(LIFTOFF_SOURCE_DIR) / "tests/fuzz/corpus"))
    if (entry.path().extension() == ".toml") paths.push_back(entry.path());
  std::sort(paths.begin(), paths.end());
  std::vector<Case> list;
  for (const auto& path : paths) {
    Case c;
    c.description = "corpus " + path.filename().string();
    c.files[c.scene] = liftoff::fuzz::read_all(path);
    std::istringstream text(c.files[c.scene]);
    for (std::string line; std::getline(text, line) && line.starts_with("#");) {
      std::istringstream words(line.substr(line.find(':') + 1));
      if (line.starts_with("# args:")) {
        for (std::string w; words >> w;) c.args.push_back(w == "SCENE" ? c.scene : w);
      } else if (line.starts_with("# exit:")) {
        c.allowed.clear();
        for (int code; words >> code;) c.allowed.insert(code);
      }
    }
    for (std::size_t i = 0; i + 1 < c.args.size(); ++i)
      if (c.args[i] == "--output" || c.args[i] == "--csv") c.outputs.push_back(c.args[i + 1]);
    c.json = std::find(c.args.begin(), c.args.end(), "--json") != c.args.end();
    c.command = c.args.empty()         ? Command::other
                : c.args[0] == "sweep" ? Command::sweep
                : c.args[0] == "trace" ? Command::trace
                                       : Command::solve;
    list.push_back(c);
  }
  return list;
}

}  // namespace

TEST_CASE("fuzz: corpus of past findings", "[fuzz]") {
  const auto list = corpus_cases();
  REQUIRE(!list.empty());
  campaign("corpus", 6, static_cast<int>(list.size()), [&](Random&, int i) { return list[i]; });
}

TEST_CASE("fuzz: valid scenes, solve", "[fuzz]") { campaign("solve", 1, cases(150), solve_case); }

TEST_CASE("fuzz: malformed scenes", "[fuzz]") { campaign("malformed", 2, cases(150), malformed_case); }

TEST_CASE("fuzz: valid scenes, sweep", "[fuzz]") { campaign("sweep", 3, cases(30), sweep_case); }

TEST_CASE("fuzz: valid scenes, trace", "[fuzz]") { campaign("trace", 4, cases(40), trace_case); }

TEST_CASE("fuzz: command lines and outputs", "[fuzz]") {
  const auto list = command_line_cases();
  campaign("command_line", 5, static_cast<int>(list.size()), [&](Random&, int i) { return list[i]; });
}
