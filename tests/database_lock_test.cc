// One lock per gait database: every command that writes a database (gaits synthesize / generate,
// train into its networks/, fis generate into its FLL file, gaits build) takes the lock on the
// database's root, so a second writer through any of them is refused while a first one writes;
// and what a killed writer leaves inside a built database (a lock file, a marked staging folder,
// a pending gait) does not make its manifest check refuse it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_fixture.h"
#include "gait_manifest.h"
#include "rabbit/gait/database_layout.h"
#include "rabbit/io/error.h"
#include "rabbit/io/sha256.h"

namespace rabbit {

namespace {

namespace fs = std::filesystem;
using rabbit::testing::CliRun;
using rabbit::testing::HeldWriter;
using rabbit::testing::ReadText;
using rabbit::testing::RunCli;

const std::string kRoot = RABBIT_SOURCE_DIR;

class DatabaseLockTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rabbit_database_lock_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // A database root with the shipped vm_0.30 and vm_0.40 in reference/ (quick to train).
  fs::path SmallDatabase() {
    const fs::path db = dir_ / "db", shipped = kRoot + "/gaits/reference";
    fs::create_directories(db / "reference");
    std::stringstream index(ReadText(shipped / "index.csv"));
    std::string line, text;
    std::getline(index, line);
    text = line + "\n";
    while (std::getline(index, line)) {
      for (const char* gait : {"vm_0.30", "vm_0.40"}) {
        if (line.rfind(std::string(gait) + ",", 0) != 0) continue;
        text += line + "\n";
        fs::copy_file(shipped / (std::string(gait) + ".csv"),
                      db / "reference" / (std::string(gait) + ".csv"));
      }
    }
    std::ofstream(db / "reference" / "index.csv") << text;
    return db;
  }
  fs::path dir_;
};

TEST_F(DatabaseLockTest, EveryWriterOfADatabaseTakesTheLockOnItsRoot) {
  EXPECT_EQ(DatabaseRootOf((dir_ / "db" / "reference").string()), (dir_ / "db").string());
  const fs::path db = SmallDatabase();
  EXPECT_EQ(DatabaseRootOf((db / "networks").string()), db.string());
  EXPECT_EQ(DatabaseRootOf((db / "gait_pattern.fll").string()), db.string());
  EXPECT_EQ(DatabaseRootOf((dir_ / "elsewhere.fll").string()), "");
  // train into the database, held while it writes its staging folder, under the lock.
  HeldWriter train("train -q --gaits " + db.string(), "train-staging", dir_ / "fifo",
                   dir_ / "train.log");
  const std::string pid = train.WaitAtPhase();
  const std::string busy = "is being written by another rabbit (pid " + pid + ")";
  const std::string targets = (dir_ / "t.toml").string();
  std::ofstream(targets) << "[[gait]]\nv_m = 0.3\n[[gait]]\nv_m = 0.4\n";
  for (const std::string& second :
       {"fis generate -q --gaits " + db.string(), "train -q --gaits " + db.string(),
        "gaits synthesize -q --vm 0.3 --budget 1 --gaits " + db.string(),
        "gaits generate -q " + targets + " --gaits " + db.string(),
        "gaits synthesize -q --vm 0.3 --budget 1 --dir " + (db / "reference").string()}) {
    SCOPED_TRACE(second);
    const CliRun r = RunCli(second);
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find(busy), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(db / "gait_pattern.fll"));
  EXPECT_EQ(train.Finish(), 0) << ReadText(dir_ / "train.log");
  EXPECT_TRUE(fs::exists(db / "networks" / ".rabbit-networks"));
  // No lock file inside the database: the one lock is beside its root.
  for (const auto& e : fs::recursive_directory_iterator(db)) {
    EXPECT_EQ(e.path().filename().string().find(".rabbit-lock"), std::string::npos) << e.path();
  }
  EXPECT_EQ(RunCli("fis generate -q --gaits " + db.string()).code, 0);
  EXPECT_TRUE(fs::exists(db / "gait_pattern.fll"));
}

// What killed writers leave inside a built database is not a file of the user's.
TEST_F(DatabaseLockTest, LeftoversOfRabbitInsideABuiltDatabaseDoNotFailItsManifest) {
  const fs::path db = dir_ / "built";
  fs::create_directories(db / "reference");
  std::ofstream(db / "reference" / "index.csv") << "name,file\n";
  std::ofstream(db / "walker.csv") << "gait,rule_share\n";
  Manifest manifest;
  manifest.generator = "rabbit test";
  for (const char* file : {"reference/index.csv", "walker.csv"}) {
    manifest.rows.push_back({"file", "", file, Sha256OfFile((db / file).string()), "", ""});
  }
  const std::string path = (db / "manifest.csv").string();
  std::ofstream(path) << ManifestText(manifest);
  VerifyManifest(ReadManifest(path), db.string(), path);
  // An older version's lock files, a marked staging folder of train, a pending gait and index,
  // a build's staging folder.
  std::ofstream(db / ".networks.rabbit-lock") << "4242\n";
  std::ofstream(db / ".reference.rabbit-lock") << "4242\n";
  fs::create_directories(db / "networks.staging");
  std::ofstream(db / "networks.staging" / ".rabbit-networks") << "rabbit-networks/1\n";
  std::ofstream(db / "networks.staging" / "vm_0.30_q_i1.csv") << "half";
  std::ofstream(db / "reference" / ".vm_0.50.csv.rabbit-pending") << "half";
  std::ofstream(db / "reference" / ".index.csv.rabbit-pending") << "half";
  fs::create_directories(db / ".build" / "reference");
  std::ofstream(db / ".build" / "reference" / "x.csv") << "half";
  EXPECT_NO_THROW(VerifyManifest(ReadManifest(path), db.string(), path));
  // A folder of the user's named like a staging folder, but without the marker, is refused.
  fs::create_directories(db / "mine.staging");
  std::ofstream(db / "mine.staging" / "notes.txt") << "mine";
  EXPECT_THROW(VerifyManifest(ReadManifest(path), db.string(), path), InputError);
  fs::remove_all(db / "mine.staging");
  std::ofstream(db / "notes.txt") << "mine";
  try {
    VerifyManifest(ReadManifest(path), db.string(), path);
    ADD_FAILURE() << "a file of the user's was not noticed";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "notes.txt");
  }
}

}  // namespace
}  // namespace rabbit
