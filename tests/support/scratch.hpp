#pragma once
// A scratch directory for a test's files, made empty on construction and removed with all it
// holds at the end of the test. The name carries the process id and a count, so that tests run
// at the same time (ctest -j) or two scratches in one test never share a directory.

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace liftoff::test {

struct Scratch {
  std::filesystem::path dir;

  explicit Scratch(const std::string& prefix = "liftoff_test") {
    static int count = 0;
    dir = std::filesystem::temp_directory_path() /
          (prefix + "_" + std::to_string(::getpid()) + "_" + std::to_string(count++));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
  }
  ~Scratch() {
    std::error_code ignored;  // a destructor must not throw
    std::filesystem::remove_all(dir, ignored);
  }
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;

  // Writes `text` to the file `name` in the directory; returns its path.
  std::filesystem::path write(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name) << text;
    return dir / name;
  }
};

}  // namespace liftoff::test
