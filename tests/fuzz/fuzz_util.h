// Shared by the fuzz targets: the readers under test take file paths, so each process writes every
// input to one file of its own temporary directory (removed at exit) and reads it back.
#ifndef RABBIT_TESTS_FUZZ_FUZZ_UTIL_H_
#define RABBIT_TESTS_FUZZ_FUZZ_UTIL_H_

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace rabbit_fuzz {

// A directory laid out like the source tree where it matters, so that the shipped files' relative
// paths resolve to the shipped files through symlinks and fuzzed inputs reach the readers past
// them: <dir>/scenarios/ (a real directory, with a link to every shipped scenario, e.g.
// "model.toml") beside a link <dir>/gaits ("../gaits/reference/vm_0.60.csv"), and
// <dir>/optimizers/jobs/ for tuning jobs ("../../scenarios/tune_ramp.toml").
class FuzzDir {
 public:
  FuzzDir() {
    namespace fs = std::filesystem;
    std::string pattern = (fs::temp_directory_path() / "rabbit-fuzz-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    root_ = pattern;
    const fs::path source = RABBIT_SOURCE_DIR;
    fs::create_directory(root_ / "scenarios");
    for (const fs::directory_entry& entry : fs::directory_iterator(source / "scenarios")) {
      fs::create_symlink(entry.path(), root_ / "scenarios" / entry.path().filename());
    }
    fs::create_directory_symlink(source / "gaits", root_ / "gaits");
    fs::create_directories(root_ / "optimizers" / "jobs");
  }
  ~FuzzDir() {
    std::error_code ignored;
    std::filesystem::remove_all(root_, ignored);
  }
  FuzzDir(const FuzzDir&) = delete;
  FuzzDir& operator=(const FuzzDir&) = delete;

  // <dir>/<name>, e.g. for a folder of the target's own.
  std::filesystem::path Path(const std::string& name) const { return root_ / name; }

  // Writes the input to <dir>/<name> (e.g. "scenarios/input.toml") and returns its path.
  std::string Write(const std::string& name, const std::uint8_t* data, std::size_t size) const {
    const std::string path = (root_ / name).string();
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    out.close();
    if (!out) throw std::runtime_error("cannot write " + path);
    return path;
  }

 private:
  std::filesystem::path root_;
};

// One per process; a function-local static so that it is made on the first input (after
// libFuzzer's start-up) and removed by the normal exit. A crash leaves it behind in /tmp.
inline const FuzzDir& Dir() {
  static const FuzzDir dir;
  return dir;
}

// Called with every InputError: with RABBIT_FUZZ_VERBOSE set, prints it, to see why the inputs of
// a corpus are refused (e.g. that the shipped seeds load: RABBIT_FUZZ_VERBOSE=1 <target> <files>).
inline void Refused(const std::exception& error) {
  static const bool verbose = std::getenv("RABBIT_FUZZ_VERBOSE") != nullptr;
  if (verbose) std::fprintf(stderr, "InputError: %s\n", error.what());
}

}  // namespace rabbit_fuzz

#endif  // RABBIT_TESTS_FUZZ_FUZZ_UTIL_H_
