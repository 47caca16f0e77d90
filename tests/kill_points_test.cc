// Kills at the named phases (RABBIT_TEST_KILL_AT) of the writers that commit more than one file:
// the shard merge of `rabbit report`, the gaits and index of `rabbit gaits generate`, and every
// phase of `rabbit gaits build`. Each leaves a state the next run resumes or cleans, and the
// result equals an uninterrupted run's, byte for byte.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "cli_fixture.h"

namespace {

namespace fs = std::filesystem;
using rabbit::testing::CliRun;
using rabbit::testing::ReadText;
using rabbit::testing::RunCli;

const std::string kRoot = RABBIT_SOURCE_DIR;

std::string KillAt(const std::string& phase) { return "RABBIT_TEST_KILL_AT=" + phase; }

// Every file and folder below `root`, relative, with the files' bytes.
std::map<std::string, std::string> Snapshot(const fs::path& root) {
  std::map<std::string, std::string> files;
  if (!fs::exists(root)) return files;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    const std::string rel = fs::relative(e.path(), root).generic_string();
    files[rel] = e.is_directory() ? "<dir>" : ReadText(e.path());
  }
  return files;
}

// The shipped targets of vm_0.30 and vm_0.40 (the cheapest: a few walks each).
const char* const kTwoGaits = R"([[gait]]
v_m = 0.3
[gait.bounds]
qr1_dsw_deg = [10, 60]
q0_d_deg = [-5, 25]
pulse_torque_nm = [0, 100]
start_speed_m_s = [0.1, 1.5]
[gait.walker]
rule_share = 1

[[gait]]
v_m = 0.4
l_step = 0.24
)";

class KillPointsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rabbit_kill_points_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path Write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  fs::path dir_;
};

// The shard merge: before the swap the shards are whole (the runs are linked into the staging
// folder, not moved), after it the merged report is; the next `rabbit report` removes the
// staging folder and ends with the report of an uninterrupted merge.
TEST_F(KillPointsTest, ReportMergeKilledAtEveryPhaseIsFinishedByTheNext) {
  const fs::path suite =
      Write("small.toml",
            "[suite]\nname = \"small\"\n[defaults.simulation]\nduration = 0.2\n"
            "[defaults.initial]\nfoot_clearance = 0.02\n[defaults.controller]\ntype = "
            "\"pd_hold\"\nkp = 600.0\nkd = 30.0\n"
            "[[scenario]]\nname = \"one\"\n[[scenario]]\nname = \"two\"\n");
  const fs::path shards = dir_ / "shards_only", ref = dir_ / "ref", out = dir_ / "out";
  for (const char* shard : {"1/2", "2/2"}) {
    const CliRun r = RunCli("run " + suite.string() + " --jobs 1 --no-html -q --shard " + shard +
                            " --out " + shards.string());
    ASSERT_EQ(r.code, 0) << r.output;
  }
  fs::copy(shards, ref, fs::copy_options::recursive);
  ASSERT_EQ(RunCli("report -q " + ref.string()).code, 0);
  const std::string summary = ReadText(ref / "summary.csv");
  ASSERT_FALSE(summary.empty());
  for (const char* phase : {"report-merge-staging", "report-merge-linking", "report-merge-linked",
                            "report-merge-written", "report-merge-replaced"}) {
    SCOPED_TRACE(phase);
    fs::remove_all(out);
    fs::copy(shards, out, fs::copy_options::recursive);
    const auto before = Snapshot(out / "shards");
    const CliRun killed = RunCli("report -q " + out.string(), KillAt(phase));
    ASSERT_TRUE(killed.killed) << killed.output;
    if (std::string(phase) != "report-merge-replaced") {
      EXPECT_TRUE(fs::exists(dir_ / "out.merging"));  // what the kill left
      EXPECT_EQ(Snapshot(out / "shards"), before);    // every finished run is still in its shard
    } else {
      EXPECT_EQ(ReadText(out / "summary.csv"), summary);
    }
    const CliRun next = RunCli("report -q " + out.string());
    ASSERT_EQ(next.code, 0) << next.output;
    EXPECT_EQ(ReadText(out / "summary.csv"), summary);
    EXPECT_TRUE(fs::exists(out / "one" / "meta.csv"));
    EXPECT_FALSE(fs::exists(out / "shards"));
    EXPECT_FALSE(fs::exists(dir_ / "out.merging"));
  }
  // Something of the user's at the staging path is not touched.
  fs::remove_all(out);
  fs::copy(shards, out, fs::copy_options::recursive);
  fs::create_directories(dir_ / "out.merging");
  std::ofstream(dir_ / "out.merging" / "mine.txt") << "mine\n";
  const CliRun refused = RunCli("report -q " + out.string());
  EXPECT_EQ(refused.code, 2) << refused.output;
  EXPECT_NE(refused.output.find("out.merging: exists and is not a merge of rabbit report"),
            std::string::npos)
      << refused.output;
  EXPECT_EQ(ReadText(dir_ / "out.merging" / "mine.txt"), "mine\n");
  EXPECT_TRUE(fs::exists(out / "shards"));
}

// gaits generate writes its gaits and the index in one commit: a kill at any phase leaves the old
// database, or pending files only, or a decided commit (its pending index written); the next
// writer of the database (killed itself as soon as it holds the database) has finished the
// commit, or rolled it back, by then: no gait file the index does not list.
TEST_F(KillPointsTest, GaitsGenerateKilledAtEveryPhaseLeavesNoUnlistedGait) {
  const fs::path targets = Write("targets.toml", kTwoGaits), ref = dir_ / "ref", db = dir_ / "db";
  const std::string generate = "gaits generate " + targets.string() + " -q -j 1 --gaits ";
  ASSERT_EQ(RunCli(generate + ref.string()).code, 0);
  const auto expected = Snapshot(ref);
  ASSERT_EQ(expected.count("reference/vm_0.40.csv"), 1u);
  // Visible gait files (not the pending ones) that the index does not list.
  auto unlisted = [](const fs::path& reference) {
    std::string found;
    if (!fs::exists(reference)) return found;
    // Without an index, every gait file there is unlisted.
    const fs::path index_file = reference / "index.csv";
    const std::string index = fs::exists(index_file) ? ReadText(index_file) : std::string();
    for (const auto& e : fs::directory_iterator(reference)) {
      const std::string name = e.path().filename().string();
      if (name[0] == '.' || name == "index.csv") continue;
      if (index.find("\n" + name.substr(0, name.size() - 4) + "," + name) == std::string::npos) {
        found += name + " ";
      }
    }
    return found;
  };
  for (const char* phase : {"gaits-claimed", "gaits-add-staged", "gaits-add-decided",
                            "gaits-add-renaming", "gaits-add-done"}) {
    SCOPED_TRACE(phase);
    fs::remove_all(db);
    const CliRun killed = RunCli(generate + db.string(), KillAt(phase));
    ASSERT_TRUE(killed.killed) << killed.output;
    const bool decided =
        std::string(phase) != "gaits-claimed" && std::string(phase) != "gaits-add-staged";
    // The next writer finishes (decided) or rolls back (not yet) before it does anything else.
    const CliRun next = RunCli(generate + db.string(), KillAt("gaits-claimed"));
    ASSERT_TRUE(next.killed) << next.output;
    EXPECT_EQ(unlisted(db / "reference"), "");
    if (decided) {
      EXPECT_EQ(Snapshot(db), expected);
    } else {
      EXPECT_FALSE(fs::exists(db / "reference" / "index.csv"));
      EXPECT_EQ(Snapshot(db / "reference"), (std::map<std::string, std::string>{}));
    }
  }
}

// gaits build: a kill at each phase, then the same build: the bytes of an uninterrupted build,
// no staging folder left.
TEST_F(KillPointsTest, GaitsBuildKilledAtEveryPhaseResumesToTheSameBytes) {
  const fs::path targets = Write("targets.toml", kTwoGaits), ref = dir_ / "ref", db = dir_ / "db";
  const std::string build = "gaits build " + targets.string() + " -q -j 1 --out ";
  ASSERT_EQ(RunCli(build + ref.string()).code, 0);
  const auto expected = Snapshot(ref);
  ASSERT_EQ(expected.count("manifest.csv"), 1u);
  for (const char* phase :
       {"gaits-build-synthesized", "gaits-build-networks", "gaits-build-fll",
        "gaits-build-manifest", "gaits-build-swapping", "gaits-build-committed"}) {
    SCOPED_TRACE(phase);
    fs::remove_all(db);
    const CliRun killed = RunCli(build + db.string(), KillAt(phase));
    ASSERT_TRUE(killed.killed) << killed.output;
    const CliRun resumed = RunCli(build + db.string());
    ASSERT_EQ(resumed.code, 0) << resumed.output;
    EXPECT_EQ(Snapshot(db), expected);
    EXPECT_FALSE(fs::exists(db / ".build"));
    EXPECT_FALSE(fs::exists(dir_ / ".db.rabbit-lock"));
  }
}

}  // namespace
