#include "rabbit/io/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <stdexcept>
#include <system_error>

#include "rabbit/io/output_ownership.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

// Whether text is a non-empty run of decimal digits (at most 18: a pid or the random suffix).
bool IsNumber(const std::string& text) {
  if (text.empty() || text.size() > 18) return false;
  for (char c : text) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  }
  return true;
}

// Removes what a killed writer of this target left: regular files named as CreateTemporary names
// them (TARGET.tmp.PID.N) whose process no longer runs on this machine. A temporary of a live
// process (another rabbit writing the same path, or this one) is kept, and so is any other file.
void RemoveStaleTemporaries(const fs::path& target) {
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const std::string prefix = target.filename().string() + ".tmp.";
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string rest = name.substr(prefix.size());
    const size_t dot = rest.find('.');
    if (dot == std::string::npos || !IsNumber(rest.substr(0, dot)) ||
        !IsNumber(rest.substr(dot + 1))) {
      continue;
    }
    const long long pid = std::stoll(rest.substr(0, dot));
    if (pid <= 0 || pid > 0x7fffffff) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH)
      continue;  // alive, or not ours to know
    std::error_code kind;
    if (!fs::is_regular_file(fs::symlink_status(it->path(), kind)) || kind) continue;
    std::error_code removed;
    fs::remove(it->path(), removed);
  }
}

// A temporary beside the target, created exclusively (never an existing file of anyone's).
fs::path CreateTemporary(const fs::path& target) {
  std::random_device random;
  for (int attempt = 0; attempt < 100; ++attempt) {
    const fs::path temp = target.string() + ".tmp." + std::to_string(::getpid()) + "." +
                          std::to_string(random() % 1000000);
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd >= 0) {
      ::close(fd);
      return temp;
    }
    if (errno != EEXIST) break;
  }
  throw std::runtime_error(target.string() + ": cannot create a temporary file beside it");
}

}  // namespace

void WriteFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const fs::path target(path);
  CheckReplaceableFile(path, target);
  std::error_code ec;
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  if (ec) throw std::runtime_error(path + ": cannot create directory: " + ec.message());
  RemoveStaleTemporaries(target);
  const fs::path temp = CreateTemporary(target);
  try {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path + ": cannot open for writing");
    // The stream keeps no reason; the system call that failed left it in errno (no space left on
    // the device, a quota).
    auto failed = [&path] {
      return std::runtime_error(path + ": write failed" +
                                (errno != 0 ? std::string(": ") + std::strerror(errno) : ""));
    };
    errno = 0;
    write(out);
    out.flush();
    if (!out) throw failed();
    out.close();  // writes what is left in the buffer
    if (out.fail()) throw failed();
    // Checked again just before: what appeared at the path meanwhile is not replaced either.
    CheckReplaceableFile(path, target);
    fs::rename(temp, target, ec);
    if (ec) throw std::runtime_error(path + ": cannot rename into place: " + ec.message());
  } catch (...) {
    fs::remove(temp, ec);
    throw;
  }
}

void WriteOutputFile(const std::string& path, const std::function<void(std::ostream&)>& write) {
  if (!IsStandardOutput(path)) return WriteFileAtomically(path, write);
  write(std::cout);
  std::cout.flush();
  if (!std::cout) throw std::runtime_error("standard output: write failed");
}

}  // namespace rabbit
