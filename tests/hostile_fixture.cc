#include "hostile_fixture.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <utility>

#include "cli_fixture.h"

namespace rabbit::testing {

namespace fs = std::filesystem;

namespace {
// A function, not a static string: the table is built at static initialisation.
std::string Root() { return RABBIT_SOURCE_DIR; }
}  // namespace

void Replace(const fs::path& path, const std::string& from, const std::string& to) {
  std::string text = ReadText(path);
  const size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from << " in " << path;
  text.replace(at, from.size(), to);
  WriteText(path, text);
}

void Sparse(const fs::path& path, std::uintmax_t bytes) {
  WriteText(path, "");
  fs::resize_file(path, bytes);
}

std::map<std::string, std::string> Snapshot(const fs::path& path) {
  std::map<std::string, std::string> out;
  if (fs::is_regular_file(path)) {
    out[path.string()] = ReadText(path);
  } else if (fs::is_directory(path)) {
    for (const auto& entry : fs::recursive_directory_iterator(path)) {
      if (entry.is_regular_file()) out[entry.path().string()] = ReadText(entry.path());
    }
  }
  return out;
}

std::string ScenarioText(const std::string& name, const std::string& body) {
  return "name = \"" + name + "\"\n" + body;
}

std::string WalkerScenario(const std::string& gaits, const std::string& extra) {
  return ScenarioText("w",
                      "[simulation]\nduration = 1.0\n[velocity]\nvalue = 0.6\n"
                      "[controller]\ntype = \"fuzzy_cmac\"\nfll = \"" +
                          Root() + "/gaits/gait_pattern.fll\"\nnetworks = \"" + Root() +
                          "/gaits/networks\"\ngaits = \"" + gaits + "\"\n" + extra);
}

std::string Expand(std::string s, const fs::path& dir) {
  for (const auto& [key, value] :
       {std::pair<std::string, std::string>("{D}", dir.string()), {"{R}", Root()}}) {
    for (size_t at = s.find(key); at != std::string::npos; at = s.find(key, at)) {
      s.replace(at, key.size(), value);
      at += value.size();
    }
  }
  return s;
}

FifoWriter::FifoWriter(const fs::path& path, std::uintmax_t bytes) : path_(path) {
  EXPECT_EQ(::mkfifo(path.c_str(), 0600), 0);
  thread_ = std::thread([this, bytes] {
    const int fd = ::open(path_.c_str(), O_WRONLY);
    if (fd >= 0) {
      const std::string chunk(65536, '\0');
      std::uintmax_t left = bytes;
      while (left > 0) {
        const ssize_t w = ::write(fd, chunk.data(), std::min<std::uintmax_t>(left, chunk.size()));
        if (w <= 0) break;  // the reader stopped reading (EPIPE: SIGPIPE is ignored)
        left -= static_cast<std::uintmax_t>(w);
      }
      ::close(fd);
    }
    done_ = true;
  });
}

FifoWriter::~FifoWriter() {
  while (!done_) {
    const int fd = ::open(path_.c_str(), O_RDONLY | O_NONBLOCK);
    if (fd >= 0) ::close(fd);
    std::this_thread::yield();
  }
  thread_.join();
}

}  // namespace rabbit::testing
