// What rabbit will never do to a user's files, end to end on the built binary: every command that
// writes refuses (exit 2, naming the path, nothing touched) an output it did not make; a special
// file is never replaced; `-` is standard output. (A writer killed or run twice at once:
// interrupted_writers_test.)
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "cli_fixture.h"
#include "file_safety_fixture.h"

namespace {

namespace fs = std::filesystem;

const std::string kRoot = RABBIT_SOURCE_DIR;

using rabbit::testing::CliRun;
using rabbit::testing::FileSafetyTest;
using rabbit::testing::RunCli;
using rabbit::testing::TreeSnapshot;

std::string Expand(std::string text, const fs::path& dir) {
  for (size_t at; (at = text.find("{d}")) != std::string::npos;) text.replace(at, 3, dir.string());
  for (size_t at; (at = text.find("{root}")) != std::string::npos;) text.replace(at, 6, kRoot);
  return text;
}

class RefusalTest : public FileSafetyTest {
 public:
  fs::path Dir() const { return dir_; }
  using FileSafetyTest::MakeFifo;
  using FileSafetyTest::SmallDatabase;
  using FileSafetyTest::SmallSuite;
  using FileSafetyTest::TuneJob;
  using FileSafetyTest::Write;
  // The small suite's report, written by rabbit run at `name`.
  void SmallReport(const std::string& name) {
    SmallSuite();
    ASSERT_EQ(RunCli("run " + (dir_ / "small.toml").string() + " --no-html -q --out " +
                     (dir_ / name).string())
                  .code,
              0);
  }
};

// One class of refused output: the command (with {d} for the scratch folder), the exit code, a
// fragment of the message, and the paths that must be left exactly as they were.
struct Refusal {
  const char* name;
  std::function<void(RefusalTest*)> setup;
  std::string command;
  int code;
  std::string fragment;
  std::vector<std::string> untouched;
};

TEST_F(RefusalTest, EveryWriterRefusesWhatItDidNotMake) {
  const std::string sim = "simulate {root}/scenarios/drop_2cm.toml -q ";
  const std::vector<Refusal> table = {
      {"train over a user's folder",
       [](RefusalTest* t) { t->Write("mine/notes.txt", "mine"); },
       "train --gaits {root}/gaits/reference --out {d}/mine",
       2,
       "not a networks folder",
       {"{d}/mine"}},
      {"train over a user's file",
       [](RefusalTest* t) { t->Write("file.txt", "mine"); },
       "train --gaits {root}/gaits/reference --out {d}/file.txt",
       2,
       "is a file",
       {"{d}/file.txt"}},
      {"train over the gait database's folder",
       [](RefusalTest* t) {
         fs::copy(kRoot + "/gaits", t->Dir() / "gaits", fs::copy_options::recursive);
       },
       "train --gaits {d}/gaits/reference --out {d}/gaits",
       2,
       "not a networks folder",
       {"{d}/gaits"}},
      {"train over the gait database itself",
       [](RefusalTest* t) { t->SmallDatabase("db"); },
       "train --gaits {d}/db --out {d}/db",
       2,
       "not a networks folder",
       {"{d}/db"}},
      {"train whose staging name is a user's folder",
       [](RefusalTest* t) { t->Write("nets.staging/notes.txt", "mine"); },
       "train --gaits {root}/gaits/reference --out {d}/nets",
       2,
       "nets.staging",
       {"{d}/nets.staging"}},
      {"run over a user's X.partial",
       [](RefusalTest* t) {
         t->SmallSuite();
         t->Write("X.partial/notes.txt", "mine");
       },
       "run {d}/small.toml --no-html -q --out {d}/X",
       2,
       "X.partial",
       {"{d}/X.partial"}},
      {"run over a user's folder",
       [](RefusalTest* t) {
         t->SmallSuite();
         t->Write("X/notes.txt", "mine");
       },
       "run {d}/small.toml --no-html -q --out {d}/X",
       2,
       "not a report of rabbit run",
       {"{d}/X"}},
      // A report rabbit wrote, with a file a user added to it: not rabbit's to delete.
      {"run over its own report holding a user's file",
       [](RefusalTest* t) {
         t->SmallReport("X");
         t->Write("X/walk/notes.txt", "mine");
       },
       "run {d}/small.toml --no-html -q --out {d}/X",
       2,
       "holds walk/notes.txt, which is not one of the files rabbit wrote there",
       {"{d}/X"}},
      {"report of its own report holding a user's file",
       [](RefusalTest* t) {
         t->SmallReport("X");
         t->Write("X/notes.txt", "mine");
       },
       "report -q {d}/X",
       2,
       "holds notes.txt, which is not one of the files rabbit wrote there",
       {"{d}/X"}},
      {"run over its own report holding a user's empty folder",
       [](RefusalTest* t) {
         t->SmallReport("X");
         fs::create_directories(t->Dir() / "X" / "myplots");
       },
       "run {d}/small.toml --no-html -q --out {d}/X",
       2,
       "holds myplots/, which is not one of the files rabbit wrote there",
       {"{d}/X"}},
      // A shard written into an earlier report: checked against its own inventory.
      {"run over a report whose shard holds a user's file",
       [](RefusalTest* t) {
         t->SmallReport("X");
         ASSERT_EQ(RunCli("run " + (t->Dir() / "small.toml").string() +
                          " --no-html -q --shard 1/1 --out " + (t->Dir() / "X").string())
                       .code,
                   0);
         t->Write("X/shards/1-of-1/notes.txt", "mine");
       },
       "run {d}/small.toml --no-html -q --out {d}/X",
       2,
       "holds shards/1-of-1/notes.txt, which is not one of the files rabbit wrote there",
       {"{d}/X"}},
      {"run below a user's file",
       [](RefusalTest* t) {
         t->SmallSuite();
         t->Write("file.txt", "mine");
       },
       "run {d}/small.toml --no-html -q --out {d}/file.txt/X",
       2,
       "file.txt is a file, not a folder",
       {"{d}/file.txt"}},
      {"gaits synthesize named like the index",
       [](RefusalTest* t) { t->SmallDatabase("db"); },
       "gaits synthesize --vm 0.5 --name index --dir {d}/db -q",
       2,
       "database's own files",
       {"{d}/db"}},
      {"gaits synthesize named like the manifest",
       [](RefusalTest* t) { t->SmallDatabase("db"); },
       "gaits synthesize --vm 0.5 --name manifest --dir {d}/db -q",
       2,
       "database's own files",
       {"{d}/db"}},
      {"gaits synthesize into a user's folder",
       [](RefusalTest* t) { t->Write("mine/notes.txt", "mine"); },
       "gaits synthesize --vm 0.5 --dir {d}/mine -q",
       2,
       "not a gait database",
       {"{d}/mine"}},
      {"gaits synthesize into a user's folder named as a database",
       [](RefusalTest* t) { t->Write("mine/notes.txt", "mine"); },
       "gaits synthesize --vm 0.5 --gaits {d}/mine -q",
       2,
       "not a gait database",
       {"{d}/mine"}},
      {"gaits synthesize over a user's file in the database",
       [](RefusalTest* t) {
         t->SmallDatabase("db");
         t->Write("db/notes.csv", "mine\n");
       },
       "gaits synthesize --vm 0.5 --name notes --dir {d}/db -q",
       2,
       "not a gait file",
       {"{d}/db"}},
      {"gaits generate with two identical targets",
       [](RefusalTest* t) {
         t->SmallDatabase("db");
         t->Write("targets.toml", "[[gait]]\nv_m = 0.5\n[[gait]]\nv_m = 0.5\n");
       },
       "gaits generate {d}/targets.toml --dir {d}/db -q",
       2,
       "a second target named \"vm_0.50\" (the first is at line 1)",
       {"{d}/db"}},
      {"gaits report over a user's folder",
       [](RefusalTest* t) {
         t->SmallDatabase("db");
         t->Write("mine/index.html", "mine");
       },
       "gaits report --dir {d}/db --out {d}/mine",
       2,
       "not a gait report",
       {"{d}/mine"}},
      {"report of a user's folder",
       [](RefusalTest* t) { t->Write("mine/summary.csv", "mine"); },
       "report -q {d}/mine",
       2,
       "not a report of rabbit run",
       {"{d}/mine"}},
      {"tune into a user's folder",
       [](RefusalTest* t) {
         t->TuneJob();
         t->Write("mine/notes.txt", "mine");
       },
       "tune {d}/job.toml -q --no-html --out {d}/mine",
       2,
       "not a tuning job's folder",
       {"{d}/mine"}},
      {"simulate into a FIFO",
       [](RefusalTest* t) { t->MakeFifo("fifo"); },
       sim + "--out {d}/fifo",
       2,
       "is a FIFO",
       {"{d}/fifo"}},
      {"simulate over a folder",
       [](RefusalTest* t) { t->Write("folder/notes.txt", "mine"); },
       sim + "--out {d}/folder",
       2,
       "is a folder",
       {"{d}/folder"}},
      {"simulate over a user's file",
       [](RefusalTest* t) { t->Write("notes.csv", "mine\n"); },
       sim + "--out {d}/notes.csv",
       2,
       "not a trajectory CSV",
       {"{d}/notes.csv"}},
      {"fis generate over the gait index",
       [](RefusalTest* t) { t->SmallDatabase("db"); },
       "fis generate --gaits {d}/db --out {d}/db/index.csv",
       2,
       "not an FLL file",
       {"{d}/db"}},
      {"fis generate into a FIFO",
       [](RefusalTest* t) { t->MakeFifo("fifo"); },
       "fis generate --gaits {root}/gaits/reference --out {d}/fifo",
       2,
       "is a FIFO",
       {"{d}/fifo"}},
      // A built database (the shipped one, copied) changes only through gaits build.
      {"train into a built database",
       [](RefusalTest* t) {
         fs::copy(kRoot + "/gaits", t->Dir() / "built", fs::copy_options::recursive);
       },
       "train -q --gaits {d}/built",
       2,
       "made by rabbit gaits build",
       {"{d}/built"}},
      {"fis generate into a built database",
       [](RefusalTest* t) {
         fs::copy(kRoot + "/gaits", t->Dir() / "built", fs::copy_options::recursive);
       },
       "fis generate -q --gaits {d}/built --out {d}/built/gait_pattern.fll",
       2,
       "made by rabbit gaits build",
       {"{d}/built"}},
  };
  for (const Refusal& row : table) {
    SCOPED_TRACE(row.name);
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    row.setup(this);
    std::map<std::string, std::map<std::string, std::string>> before;
    for (const std::string& p : row.untouched) {
      before[p] = TreeSnapshot(Expand(p, dir_));
      ASSERT_FALSE(before[p].empty()) << p << ": nothing there to keep";
    }
    const CliRun run = RunCli(Expand(row.command, dir_));
    EXPECT_EQ(run.code, row.code) << run.output;
    EXPECT_NE(run.output.find(row.fragment), std::string::npos) << run.output;
    for (const std::string& p : row.untouched) {
      EXPECT_EQ(TreeSnapshot(Expand(p, dir_)), before[p]) << p << " changed";
    }
    // Nothing left beside them either: no lock, staging or temporary files.
    for (const auto& e : fs::directory_iterator(dir_)) {
      const std::string name = e.path().filename().string();
      EXPECT_EQ(name.find("rabbit-lock"), std::string::npos) << name;
      EXPECT_EQ(name.find(".tmp."), std::string::npos) << name;
    }
  }
}

// A symbolic link at a folder output, dangling or pointing to a folder, is refused before any
// work: replacing the folder would replace the user's link (and, before, left it renamed
// beside as X.partial).
TEST_F(FileSafetyTest, ASymbolicLinkAtAFolderOutputIsRefused) {
  SmallSuite();
  TuneJob();
  Write("targets.toml", "[[gait]]\nv_m = 0.5\n[[gait]]\nv_m = 0.6\n");
  Write("elsewhere/notes.txt", "mine");
  const std::vector<std::string> commands = {"run {d}/small.toml --no-html -q --out {d}/link",
                                             "tune {d}/job.toml -q --out {d}/link",
                                             "gaits build {d}/targets.toml -q --out {d}/link"};
  for (const char* target : {"missing", "elsewhere"}) {
    for (const std::string& command : commands) {
      SCOPED_TRACE(command + " -> " + target);
      fs::remove(dir_ / "link");
      fs::create_symlink(dir_ / target, dir_ / "link");
      const auto before = TreeSnapshot(dir_ / "elsewhere");
      const CliRun run = RunCli(Expand(command, dir_));
      EXPECT_EQ(run.code, 2);
      EXPECT_NE(run.output.find("is a symbolic link, not "), std::string::npos) << run.output;
      EXPECT_NE(run.output.find(": refusing to replace it or write through it; give the folder it "
                                "points to, or another path"),
                std::string::npos)
          << run.output;
      EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir_ / "link")));
      EXPECT_EQ(fs::read_symlink(dir_ / "link"), dir_ / target);
      EXPECT_EQ(TreeSnapshot(dir_ / "elsewhere"), before);
      EXPECT_FALSE(fs::exists(fs::symlink_status(dir_ / "link.partial")));
      EXPECT_FALSE(fs::exists(dir_ / "missing"));
    }
  }
}

// The report's own life is not refused: a run without pages, the pages added by rabbit report,
// a shard run into it and merged, a run again.
TEST_F(FileSafetyTest, AReportRewrittenByRabbitIsNotRefused) {
  SmallSuite();
  const std::string run = Expand("run {d}/small.toml -q --out {d}/X", dir_);
  ASSERT_EQ(RunCli(run + " --no-html").code, 0);
  ASSERT_EQ(RunCli(Expand("report -q {d}/X --gnuplot /bin/false", dir_), "", " 2>/dev/null").code,
            0);
  EXPECT_TRUE(fs::exists(dir_ / "X" / "index.html"));
  ASSERT_EQ(RunCli(run + " --no-html --shard 1/1").code, 0);
  ASSERT_EQ(RunCli(Expand("report -q {d}/X --gnuplot /bin/false", dir_), "", " 2>/dev/null").code,
            0);
  EXPECT_EQ(RunCli(run + " --no-html").code, 0);
  EXPECT_TRUE(fs::exists(dir_ / "X" / ".rabbit-inventory"));
}

// A build in which too few gaits meet their criteria writes nothing, not even its folder.
TEST_F(FileSafetyTest, AFailedGaitsBuildLeavesNoFolder) {
  Write("targets.toml", "[[gait]]\nv_m = 0.45\nbudget = 3\n[[gait]]\nv_m = 0.6\nbudget = 3\n");
  const CliRun run = RunCli(Expand("gaits build {d}/targets.toml -q -j2 --out {d}/db", dir_));
  EXPECT_EQ(run.code, 1);
  EXPECT_NE(run.output.find("fewer than 2 speed gaits met their criteria (the fuzzy system "
                            "blends at least 2): nothing written to"),
            std::string::npos)
      << run.output;
  EXPECT_FALSE(fs::exists(dir_ / "db"));
}

TEST_F(FileSafetyTest, DashIsStandardOutputForSingleFileOutputs) {
  const CliRun sim =
      RunCli("simulate " + kRoot + "/scenarios/drop_2cm.toml --out -", "", " 2>/dev/null");
  EXPECT_EQ(sim.code, 0);
  EXPECT_EQ(sim.output.rfind("t_s,", 0), 0u) << sim.output.substr(0, 200);
  EXPECT_FALSE(fs::exists("-"));
  const CliRun fll =
      RunCli("fis generate --gaits " + kRoot + "/gaits/reference --out -", "", " 2>/dev/null");
  EXPECT_EQ(fll.code, 0);
  EXPECT_NE(fll.output.find("RuleBlock"), std::string::npos) << fll.output;
  EXPECT_EQ(fll.output.find("wrote"), std::string::npos);  // the note went to standard error
}

TEST_F(FileSafetyTest, TrainReplacesOnlyItsOwnNetworksFolder) {
  const fs::path db = SmallDatabase("db"), nets = dir_ / "nets";
  const std::string train = "train --gaits " + db.string() + " --out " + nets.string();
  ASSERT_EQ(RunCli(train).code, 0);
  EXPECT_TRUE(fs::exists(nets / ".rabbit-networks"));
  EXPECT_TRUE(fs::exists(nets / "vm_0.40_qd_i2.csv"));
  // A file an earlier train wrote (listed in the folder's inventory) goes with the folder.
  std::ofstream(nets / "stale.csv") << "left by an earlier train\n";
  std::ofstream(nets / ".rabbit-inventory", std::ios::app) << "stale.csv\n";
  ASSERT_EQ(RunCli(train).code, 0);  // its own: replaced whole
  EXPECT_FALSE(fs::exists(nets / "stale.csv"));
  EXPECT_FALSE(fs::exists(dir_ / "nets.staging"));
  // A file a user put there (not in the inventory) is not rabbit's to delete: refused, kept.
  std::ofstream(nets / "notes.txt") << "mine\n";
  const auto before = TreeSnapshot(nets);
  const CliRun refused = RunCli(train);
  EXPECT_EQ(refused.code, 2);
  EXPECT_NE(
      refused.output.find("holds notes.txt, which is not one of the files rabbit wrote there"),
      std::string::npos)
      << refused.output;
  EXPECT_EQ(TreeSnapshot(nets), before);
  EXPECT_FALSE(fs::exists(dir_ / "nets.staging"));
}

}  // namespace
