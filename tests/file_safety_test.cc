// What rabbit will never do to a user's files, end to end on the built binary: every command that
// writes refuses (exit 2, naming the path, nothing touched) an output it did not make; a special
// file is never replaced; `-` is standard output; one writer per output; and a SIGKILL at each
// named phase (RABBIT_TEST_KILL_AT) leaves a state the next run resumes or cleans up.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_fixture.h"

namespace {

namespace fs = std::filesystem;

const std::string kRoot = RABBIT_SOURCE_DIR;

using rabbit::testing::CliRun;
using rabbit::testing::ReadText;
using rabbit::testing::RunCli;
using rabbit::testing::WithoutWallTime;

// Every file below `root` (or `root` itself) with its content, and every folder: what "untouched"
// compares.
std::map<std::string, std::string> Snapshot(const fs::path& root) {
  std::map<std::string, std::string> files;
  if (!fs::exists(fs::symlink_status(root))) return files;
  if (!fs::is_directory(fs::symlink_status(root))) {
    files[root.string()] = fs::is_fifo(fs::symlink_status(root)) ? "<fifo>" : ReadText(root);
    return files;
  }
  files[root.string()] = "<dir>";
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    const fs::file_status s = fs::symlink_status(e.path());
    files[e.path().string()] = fs::is_directory(s) ? "<dir>"
                               : fs::is_fifo(s)    ? "<fifo>"
                                                   : ReadText(e.path());
  }
  return files;
}

class FileSafetyTest : public rabbit::testing::ScratchDirTest {
 protected:
  FileSafetyTest() : ScratchDirTest("rabbit_file_safety") {}
  // A gait database of two shipped gaits (quick to train), at `name`.
  fs::path SmallDatabase(const std::string& name) {
    const fs::path db = dir_ / name, shipped = kRoot + "/gaits/reference";
    fs::create_directories(db);
    std::stringstream index(ReadText(shipped / "index.csv"));
    std::string line, text;
    std::getline(index, line);
    text = line + "\n";
    while (std::getline(index, line)) {
      if (line.rfind("vm_0.30,", 0) == 0 || line.rfind("vm_0.40,", 0) == 0) {
        text += line + "\n";
        const std::string file = line.substr(line.find(',') + 1);
        fs::copy_file(shipped / file.substr(0, file.find(',')),
                      db / file.substr(0, file.find(',')));
      }
    }
    std::ofstream(db / "index.csv") << text;
    return db;
  }
  // A two-scenario walking suite on the shipped database (a few seconds).
  fs::path SmallSuite() {
    return Write("small.toml",
                 "[suite]\nname = \"small\"\n[defaults]\nexpect_outcome = \"completed\"\n"
                 "[defaults.simulation]\nduration = 3.0\nrecord_every = 20\n"
                 "[defaults.velocity]\nvalue = 0.6\n"
                 "[defaults.controller]\ntype = \"fuzzy_cmac\"\nfll = \"" +
                     kRoot + "/gaits/gait_pattern.fll\"\nnetworks = \"" + kRoot +
                     "/gaits/networks\"\ngaits = \"" + kRoot + "/gaits/reference\"\n" +
                     "[[scenario]]\nname = \"walk\"\n[[scenario]]\nname = \"second\"\n");
  }
  fs::path TuneJob() {
    return Write("job.toml", "[job]\nsuites = [\"" + kRoot +
                                 "/scenarios/tune_ramp.toml\"]\nfilter = \"^ramp_up$\"\n"
                                 "max_evaluations = 4\n[objective]\nspeed_error = 1.0\n"
                                 "[[parameter]]\npath = \"controller.k_p\"\nlower = 0.0\n"
                                 "upper = 0.6\n[[parameter]]\npath = \"controller.k_v\"\n"
                                 "lower = 0.0\nupper = 0.4\n");
  }
  fs::path MakeFifo(const std::string& name) {
    const fs::path path = dir_ / name;
    EXPECT_EQ(::mkfifo(path.c_str(), 0600), 0);
    return path;
  }
};

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
    for (const std::string& p : row.untouched) before[p] = Snapshot(Expand(p, dir_));
    const CliRun run = RunCli(Expand(row.command, dir_));
    EXPECT_EQ(run.code, row.code) << run.output;
    EXPECT_NE(run.output.find(row.fragment), std::string::npos) << run.output;
    for (const std::string& p : row.untouched) {
      EXPECT_EQ(Snapshot(Expand(p, dir_)), before[p]) << p << " changed";
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
      const auto before = Snapshot(dir_ / "elsewhere");
      const CliRun run = RunCli(Expand(command, dir_));
      EXPECT_EQ(run.code, 2);
      EXPECT_NE(run.output.find("is a symbolic link"), std::string::npos) << run.output;
      EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir_ / "link")));
      EXPECT_EQ(fs::read_symlink(dir_ / "link"), dir_ / target);
      EXPECT_EQ(Snapshot(dir_ / "elsewhere"), before);
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
  ASSERT_EQ(
      RunCli(Expand("report -q {d}/X --gnuplot /nonexistent/gnuplot", dir_), "", " 2>/dev/null")
          .code,
      0);
  EXPECT_TRUE(fs::exists(dir_ / "X" / "index.html"));
  ASSERT_EQ(RunCli(run + " --no-html --shard 1/1").code, 0);
  ASSERT_EQ(
      RunCli(Expand("report -q {d}/X --gnuplot /nonexistent/gnuplot", dir_), "", " 2>/dev/null")
          .code,
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
  const auto before = Snapshot(nets);
  const CliRun refused = RunCli(train);
  EXPECT_EQ(refused.code, 2);
  EXPECT_NE(
      refused.output.find("holds notes.txt, which is not one of the files rabbit wrote there"),
      std::string::npos)
      << refused.output;
  EXPECT_EQ(Snapshot(nets), before);
  EXPECT_FALSE(fs::exists(dir_ / "nets.staging"));
}

// SIGKILL at each of train's phases: the old networks stay whole until the swap, and the next
// train cleans up and succeeds.
TEST_F(FileSafetyTest, TrainKilledAtEveryPhaseIsCleanedUpByTheNext) {
  const fs::path db = SmallDatabase("db"), nets = dir_ / "nets";
  const std::string train = "train --gaits " + db.string() + " --out " + nets.string();
  ASSERT_EQ(RunCli(train).code, 0);
  const auto networks = Snapshot(nets);
  for (const char* phase : {"train-staging", "train-written", "train-replaced"}) {
    SCOPED_TRACE(phase);
    const CliRun killed = RunCli(train, std::string("RABBIT_TEST_KILL_AT=") + phase);
    ASSERT_TRUE(killed.killed) << killed.output;
    // Before the swap the old networks are whole; after it, the new ones (the same fits).
    EXPECT_EQ(Snapshot(nets), networks);
    const CliRun next = RunCli(train);
    ASSERT_EQ(next.code, 0) << next.output;
    EXPECT_EQ(Snapshot(nets), networks);
    EXPECT_FALSE(fs::exists(dir_ / "nets.staging"));
    EXPECT_FALSE(fs::exists(dir_ / ".nets.rabbit-lock"));
  }
}

// SIGKILL at each of gaits report's phases: the next report cleans up and succeeds.
TEST_F(FileSafetyTest, GaitReportKilledAtEveryPhaseIsCleanedUpByTheNext) {
  const fs::path db = SmallDatabase("db"), out = dir_ / "report";
  const std::string report = "gaits report --dir " + db.string() + " --out " + out.string();
  ASSERT_EQ(RunCli(report).code, 0);
  const auto page = Snapshot(out);
  for (const char* phase :
       {"gaits-report-staging", "gaits-report-written", "gaits-report-replaced"}) {
    SCOPED_TRACE(phase);
    ASSERT_TRUE(RunCli(report, std::string("RABBIT_TEST_KILL_AT=") + phase).killed);
    EXPECT_EQ(Snapshot(out), page);  // whole at every moment (the same walks, the same page)
    ASSERT_EQ(RunCli(report).code, 0);
    EXPECT_EQ(Snapshot(out), page);
    EXPECT_FALSE(fs::exists(dir_ / "report.partial"));
  }
}

// SIGKILL at each of run's phases, then the same command with --resume: the report of an
// uninterrupted run, no staging folder left.
TEST_F(FileSafetyTest, RunKilledAtEveryPhaseResumes) {
  const fs::path suite = SmallSuite(), one = dir_ / "one", out = dir_ / "out";
  const std::string run = "run " + suite.string() + " --jobs 1 --no-html -q --out ";
  ASSERT_EQ(RunCli(run + one.string()).code, 0);
  const std::string expected = WithoutWallTime(ReadText(one / "summary.csv"));
  ASSERT_EQ(RunCli(run + out.string()).code, 0);  // an earlier report, replaced each time
  for (const char* phase : {"run-claimed", "run-staged", "run-replaced", "run-clearing-staging"}) {
    SCOPED_TRACE(phase);
    if (std::string(phase) == "run-clearing-staging") {
      // Clearing only happens over a staging folder left behind: leave one with finished runs.
      ASSERT_TRUE(RunCli(run + out.string(), "RABBIT_RUN_KILL_AFTER=2").killed);
    }
    const CliRun killed = RunCli(run + out.string(), std::string("RABBIT_TEST_KILL_AT=") + phase);
    ASSERT_TRUE(killed.killed) << killed.output;
    EXPECT_TRUE(fs::exists(out / "summary.csv"));  // a whole report is there at every moment
    const CliRun resumed = RunCli(run + out.string() + " --resume");
    ASSERT_EQ(resumed.code, 0) << resumed.output;
    EXPECT_EQ(WithoutWallTime(ReadText(out / "summary.csv")), expected);
    EXPECT_FALSE(fs::exists(dir_ / "out.partial"));
    EXPECT_FALSE(fs::exists(out / ".rabbit-staging"));
    EXPECT_FALSE(fs::exists(dir_ / ".out.rabbit-lock"));
  }
}

// A resume over a changed input file (here the gait database's index) is refused, naming it.
TEST_F(FileSafetyTest, RunResumeRefusesChangedInputFilesNamingThem) {
  fs::copy(kRoot + "/gaits", dir_ / "gaits", fs::copy_options::recursive);
  std::string text = ReadText(SmallSuite());
  for (size_t at; (at = text.find(kRoot + "/gaits")) != std::string::npos;) {
    text.replace(at, kRoot.size() + 6, (dir_ / "gaits").string());
  }
  const fs::path suite = Write("local.toml", text), out = dir_ / "out";
  const std::string run = "run " + suite.string() + " --jobs 1 --no-html -q --out " + out.string();
  ASSERT_TRUE(RunCli(run, "RABBIT_RUN_KILL_AFTER=1").killed);
  const fs::path changed = dir_ / "gaits" / "reference" / "vm_0.30.csv";
  std::ofstream(changed, std::ios::app) << "\n";
  const CliRun resumed = RunCli(run + " --resume");
  EXPECT_EQ(resumed.code, 2) << resumed.output;
  EXPECT_NE(resumed.output.find(changed.string() + " changed since the run began"),
            std::string::npos)
      << resumed.output;
  EXPECT_TRUE(fs::exists(dir_ / "out.partial" / ".rabbit-staging"));  // nothing discarded
}

// Shards run over different input files (a gait changed between them) are not merged.
TEST_F(FileSafetyTest, ShardsOverChangedInputFilesAreNotMerged) {
  fs::copy(kRoot + "/gaits", dir_ / "gaits", fs::copy_options::recursive);
  std::string text = ReadText(SmallSuite());
  for (size_t at; (at = text.find(kRoot + "/gaits")) != std::string::npos;) {
    text.replace(at, kRoot.size() + 6, (dir_ / "gaits").string());
  }
  const fs::path suite = Write("local.toml", text), out = dir_ / "out";
  const std::string run = "run " + suite.string() + " --jobs 1 --no-html -q --out " + out.string();
  ASSERT_EQ(RunCli(run + " --shard 1/2").code, 0);
  std::ofstream(dir_ / "gaits" / "reference" / "vm_0.30.csv", std::ios::app) << "\n";
  ASSERT_EQ(RunCli(run + " --shard 2/2").code, 0);
  const auto shards = Snapshot(out);
  const CliRun merged = RunCli("report -q " + out.string());
  EXPECT_EQ(merged.code, 2) << merged.output;
  EXPECT_NE(merged.output.find("another plan"), std::string::npos) << merged.output;
  EXPECT_EQ(Snapshot(out), shards);
}

// SIGKILL at each of tune's phases, then --resume: the result of an uninterrupted job.
TEST_F(FileSafetyTest, TuneKilledAtEveryPhaseResumes) {
  const fs::path job = TuneJob(), whole = dir_ / "whole", cut = dir_ / "cut";
  const std::string tune = "tune " + job.string() + " -q --no-html --out ";
  ASSERT_EQ(RunCli(tune + whole.string()).code, 0);
  for (const char* phase : {"tune-marked", "tune-searched"}) {
    SCOPED_TRACE(phase);
    fs::remove_all(cut);
    const CliRun killed = RunCli(tune + cut.string(), std::string("RABBIT_TEST_KILL_AT=") + phase);
    ASSERT_TRUE(killed.killed) << killed.output;
    const CliRun resumed = RunCli(tune + cut.string() + " --resume");
    ASSERT_EQ(resumed.code, 0) << resumed.output;
    EXPECT_EQ(ReadText(cut / "best.toml"), ReadText(whole / "best.toml"));
    EXPECT_FALSE(fs::exists(dir_ / ".cut.rabbit-lock"));
  }
}

// A tune --resume over a changed input file (a gait of the database) is refused, naming it.
TEST_F(FileSafetyTest, TuneResumeRefusesChangedInputFilesNamingThem) {
  fs::copy(kRoot + "/gaits", dir_ / "gaits", fs::copy_options::recursive);
  fs::create_directories(dir_ / "scenarios");
  fs::copy_file(kRoot + "/scenarios/tune_ramp.toml", dir_ / "scenarios" / "tune_ramp.toml");
  std::string text = ReadText(TuneJob());
  text.replace(text.find(kRoot), kRoot.size(), dir_.string());
  const fs::path job = Write("local_job.toml", text), out = dir_ / "job";
  const std::string tune = "tune " + job.string() + " -q --no-html --out " + out.string();
  ASSERT_TRUE(RunCli(tune, "RABBIT_TUNE_KILL_AFTER=2").killed);  // a log to resume
  const fs::path changed = dir_ / "gaits" / "reference" / "vm_0.30.csv";
  std::ofstream(changed, std::ios::app) << "\n";
  const CliRun resumed = RunCli(tune + " --resume");
  EXPECT_EQ(resumed.code, 2) << resumed.output;
  EXPECT_NE(resumed.output.find(changed.string() + " changed since the run began"),
            std::string::npos)
      << resumed.output;
}

// A process started in the background, held at a phase by the test hook's FIFO handshake, so the
// order of two writers is forced without any sleep.
class HeldWriter {
 public:
  HeldWriter(const std::string& args, const std::string& phase, const fs::path& fifo,
             const fs::path& log)
      : fifo_(fifo) {
    const std::string command = "RABBIT_TEST_PAUSE_AT=" + phase +
                                " RABBIT_TEST_PAUSE_FIFO=" + fifo.string() + " " + RABBIT_CLI_PATH +
                                " " + args + " > " + log.string() + " 2>&1";
    pipe_ = popen(command.c_str(), "r");
  }
  // Blocks until the writer has reached its phase; returns its pid.
  std::string WaitAtPhase() {
    std::ifstream in(fifo_);
    std::string phase, pid;
    in >> phase >> pid;
    return pid;
  }
  // Lets it go on, and returns its exit code.
  int Finish() {
    { std::ofstream release(fifo_); }
    const int status = pclose(pipe_);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

 private:
  fs::path fifo_;
  FILE* pipe_ = nullptr;
};

TEST_F(FileSafetyTest, SecondRunWaitsForNoneAndTouchesNothingWhileTheFirstReplaces) {
  const fs::path suite = SmallSuite(), out = dir_ / "out";
  const std::string run = "run " + suite.string() + " --jobs 1 --no-html -q --out " + out.string();
  ASSERT_EQ(RunCli(run).code, 0);
  // The first run holds just before it swaps its finished report in, under its lock.
  HeldWriter first(run, "run-staged", MakeFifo("fifo"), dir_ / "first.log");
  const std::string pid = first.WaitAtPhase();
  const auto staging = Snapshot(dir_ / "out.partial");
  const CliRun second = RunCli(run);
  EXPECT_EQ(second.code, 2) << second.output;
  EXPECT_NE(second.output.find("is being written by another rabbit (pid " + pid + ")"),
            std::string::npos)
      << second.output;
  EXPECT_EQ(Snapshot(dir_ / "out.partial"), staging);  // the first one's work is untouched
  EXPECT_EQ(RunCli(run + " --resume").code, 2);
  EXPECT_EQ(first.Finish(), 0) << ReadText(dir_ / "first.log");
  EXPECT_TRUE(fs::exists(out / "summary.csv"));
  EXPECT_FALSE(fs::exists(dir_ / "out.partial"));
}

TEST_F(FileSafetyTest, SecondTuneResumeIsRefusedWhileTheFirstWrites) {
  const fs::path job = TuneJob(), out = dir_ / "job";
  const std::string tune = "tune " + job.string() + " -q --no-html --out " + out.string();
  HeldWriter first(tune, "tune-marked", MakeFifo("fifo"), dir_ / "first.log");
  const std::string pid = first.WaitAtPhase();
  const CliRun second = RunCli(tune + " --resume");
  EXPECT_EQ(second.code, 2) << second.output;
  EXPECT_NE(second.output.find("is being written by another rabbit (pid " + pid + ")"),
            std::string::npos)
      << second.output;
  EXPECT_EQ(first.Finish(), 0) << ReadText(dir_ / "first.log");
  EXPECT_TRUE(fs::exists(out / "best.toml"));
}

}  // namespace
