// The ownership rule's pieces (rabbit/io/output_ownership.h) on their own: which folders and files
// are rabbit's, the gait database's recognition, the lock and the one-step folder replacement.
#include "rabbit/io/output_ownership.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "rabbit/io/atomic_file.h"
#include "rabbit/io/error.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

class OutputOwnershipTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rabbit_ownership_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path Write(const std::string& name, const std::string& text) {
    fs::create_directories((dir_ / name).parent_path());
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  static std::string Read(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }
  fs::path dir_;
};

TEST_F(OutputOwnershipTest, OwnedFoldersAreMissingEmptyOrMarked) {
  EXPECT_NO_THROW(CheckOwnedFolder("--out", dir_ / "missing", {".rabbit-x"}, "x"));
  fs::create_directories(dir_ / "empty");
  EXPECT_NO_THROW(CheckOwnedFolder("--out", dir_ / "empty", {".rabbit-x"}, "x"));
  Write("marked/.rabbit-x", "");
  Write("marked/data.csv", "1\n");
  EXPECT_NO_THROW(CheckOwnedFolder("--out", dir_ / "marked", {".rabbit-y", ".rabbit-x"}, "x"));
  Write("mine/notes.txt", "mine");
  try {
    CheckOwnedFolder("--out", dir_ / "mine", {".rabbit-x"}, "a thing of rabbit");
    ADD_FAILURE() << "a user's folder accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), (dir_ / "mine").string());
    EXPECT_NE(std::string(e.what()).find("is not a thing of rabbit (no .rabbit-x)"),
              std::string::npos)
        << e.what();
  }
  Write("file", "mine");
  EXPECT_THROW(CheckOwnedFolder("--out", dir_ / "file", {".rabbit-x"}, "x"), InputError);
}

TEST_F(OutputOwnershipTest, GaitDatabasesAreRecognisedByManifestOrIndex) {
  EXPECT_FALSE(IsGaitDatabase((dir_ / "none").string()));
  Write("new/manifest.csv", std::string(kGaitManifestFormat) + "\nfile,sha256\n");
  EXPECT_TRUE(IsGaitDatabase((dir_ / "new").string()));
  Write("old/index.csv", "name,file,target_v_m,measured_v_m,l_step_m,t_step_s,steps,source\n");
  EXPECT_TRUE(IsGaitDatabase((dir_ / "old").string()));
  Write("other/manifest.csv", "# format = something-else/1\n");
  Write("other/index.csv", "a,b\n");
  EXPECT_FALSE(IsGaitDatabase((dir_ / "other").string()));
  EXPECT_THROW(CheckGaitDatabaseOutput("--dir", (dir_ / "other").string()), InputError);
  EXPECT_NO_THROW(CheckGaitDatabaseOutput("--dir", (dir_ / "old").string()));
  EXPECT_TRUE(IsReservedGaitName("index"));
  EXPECT_TRUE(IsReservedGaitName("manifest"));
  EXPECT_FALSE(IsReservedGaitName("vm_0.50"));
}

TEST_F(OutputOwnershipTest, AtomicWriterRemovesTheTemporariesOfAKilledWriterOnly) {
  // A process that has ended: its pid names no running process (until the system reuses it).
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) ::_exit(0);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  const std::string dead = std::to_string(child), alive = std::to_string(::getpid());
  const fs::path file = Write("out.csv", "old");
  const fs::path stale = Write("out.csv.tmp." + dead + ".42", "half");
  const std::vector<fs::path> kept = {
      Write("out.csv.tmp." + alive + ".7", "a live writer's"),  // this process is running
      Write("other.csv.tmp." + dead + ".42", "another target's"),
      Write("out.csv.tmp." + dead, "no suffix: not a name rabbit gives"),
      Write("out.csv.tmp." + dead + ".4x", "not a number"),
      Write("out.csv.tmp.mine.1", "the user's")};
  fs::create_directories(dir_ / ("out.csv.tmp." + dead + ".43"));  // a folder is never removed
  WriteFileAtomically(file.string(), [](std::ostream& o) { o << "new"; });
  EXPECT_EQ(Read(file), "new");
  EXPECT_FALSE(fs::exists(stale));
  for (const fs::path& p : kept) EXPECT_TRUE(fs::exists(p)) << p;
  EXPECT_TRUE(fs::is_directory(dir_ / ("out.csv.tmp." + dead + ".43")));
}

TEST_F(OutputOwnershipTest, AtomicWriterReplacesOnlyRegularFiles) {
  const fs::path file = Write("a.txt", "old");
  WriteFileAtomically(file.string(), [](std::ostream& o) { o << "new"; });
  EXPECT_EQ(Read(file), "new");
  const fs::path fifo = dir_ / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_THROW(WriteFileAtomically(fifo.string(), [](std::ostream& o) { o << "x"; }), InputError);
  EXPECT_TRUE(fs::is_fifo(fifo));
  fs::create_directories(dir_ / "folder");
  EXPECT_THROW(WriteFileAtomically((dir_ / "folder").string(), [](std::ostream& o) { o << "x"; }),
               InputError);
  fs::create_symlink(file, dir_ / "link");
  EXPECT_THROW(WriteFileAtomically((dir_ / "link").string(), [](std::ostream& o) { o << "x"; }),
               InputError);
  EXPECT_EQ(Read(file), "new");
  // No temporary left beside them.
  for (const auto& e : fs::directory_iterator(dir_)) {
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos);
  }
}

TEST_F(OutputOwnershipTest, ASecondLockOnTheSameOutputIsRefusedNamingTheHolder) {
  const fs::path out = dir_ / "report";
  {
    OutputLock first(out, "--out");
    EXPECT_TRUE(first.held());
    EXPECT_TRUE(fs::exists(dir_ / ".report.rabbit-lock"));
    try {
      OutputLock second(out, "--out");
      ADD_FAILURE() << "two locks on one output";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("is being written by another rabbit (pid " +
                                           std::to_string(::getpid()) + ")"),
                std::string::npos)
          << e.what();
    }
    OutputLock other(dir_ / "another", "--out");  // another output: its own lock
    EXPECT_TRUE(other.held());
  }
  EXPECT_FALSE(fs::exists(dir_ / ".report.rabbit-lock"));  // removed by its holder
  OutputLock again(out / "", "--out");                     // free again ("report/" is "report")
  EXPECT_TRUE(again.held());
}

TEST_F(OutputOwnershipTest, ReplaceFolderSwapsInOneStepAndRemovesTheOld) {
  Write("out/.rabbit-x", "");
  Write("out/old.csv", "old");
  Write("out.staging/.rabbit-x", "");
  Write("out.staging/new.csv", "new");
  ReplaceFolder(dir_ / "out.staging", dir_ / "out");
  EXPECT_EQ(Read(dir_ / "out" / "new.csv"), "new");
  EXPECT_FALSE(fs::exists(dir_ / "out" / "old.csv"));
  EXPECT_FALSE(fs::exists(dir_ / "out.staging"));
  // Into a place where nothing is yet.
  Write("s2/a.csv", "a");
  ReplaceFolder(dir_ / "s2", dir_ / "sub" / "fresh");
  EXPECT_EQ(Read(dir_ / "sub" / "fresh" / "a.csv"), "a");
}

}  // namespace
}  // namespace rabbit
