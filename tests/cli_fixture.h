// Running the built `rabbit` binary from a test, in a scratch folder of its own: the command's
// exit code and output, whether a SIGKILL ended it, and small file helpers.
#ifndef RABBIT_TESTS_CLI_FIXTURE_H_
#define RABBIT_TESTS_CLI_FIXTURE_H_

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

namespace rabbit::testing {

struct CliRun {
  int code = -1;
  bool killed = false;  // by SIGKILL (directly, or as the shell reports it: 128 + 9)
  std::string output;   // what `streams` captured (stdout and stderr by default)
};

// The binary under test: the build's, or RABBIT_CLI when set (e.g. a sanitizer build's).
std::string CliPath();

// Runs `rabbit args`; `env` is prefixed to the command (e.g. "RABBIT_RUN_KILL_AFTER=5") and
// `streams` says where its output goes.
CliRun RunCli(const std::string& args, const std::string& env = "",
              const std::string& streams = " 2>&1");

// The exit code of `rabbit args` (128 + the signal's number when one ended it), with its output
// (stdout and stderr) into *output when given.
int RunCliCode(const std::string& args, std::string* output = nullptr);

// A CSV text without its last column (e.g. wall_s: not deterministic).
std::string WithoutLastColumn(const std::string& text);

// A file's bytes; when it cannot be read, a test failure and "".
std::string ReadText(const std::filesystem::path& path);

// Writes `text` to `path`, creating its folder.
void WriteText(const std::filesystem::path& path, const std::string& text);

// summary.csv without its last two columns (wall_s, real_time_factor).
std::string WithoutWallTime(const std::string& csv);

// A small walker suite on the shipped gaits: two short scenarios (6 s), one with a baseline;
// `extra` lands in the second scenario's own table.
std::string SmallWalkerSuite(const std::string& extra);

// A fresh empty folder under the system's temporary folder, named after `prefix`, the process and
// the running test (its name made safe for a path).
std::filesystem::path MakeScratchDir(const std::string& prefix);

// A test in a scratch folder of its own (dir_), made before each test and removed after.
class ScratchDirTest : public ::testing::Test {
 protected:
  explicit ScratchDirTest(std::string prefix) : prefix_(std::move(prefix)) {}
  void SetUp() override { dir_ = MakeScratchDir(prefix_); }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  // Writes `text` to dir_/name (its folder created) and returns the path.
  std::string Write(const std::string& name, const std::string& text) {
    WriteText(dir_ / name, text);
    return (dir_ / name).string();
  }
  std::string prefix_;
  std::filesystem::path dir_;
};

// A rabbit command started in the background and held at a test phase (RABBIT_TEST_PAUSE_AT, with
// the FIFO `fifo`, which it makes), so that the order of two writers is forced without any sleep;
// its output goes to `log`.
class HeldWriter {
 public:
  HeldWriter(const std::string& args, const std::string& phase, const std::filesystem::path& fifo,
             const std::filesystem::path& log);
  // Blocks until the command has reached its phase; returns its pid.
  std::string WaitAtPhase();
  // Lets it go on, and returns its exit code (-1 if it did not exit).
  int Finish();

 private:
  std::filesystem::path fifo_;
  FILE* pipe_ = nullptr;
};

// The CLI tests' fixture (cli_test, cli_run_test, cli_report_test): a scratch folder, and the
// shipped scenarios by name.
class CliTest : public ScratchDirTest {
 protected:
  CliTest() : ScratchDirTest("rabbit_cli_test") {}
  static std::string Scenario(const std::string& name) {
    return std::string(RABBIT_SOURCE_DIR) + "/scenarios/" + name;
  }
};

}  // namespace rabbit::testing

#endif  // RABBIT_TESTS_CLI_FIXTURE_H_
