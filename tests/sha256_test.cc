#include "rabbit/io/sha256.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "rabbit/io/error.h"

namespace rabbit {
namespace {

// FIPS 180-2 test vectors (the independent reference).
TEST(Sha256Test, MatchesPublishedVectors) {
  EXPECT_EQ(Sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(Sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(Sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

// A file larger than one read buffer hashes like the same bytes in memory.
TEST(Sha256Test, FileHashEqualsMemoryHash) {
  const std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / "sha256_test";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "data.bin").string();
  std::string bytes;
  for (int i = 0; i < 200000; ++i) bytes.push_back(static_cast<char>((i * 7919) % 251));
  {
    std::ofstream out(path, std::ios::binary);
    out << bytes;
  }
  EXPECT_EQ(Sha256OfFile(path), Sha256Hex(bytes));
}

TEST(Sha256Test, RefusesWhatIsNotARegularFile) {
  const std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / "sha256_dir";
  std::filesystem::create_directories(dir);
  EXPECT_THROW(Sha256OfFile(dir.string()), InputError);
  EXPECT_THROW(Sha256OfFile((dir / "missing").string()), InputError);
}

}  // namespace
}  // namespace rabbit
