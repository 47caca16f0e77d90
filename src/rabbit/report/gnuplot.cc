#include "rabbit/report/gnuplot.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "rabbit/io/bounded_read.h"

extern char** environ;

namespace rabbit {
namespace {

namespace fs = std::filesystem;

// Removes the temporary directory however RunGnuplot returns.
struct TempDir {
  fs::path path;
  ~TempDir() {
    std::error_code ec;
    if (!path.empty()) fs::remove_all(path, ec);
  }
};

bool ReadWhole(const fs::path& path, std::string* text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream out;
  out << in.rdbuf();
  *text = out.str();
  return !in.bad();
}

bool WriteWhole(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  out.close();
  return static_cast<bool>(out);
}

bool IsPlainName(const std::string& name) {
  return !name.empty() && name != "." && name != ".." && name.find('/') == std::string::npos &&
         name.find('\0') == std::string::npos;
}

// The first few lines of gnuplot's messages, for a warning, cut at kMaxQuotedOutputBytes in all
// (with a note of what was left out).
std::string Head(const std::string& text, int max_lines) {
  std::istringstream in(text);
  std::string line, out;
  for (int k = 0; k < max_lines && std::getline(in, line);) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    out += (out.empty() ? "" : " | ") + TruncateForMessage(line, kMaxQuotedOutputBytes);
    ++k;
  }
  return TruncateForMessage(out, kMaxQuotedOutputBytes);
}

bool IsRunnableFile(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(path.c_str(), X_OK) == 0;
}

}  // namespace

bool IsRunnableExecutable(const std::string& executable) {
  if (executable.empty()) return false;
  if (executable.find('/') != std::string::npos) return IsRunnableFile(executable);
  const char* path = std::getenv("PATH");
  const std::string dirs = path != nullptr ? path : "/bin:/usr/bin";
  size_t start = 0;
  while (true) {
    const size_t colon = dirs.find(':', start);
    const std::string dir = dirs.substr(start, colon == std::string::npos ? colon : colon - start);
    if (IsRunnableFile((dir.empty() ? std::string(".") : dir) + "/" + executable)) return true;
    if (colon == std::string::npos) return false;
    start = colon + 1;
  }
}

std::string GnuplotQuote(const std::string& text) {
  std::string out = "'";
  for (char c : text) {
    if (c == '\'') {
      out += "''";
    } else if (c == '\n' || c == '\r') {
      out += ' ';
    } else {
      out += c;
    }
  }
  return out + "'";
}

GnuplotResult RunGnuplot(const std::string& executable, const GnuplotJob& job, double timeout) {
  GnuplotResult result;
  std::error_code ec;
  const fs::path base = fs::temp_directory_path(ec);
  if (ec) {
    result.error = "no temporary directory: " + ec.message();
    return result;
  }
  std::string pattern = (base / "rabbit-report-XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr) {
    result.error =
        "cannot create a temporary directory in " + base.string() + ": " + std::strerror(errno);
    return result;
  }
  TempDir work{fs::path(pattern)};
  if (pattern.find('\n') != std::string::npos || pattern.find('\r') != std::string::npos) {
    result.error = "the temporary directory's name has a line break: " + pattern;
    return result;
  }
  for (const auto& [name, contents] : job.files) {
    if (!IsPlainName(name) || !WriteWhole(work.path / name, contents)) {
      result.error = "cannot write gnuplot's data file " + name;
      return result;
    }
  }
  const std::string script_path = (work.path / "figures.gp").string();
  if (!WriteWhole(script_path, "cd " + GnuplotQuote(pattern) + "\n" + job.script)) {
    result.error = "cannot write " + script_path;
    return result;
  }

  const std::string log_path = (work.path / "gnuplot.log").string();
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0600);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::string arg0 = executable, arg1 = script_path;
  char* argv[] = {arg0.data(), arg1.data(), nullptr};
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, executable.c_str(), &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) {
    result.error = "cannot run '" + executable + "': " + std::strerror(spawned);
    return result;
  }

  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout);
  int status = 0;
  while (true) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) {
      result.error = std::string("waiting for gnuplot: ") + std::strerror(errno);
      return result;
    }
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      result.error = "'" + executable + "' did not finish within " + std::to_string(timeout) +
                     " s and was stopped";
      return result;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  std::string log;
  ReadWhole(log_path, &log);
  if (WIFSIGNALED(status)) {
    result.error = "'" + executable + "' was killed by signal " + std::to_string(WTERMSIG(status));
    return result;
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    result.error = "'" + executable + "' exited with status " +
                   std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                   (log.empty() ? "" : ": " + Head(log, 3));
    return result;
  }
  for (const std::string& name : job.outputs) {
    std::string text;
    if (!IsPlainName(name) || !ReadWhole(work.path / name, &text) || text.empty()) {
      result.error =
          "'" + executable + "' did not write " + name + (log.empty() ? "" : ": " + Head(log, 3));
      result.outputs.clear();
      return result;
    }
    result.outputs.push_back(std::move(text));
  }
  result.ok = true;
  return result;
}

}  // namespace rabbit
