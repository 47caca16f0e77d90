// ReadBoundedFile and its helpers: a file within its limits reads back byte for byte; one byte
// over any limit (size, lines, one line) is an InputError naming the file, the line where there is
// one, and the limit; a FIFO fed more than the limit stops there; messages are cut with a note.
#include "rabbit/io/bounded_read.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "rabbit/io/error.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

// Small limits, so that the edges are cheap to reach.
constexpr FileLimits kSmall = {"test files", 100, 4, 10};

class BoundedReadTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rabbit_bounded_read_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name, std::ios::binary) << text;
    return (dir_ / name).string();
  }
  // The InputError of reading `path`, or a failure.
  InputError Refusal(const std::string& path, const FileLimits& limits = kSmall) {
    try {
      ReadBoundedFile(path, limits);
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      return e;
    }
    ADD_FAILURE() << "read " << path;
    return InputError("", 0, "", "");
  }
  fs::path dir_;
};

TEST_F(BoundedReadTest, WithinTheLimitsReadsBackExactly) {
  // 4 lines of at most 10 bytes, 100 bytes at most; CR, NUL and no final newline kept as they are.
  const std::string text = std::string("0123456789\nab\r\n") + '\0' + "x\nlast";
  EXPECT_EQ(ReadBoundedFile(Write("ok.txt", text), kSmall), text);
  EXPECT_EQ(ReadBoundedFile(Write("empty.txt", ""), kSmall), "");
  const std::string full(100, '\n');  // 100 bytes, but 100 lines: over the line count
  const InputError lines = Refusal(Write("lines.txt", full));
  EXPECT_EQ(lines.line(), 5);
  EXPECT_NE(std::string(lines.what()).find("more than 4 lines"), std::string::npos) << lines.what();
}

TEST_F(BoundedReadTest, OneByteOverEachLimitIsRefusedNamingIt) {
  const InputError size = Refusal(Write("size.txt", std::string(101, 'x')));
  EXPECT_EQ(size.line(), 0);
  EXPECT_NE(std::string(size.what()).find("larger than 100 bytes (the limit for test files"),
            std::string::npos)
      << size.what();
  const InputError line = Refusal(Write("line.txt", "short\n01234567890\n"));
  EXPECT_EQ(line.line(), 2);
  EXPECT_NE(std::string(line.what()).find("line longer than 10 bytes"), std::string::npos)
      << line.what();
  EXPECT_NO_THROW(ReadBoundedFile(Write("edge.txt", "0123456789\n0123456789"), kSmall));
}

TEST_F(BoundedReadTest, ALargeSparseFileIsRefusedFromItsSize) {
  const std::string path = Write("sparse.csv", "");
  fs::resize_file(path, std::uintmax_t{2} * 1024 * 1024 * 1024);  // 2 GiB, no disk used
  const InputError e = Refusal(path, kCsvTableLimits);
  EXPECT_NE(std::string(e.what()).find("larger than 768 MiB"), std::string::npos) << e.what();
}

TEST_F(BoundedReadTest, MissingFileAndDirectory) {
  const InputError missing = Refusal((dir_ / "nowhere.toml").string());
  EXPECT_NE(std::string(missing.what()).find("no such file"), std::string::npos);
  const InputError folder = Refusal(dir_.string());
  EXPECT_NE(std::string(folder.what()).find("is a directory"), std::string::npos);
}

// A FIFO fed 1 MiB by a thread (as /dev/zero would, but bounded): the reader stops after its
// 100 bytes and the writer sees the pipe closed.
TEST_F(BoundedReadTest, AFifoFedBeyondTheLimitStopsAtIt) {
  std::signal(SIGPIPE, SIG_IGN);
  const fs::path fifo = dir_ / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::atomic<bool> done{false};
  std::thread writer([&] {
    const int fd = ::open(fifo.c_str(), O_WRONLY);
    if (fd >= 0) {
      const std::string chunk(4096, '\0');
      for (int k = 0; k < 256; ++k) {
        if (::write(fd, chunk.data(), chunk.size()) <= 0) break;
      }
      ::close(fd);
    }
    done = true;
  });
  const InputError e = Refusal(fifo.string());
  EXPECT_NE(std::string(e.what()).find("larger than 100 bytes"), std::string::npos) << e.what();
  while (!done) {  // a writer still waiting to open: release it
    const int fd = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
    if (fd >= 0) ::close(fd);
    std::this_thread::yield();
  }
  writer.join();
}

TEST(BoundedReadFormatTest, BytesLimitsAndTruncation) {
  EXPECT_EQ(FormatBytes(4 * kMiB), "4 MiB");
  EXPECT_EQ(FormatBytes(64 * kKiB), "64 KiB");
  EXPECT_EQ(FormatBytes(100), "100 bytes");
  EXPECT_EQ(FormatBytes(kMiB + 1), std::to_string(kMiB + 1) + " bytes");
  EXPECT_EQ(TruncateForMessage("short", 10), "short");
  EXPECT_EQ(TruncateForMessage(std::string(25, 'x'), 10),
            std::string(10, 'x') + "... [15 more bytes left out]");
  EXPECT_NO_THROW(CheckLineLimits("a\nb\nc\nd\n", "mem", kSmall));
  EXPECT_THROW(CheckLineLimits("a\nb\nc\nd\ne", "mem", kSmall), InputError);
}

}  // namespace
}  // namespace rabbit
