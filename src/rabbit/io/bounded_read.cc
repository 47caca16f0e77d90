#include "rabbit/io/bounded_read.h"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>

#include "rabbit/io/error.h"

namespace rabbit {
namespace {

std::string LimitNote(const FileLimits& limits) {
  return std::string(" (the limit for ") + limits.what + "; see docs/bad-input.md)";
}

}  // namespace

std::string FormatBytes(size_t bytes) {
  if (bytes >= kMiB && bytes % kMiB == 0) return std::to_string(bytes / kMiB) + " MiB";
  if (bytes >= kKiB && bytes % kKiB == 0) return std::to_string(bytes / kKiB) + " KiB";
  return std::to_string(bytes) + " bytes";
}

std::string TruncateForMessage(const std::string& text, size_t max_bytes) {
  if (text.size() <= max_bytes) return text;
  return text.substr(0, max_bytes) + "... [" + std::to_string(text.size() - max_bytes) +
         " more bytes left out]";
}

void CheckLineLimits(std::string_view text, const std::string& file, const FileLimits& limits) {
  size_t line = 0, start = 0;
  while (start < text.size()) {
    ++line;
    if (line > limits.max_lines) {
      throw InputError(
          file, static_cast<int>(std::min<size_t>(line, 2147483647)), "",
          "more than " + std::to_string(limits.max_lines) + " lines" + LimitNote(limits));
    }
    size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    if (end - start > limits.max_line_bytes) {
      throw InputError(
          file, static_cast<int>(line), "",
          "line longer than " + FormatBytes(limits.max_line_bytes) + LimitNote(limits));
    }
    start = end + 1;
  }
}

std::string ReadBoundedFile(const std::string& path, const FileLimits& limits) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    if (errno == ENOENT || errno == ENOTDIR)
      throw InputError(path, 0, "", "cannot open the file: no such file");
    throw InputError(path, 0, "", std::string("cannot open the file: ") + std::strerror(errno));
  }
  if (S_ISDIR(info.st_mode)) {
    throw InputError(path, 0, "", "is a directory, not a file");
  }
  const std::string too_large =
      std::string("larger than ") + FormatBytes(limits.max_bytes) + LimitNote(limits);
  if (S_ISREG(info.st_mode) && static_cast<unsigned long long>(info.st_size) > limits.max_bytes) {
    throw InputError(path, 0, "", too_large);
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open the file");
  std::string text;
  char buffer[65536];
  while (in) {
    in.read(buffer, sizeof buffer);
    const size_t got = static_cast<size_t>(in.gcount());
    if (text.size() + got > limits.max_bytes) throw InputError(path, 0, "", too_large);
    text.append(buffer, got);
  }
  if (in.bad()) throw InputError(path, 0, "", "cannot read the file");
  CheckLineLimits(text, path, limits);
  return text;
}

std::string ReadBoundedFileIfExists(const std::string& path, const FileLimits& limits) {
  struct stat status;
  if (::lstat(path.c_str(), &status) != 0 && errno == ENOENT) return "";
  return ReadBoundedFile(path, limits);
}

}  // namespace rabbit
