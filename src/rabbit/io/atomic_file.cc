#include "rabbit/io/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

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
  const fs::path temp = CreateTemporary(target);
  try {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path + ": cannot open for writing");
    write(out);
    out.flush();
    if (!out) throw std::runtime_error(path + ": write failed");
    out.close();
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
