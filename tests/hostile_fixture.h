// The hostile-input table's row type and helpers (hostile_input_test): a row's command with its
// placeholders, snapshots of the files a row must leave as they were, sparse files and a FIFO fed
// by a writer thread with a bounded amount of data.
#ifndef RABBIT_TESTS_HOSTILE_FIXTURE_H_
#define RABBIT_TESTS_HOSTILE_FIXTURE_H_

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <thread>
#include <vector>

namespace rabbit::testing {

// Replaces the first `from` in the file at `path` by `to` (a test failure when it is absent).
void Replace(const std::filesystem::path& path, const std::string& from, const std::string& to);

// A sparse file of `bytes` (no disk used).
void Sparse(const std::filesystem::path& path, std::uintmax_t bytes);

// Every regular file under `path` (or `path` itself) with its bytes.
std::map<std::string, std::string> Snapshot(const std::filesystem::path& path);

constexpr std::uintmax_t kMiB = 1024 * 1024;

// A scenario file's text: the name, then `body`.
std::string ScenarioText(const std::string& name, const std::string& body);

// A walker scenario on the given gait database (other files shipped).
std::string WalkerScenario(const std::string& gaits, const std::string& extra);

// A short drop of the robot under a PD hold: a scenario's tables, and the same as one
// [[scenario]] of a suite. Inline, so that they are made before a table built at static
// initialisation uses them.
inline const std::string kDrop =
    "[simulation]\nduration = 0.05\n[initial]\nfoot_clearance = 0.02\n[controller]\n"
    "type = \"pd_hold\"\nkp = 600.0\nkd = 30.0\n";
inline const std::string kDropInSuite =
    "[scenario.simulation]\nduration = 0.05\n[scenario.initial]\nfoot_clearance = 0.02\n"
    "[scenario.controller]\ntype = \"pd_hold\"\nkp = 600.0\nkd = 30.0\n";

// One row of the table. Paths in `args`, `untouched` and `absent` may use {D} (the scratch
// folder) and {R} (the source tree).
struct Case {
  std::string name;
  std::function<void(const std::filesystem::path& dir)> setup;
  std::string args;
  int code;
  std::vector<std::string> fragments;
  std::vector<std::string> untouched;
  std::vector<std::string> absent;
  std::string fifo;  // a FIFO to create and feed (relative to {D}), or empty
  std::uintmax_t fifo_bytes = 0;
};

// `s` with {D} replaced by `dir` and {R} by the source tree.
std::string Expand(std::string s, const std::filesystem::path& dir);

// Feeds `bytes` NUL bytes into the FIFO at `path` from a thread, as /dev/zero would but bounded.
class FifoWriter {
 public:
  FifoWriter(const std::filesystem::path& path, std::uintmax_t bytes);
  // Releases a writer still waiting for a reader (opening the FIFO without blocking), then joins.
  ~FifoWriter();

 private:
  std::filesystem::path path_;
  std::atomic<bool> done_{false};
  std::thread thread_;
};

}  // namespace rabbit::testing

#endif  // RABBIT_TESTS_HOSTILE_FIXTURE_H_
