// A writer interrupted, or started while another writes the same output, end to end on the built
// binary: a SIGKILL at each named phase (RABBIT_TEST_KILL_AT) of train, gaits report, run and tune
// leaves a state the next run resumes or cleans up, to the uninterrupted result; a resume over
// changed inputs is refused; a second writer is refused while the first holds the lock.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_fixture.h"
#include "file_safety_fixture.h"

namespace {

namespace fs = std::filesystem;

const std::string kRoot = RABBIT_SOURCE_DIR;

using rabbit::testing::CliRun;
using rabbit::testing::FileSafetyTest;
using rabbit::testing::HeldWriter;
using rabbit::testing::ReadText;
using rabbit::testing::RunCli;
using rabbit::testing::TreeSnapshot;
using rabbit::testing::WithoutWallTime;

// SIGKILL at each of train's phases: the old networks stay whole until the swap, and the next
// train cleans up and succeeds.
TEST_F(FileSafetyTest, TrainKilledAtEveryPhaseIsCleanedUpByTheNext) {
  const fs::path db = SmallDatabase("db"), nets = dir_ / "nets";
  const std::string train = "train --gaits " + db.string() + " --out " + nets.string();
  ASSERT_EQ(RunCli(train).code, 0);
  const auto networks = TreeSnapshot(nets);
  for (const char* phase : {"train-staging", "train-written", "train-replaced"}) {
    SCOPED_TRACE(phase);
    const CliRun killed = RunCli(train, std::string("RABBIT_TEST_KILL_AT=") + phase);
    ASSERT_TRUE(killed.killed) << killed.output;
    // Before the swap the old networks are whole; after it, the new ones (the same fits).
    EXPECT_EQ(TreeSnapshot(nets), networks);
    const CliRun next = RunCli(train);
    ASSERT_EQ(next.code, 0) << next.output;
    EXPECT_EQ(TreeSnapshot(nets), networks);
    EXPECT_FALSE(fs::exists(dir_ / "nets.staging"));
    EXPECT_FALSE(fs::exists(dir_ / ".nets.rabbit-lock"));
  }
}

// SIGKILL at each of gaits report's phases: the next report cleans up and succeeds.
TEST_F(FileSafetyTest, GaitReportKilledAtEveryPhaseIsCleanedUpByTheNext) {
  const fs::path db = SmallDatabase("db"), out = dir_ / "report";
  const std::string report = "gaits report --dir " + db.string() + " --out " + out.string();
  ASSERT_EQ(RunCli(report).code, 0);
  const auto page = TreeSnapshot(out);
  for (const char* phase :
       {"gaits-report-staging", "gaits-report-written", "gaits-report-replaced"}) {
    SCOPED_TRACE(phase);
    ASSERT_TRUE(RunCli(report, std::string("RABBIT_TEST_KILL_AT=") + phase).killed);
    EXPECT_EQ(TreeSnapshot(out), page);  // whole at every moment (the same walks, the same page)
    ASSERT_EQ(RunCli(report).code, 0);
    EXPECT_EQ(TreeSnapshot(out), page);
    EXPECT_FALSE(fs::exists(dir_ / "report.partial"));
  }
}

// Every gait file is read before the first walk: with the second gait broken, the report stops
// before it walks (a kill at the first walk is never reached), exit 2, naming the file.
TEST_F(FileSafetyTest, GaitReportReadsEveryGaitBeforeWalking) {
  const fs::path db = SmallDatabase("db");
  std::ofstream(db / "vm_0.40.csv", std::ios::app) << "not,a,row\n";
  const CliRun run =
      RunCli("gaits report --dir " + db.string() + " --out " + (dir_ / "report").string(),
             "RABBIT_TEST_KILL_AT=gaits-report-walking");
  EXPECT_FALSE(run.killed);
  EXPECT_EQ(run.code, 2) << run.output;
  EXPECT_NE(run.output.find("vm_0.40.csv"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(dir_ / "report"));
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
  const fs::path suite = SmallSuiteOnACopyOfTheGaits(), out = dir_ / "out";
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
  const fs::path suite = SmallSuiteOnACopyOfTheGaits(), out = dir_ / "out";
  const std::string run = "run " + suite.string() + " --jobs 1 --no-html -q --out " + out.string();
  ASSERT_EQ(RunCli(run + " --shard 1/2").code, 0);
  std::ofstream(dir_ / "gaits" / "reference" / "vm_0.30.csv", std::ios::app) << "\n";
  ASSERT_EQ(RunCli(run + " --shard 2/2").code, 0);
  const auto shards = TreeSnapshot(out);
  const CliRun merged = RunCli("report -q " + out.string());
  EXPECT_EQ(merged.code, 2) << merged.output;
  EXPECT_NE(merged.output.find("another plan"), std::string::npos) << merged.output;
  EXPECT_EQ(TreeSnapshot(out), shards);
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

TEST_F(FileSafetyTest, SecondRunWaitsForNoneAndTouchesNothingWhileTheFirstReplaces) {
  const fs::path suite = SmallSuite(), out = dir_ / "out";
  const std::string run = "run " + suite.string() + " --jobs 1 --no-html -q --out " + out.string();
  ASSERT_EQ(RunCli(run).code, 0);
  // The first run holds just before it swaps its finished report in, under its lock.
  HeldWriter first(run, "run-staged", dir_ / "fifo", dir_ / "first.log");
  const std::string pid = first.WaitAtPhase();
  const auto staging = TreeSnapshot(dir_ / "out.partial");
  const CliRun second = RunCli(run);
  EXPECT_EQ(second.code, 2) << second.output;
  EXPECT_NE(second.output.find("is being written by another rabbit (pid " + pid + ")"),
            std::string::npos)
      << second.output;
  EXPECT_EQ(TreeSnapshot(dir_ / "out.partial"), staging);  // the first one's work is untouched
  EXPECT_EQ(RunCli(run + " --resume").code, 2);
  EXPECT_EQ(first.Finish(), 0) << ReadText(dir_ / "first.log");
  EXPECT_TRUE(fs::exists(out / "summary.csv"));
  EXPECT_FALSE(fs::exists(dir_ / "out.partial"));
}

TEST_F(FileSafetyTest, SecondTuneResumeIsRefusedWhileTheFirstWrites) {
  const fs::path job = TuneJob(), out = dir_ / "job";
  const std::string tune = "tune " + job.string() + " -q --no-html --out " + out.string();
  HeldWriter first(tune, "tune-marked", dir_ / "fifo", dir_ / "first.log");
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
