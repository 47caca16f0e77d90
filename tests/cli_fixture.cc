#include "cli_fixture.h"

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace rabbit::testing {

namespace fs = std::filesystem;

std::string CliPath() {
  const char* other = std::getenv("RABBIT_CLI");
  return other != nullptr ? other : RABBIT_CLI_PATH;
}

CliRun RunCli(const std::string& args, const std::string& env, const std::string& streams) {
  const std::string command = (env.empty() ? "" : env + " ") + CliPath() + " " + args + streams;
  CliRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) run.output.append(buffer, n);
  const int status = pclose(pipe);
  run.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.killed = (WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) || run.code == 128 + SIGKILL;
  return run;
}

int RunCliCode(const std::string& args, std::string* output) {
  const std::string command = CliPath() + " " + args + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return -1;
  std::string text;
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) text.append(buffer, n);
  const int status = pclose(pipe);
  if (output != nullptr) *output = text;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : -1;
}

std::string WithoutLastColumn(const std::string& text) {
  std::istringstream in(text);
  std::string line, out;
  while (std::getline(in, line)) out += line.substr(0, line.rfind(',')) + "\n";
  return out;
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    // A missing file is a failure, not "": two missing files must not compare equal.
    ADD_FAILURE() << "cannot read " << path;
    return std::string();
  }
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void WriteText(const fs::path& path, const std::string& text) {
  if (path.has_parent_path()) fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

std::string WithoutWallTime(const std::string& csv) {
  std::stringstream in(csv), out;
  for (std::string line; std::getline(in, line);) {
    for (int k = 0; k < 2; ++k) line = line.substr(0, line.rfind(','));
    out << line << "\n";
  }
  return out.str();
}

std::string SmallWalkerSuite(const std::string& extra) {
  const std::string root = RABBIT_SOURCE_DIR;
  return "[suite]\nname = \"small\"\n[defaults]\nexpect_outcome = \"completed\"\n"
         "[defaults.simulation]\nduration = 6.0\nrecord_every = 20\n"
         "[defaults.velocity]\nvalue = 0.6\n"
         "[defaults.controller]\ntype = \"fuzzy_cmac\"\nfll = \"" +
         root + "/gaits/gait_pattern.fll\"\nnetworks = \"" + root +
         "/gaits/networks\"\ngaits = \"" + root +
         "/gaits/reference\"\n"
         "[[scenario]]\nname = \"walk\"\n[scenario.controller]\nbaselines = [\"nearest_gait\"]\n"
         "[[scenario]]\nname = \"second\"\n" +
         extra;
}

fs::path MakeScratchDir(const std::string& prefix) {
  std::string name = prefix + "_" + std::to_string(::getpid());
  if (const auto* info = ::testing::UnitTest::GetInstance()->current_test_info()) {
    name += "_";
    for (const char ch : std::string(info->name())) {
      name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
    }
  }
  const fs::path dir = fs::temp_directory_path() / name.substr(0, 200);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

HeldWriter::HeldWriter(const std::string& args, const std::string& phase, const fs::path& fifo,
                       const fs::path& log)
    : fifo_(fifo) {
  EXPECT_EQ(::mkfifo(fifo.c_str(), 0600), 0) << fifo;
  const std::string command = "RABBIT_TEST_PAUSE_AT=" + phase +
                              " RABBIT_TEST_PAUSE_FIFO=" + fifo.string() + " " + CliPath() + " " +
                              args + " > " + log.string() + " 2>&1";
  pipe_ = popen(command.c_str(), "r");
}

std::string HeldWriter::WaitAtPhase() {
  std::ifstream in(fifo_);
  std::string phase, pid;
  in >> phase >> pid;
  return pid;
}

int HeldWriter::Finish() {
  { std::ofstream release(fifo_); }
  const int status = pclose(pipe_);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace rabbit::testing
