// `rabbit run` end to end on the built binary: the report, the same on one and two threads, exit
// codes, bad input, resume after a kill, the wall-time limit, the data root and the verdict line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_fixture.h"
#include "rabbit/io/csv_table.h"

namespace {

namespace fs = std::filesystem;
using rabbit::testing::CliRun;
using rabbit::testing::CliTest;
using rabbit::testing::ReadText;
using rabbit::testing::RunCli;
using rabbit::testing::SmallWalkerSuite;
using rabbit::testing::WithoutWallTime;

}  // namespace

TEST_F(CliTest, RunWritesTheReportAndIsTheSameOnOneAndTwoThreads) {
  const std::string suite = Write("small.toml", SmallWalkerSuite(""));
  const fs::path one = dir_ / "one", two = dir_ / "two";
  const CliRun a = RunCli("run " + suite + " --jobs 1 --no-html -q --out " + one.string());
  ASSERT_EQ(a.code, 0) << a.output;
  const CliRun b = RunCli("run " + suite + " --jobs 2 --out " + two.string());
  ASSERT_EQ(b.code, 0) << b.output;
  for (const char* file : {"summary.csv", "walk/steps.csv", "walk+nearest_gait/trajectory.csv",
                           "second/meta.csv", "second/tracking.csv", "second/terrain.csv"}) {
    EXPECT_TRUE(fs::exists(one / file)) << file;
  }
  EXPECT_TRUE(fs::exists(two / "index.html"));
  const std::string summary = ReadText(one / "summary.csv");
  EXPECT_EQ(WithoutWallTime(summary), WithoutWallTime(ReadText(two / "summary.csv")));
  EXPECT_EQ(ReadText(one / "walk" / "steps.csv"), ReadText(two / "walk" / "steps.csv"));
  EXPECT_NE(summary.find("small,walk,nearest_gait,walk+nearest_gait"), std::string::npos);
  EXPECT_NE(b.output.find("3 runs"), std::string::npos) << b.output;
  // No staging folder is left beside the reports.
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().filename().string().find(".partial"), std::string::npos);
  }
}

TEST_F(CliTest, RunWithTheMultiCmacBaselineWritesItsRunFolderTheSameOnOneAndTwoThreads) {
  const std::string suite = Write(
      "multi.toml", SmallWalkerSuite("[scenario.controller]\nbaselines = [\"multi_cmac\"]\n"));
  const fs::path one = dir_ / "one", two = dir_ / "two";
  const CliRun a = RunCli("run " + suite + " --jobs 1 --no-html -q --out " + one.string());
  ASSERT_EQ(a.code, 0) << a.output;
  const CliRun b = RunCli("run " + suite + " --jobs 2 --no-html -q --out " + two.string());
  ASSERT_EQ(b.code, 0) << b.output;
  for (const char* file : {"steps.csv", "trajectory.csv", "tracking.csv", "meta.csv"}) {
    EXPECT_TRUE(fs::exists(one / "second+multi_cmac" / file)) << file;
    EXPECT_EQ(ReadText(one / "second+multi_cmac" / file),
              ReadText(two / "second+multi_cmac" / file))
        << file;
  }
  const std::string summary = ReadText(one / "summary.csv");
  EXPECT_NE(summary.find("small,second,multi_cmac,second+multi_cmac"), std::string::npos);
  EXPECT_EQ(WithoutWallTime(summary), WithoutWallTime(ReadText(two / "summary.csv")));
  // No per-gait weights: the columns of the other variants, all nan; no rules.
  std::stringstream steps(ReadText(one / "second+multi_cmac" / "steps.csv"));
  std::string line;
  std::getline(steps, line);
  EXPECT_NE(line.find(",w_O1,w_O2,w_O3,w_O4,w_O5,w_O6,w_O7,w_O8,rules,warmup"), std::string::npos)
      << line;
  int rows = 0;
  while (std::getline(steps, line)) {
    ++rows;
    EXPECT_NE(line.find(",nan,nan,nan,nan,nan,nan,nan,nan,,"), std::string::npos) << line;
  }
  EXPECT_GT(rows, 6);  // past the warm-up
  // A bad setting is bad input.
  const CliRun bad = RunCli(
      "run " +
      Write("bad.toml", SmallWalkerSuite("[scenario.controller.multi_cmac]\nv_m_width = 2\n")) +
      " --no-html --out " + (dir_ / "bad").string());
  EXPECT_EQ(bad.code, 2) << bad.output;
  EXPECT_NE(bad.output.find("scenario[2].controller.multi_cmac.v_m_width"), std::string::npos)
      << bad.output;
  EXPECT_FALSE(fs::exists(dir_ / "bad"));
}

TEST_F(CliTest, RunExitsOneWhenARequiredScenarioFailsItsCriteria) {
  const fs::path out = dir_ / "report";
  // 6 s cannot give 40 steps; the non-required scenario's failure alone would not count.
  const std::string failing =
      Write("fail.toml", SmallWalkerSuite("[scenario.criteria]\nmin_steps = 40\n"));
  const CliRun r = RunCli("run " + failing + " --no-html --out " + out.string());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("steps after the warm-up (at least 40 required)"), std::string::npos)
      << r.output;
  EXPECT_TRUE(fs::exists(out / "summary.csv"));  // the report is still written
  const std::string optional = Write(
      "optional.toml", SmallWalkerSuite("required = false\n[scenario.criteria]\nmin_steps = 40\n"));
  EXPECT_EQ(RunCli("run " + optional + " --no-html -q --out " + out.string()).code, 0);
  // --filter: only the matching scenario runs.
  const CliRun filtered =
      RunCli("run " + failing + " --filter ^walk$ --no-html --out " + out.string());
  EXPECT_EQ(filtered.code, 0) << filtered.output;
  EXPECT_EQ(ReadText(out / "summary.csv").find("second"), std::string::npos);
}

TEST_F(CliTest, RunOfSeveralSuitesReplacesNothingWhenOneIsBad) {
  const fs::path out = dir_ / "reports";
  const std::string good = Write("good.toml", SmallWalkerSuite(""));
  std::string bad_text = SmallWalkerSuite("");
  bad_text.replace(bad_text.find("name = \"small\""), 14, "name = \"other\"");
  bad_text.replace(bad_text.find("/gaits/networks"), 15, "/gaits/nowhere");
  const std::string bad = Write("bad.toml", bad_text);
  const CliRun r = RunCli("run " + good + " " + bad + " --no-html --out " + out.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_FALSE(fs::exists(out / "small")) << "the good suite's report was written";
  EXPECT_FALSE(fs::exists(out / "other"));
  ASSERT_EQ(RunCli("run " + good + " " + good + " --no-html -q --out " + out.string()).code, 2);
}

TEST_F(CliTest, RunBadInputExitsTwoAndLeavesNoReport) {
  const fs::path out = dir_ / "report";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"[scenario.controller]\ntype = \"walker\"\n", "unknown controller"},
      {"[[scenario.terrain.obstacles]]\nx_start = 3.0\nlength = 0.2\nheight = -0.05\n", "height"},
      {"[scenario.velocity]\nprofile = \"steps\"\n", "no points"},
      {"colour = \"red\"\n", "unknown key"},
  };
  for (const auto& [extra, fragment] : cases) {
    const std::string suite = Write("bad.toml", SmallWalkerSuite(extra));
    const CliRun r = RunCli("run " + suite + " --out " + out.string());
    EXPECT_EQ(r.code, 2) << extra << r.output;
    EXPECT_NE(r.output.find(fragment), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("bad.toml:"), std::string::npos) << r.output;  // file and line
    EXPECT_FALSE(fs::exists(out)) << extra;
    for (const auto& entry : fs::directory_iterator(dir_)) {
      EXPECT_EQ(entry.path().filename().string().find(".partial"), std::string::npos);
    }
  }
  EXPECT_EQ(RunCli("run " + dir_.string() + "/missing.toml --out " + out.string()).code, 2);
  // An existing folder that is not a report of rabbit run is never replaced, not even one with a
  // summary.csv; a trailing slash names the same folder.
  fs::create_directories(dir_ / "precious");
  std::ofstream(dir_ / "precious" / "thesis.tex") << "keep me";
  std::ofstream(dir_ / "precious" / "summary.csv") << "a,b\n";
  const CliRun refused = RunCli("run " + Write("ok.toml", SmallWalkerSuite("")) + " --out " +
                                (dir_ / "precious").string() + "/");
  EXPECT_EQ(refused.code, 2) << refused.output;
  EXPECT_NE(refused.output.find("refusing to replace"), std::string::npos) << refused.output;
  EXPECT_TRUE(fs::exists(dir_ / "precious" / "thesis.tex"));
  EXPECT_EQ(RunCli("run " + Write("ok.toml", SmallWalkerSuite("")) + " --out .").code, 2);
  // A report of rabbit run is replaced; a suite given to simulate is pointed to rabbit run.
  const fs::path report = dir_ / "report_twice";
  ASSERT_EQ(RunCli("run " + Write("ok.toml", SmallWalkerSuite("")) + " --no-html -q --out " +
                   report.string())
                .code,
            0);
  EXPECT_EQ(RunCli("run " + Write("ok.toml", SmallWalkerSuite("")) + " --no-html -q --out " +
                   report.string() + "/")
                .code,
            0);
  EXPECT_TRUE(fs::exists(report / ".rabbit-report"));
  const CliRun suite_to_simulate = RunCli("simulate " + Write("ok.toml", SmallWalkerSuite("")));
  EXPECT_EQ(suite_to_simulate.code, 2);
  EXPECT_NE(suite_to_simulate.output.find("rabbit run"), std::string::npos);
  EXPECT_EQ(RunCli("run " + Write("ok.toml", SmallWalkerSuite("")) + " --filter '(' --out " +
                   out.string())
                .code,
            2);
  EXPECT_FALSE(fs::exists(out));
}

namespace {

// SmallSuite with three more scenarios: six runs (walk, walk+nearest_gait, second, third, fourth,
// fifth).
std::string SixRunSuite() {
  return SmallWalkerSuite("") +
         "[[scenario]]\nname = \"third\"\n[scenario.velocity]\nvalue = 0.5\n"
         "[[scenario]]\nname = \"fourth\"\n[scenario.velocity]\nvalue = 0.55\n"
         "[[scenario]]\nname = \"fifth\"\n[scenario.velocity]\nvalue = 0.65\n";
}

const char* const kSixRuns[] = {"walk", "walk+nearest_gait", "second", "third", "fourth", "fifth"};

// The run folders of a staging folder that hold their completion marker, with its text.
std::map<std::string, std::string> FinishedRuns(const fs::path& staging) {
  std::map<std::string, std::string> finished;
  for (const auto& entry : fs::directory_iterator(staging)) {
    if (fs::exists(entry.path() / ".rabbit-run")) {
      finished[entry.path().filename().string()] = ReadText(entry.path() / ".rabbit-run");
    }
  }
  return finished;
}

}  // namespace

TEST_F(CliTest, RunKilledMidwayResumesToTheReportOfAnUninterruptedRun) {
  const std::string suite = Write("six.toml", SixRunSuite());
  const fs::path one = dir_ / "one", out = dir_ / "out", staging = dir_ / "out.partial";
  const CliRun whole = RunCli("run " + suite + " --jobs 2 --no-html -q --out " + one.string());
  ASSERT_EQ(whole.code, 0) << whole.output;

  const CliRun killed = RunCli("run " + suite + " --jobs 2 --no-html --out " + out.string(),
                               "RABBIT_RUN_KILL_AFTER=5");
  ASSERT_TRUE(killed.killed) << killed.code << killed.output;
  EXPECT_FALSE(fs::exists(out));
  std::map<std::string, std::string> before = FinishedRuns(staging);
  ASSERT_EQ(before.size(), 5u);
  // A run cut short while writing (its files partial, no marker) is run again, not reused.
  const std::string cut = before.begin()->first;
  fs::remove(staging / cut / ".rabbit-run");
  std::ofstream(staging / cut / "steps.csv") << "step,leg\n1,";
  before.erase(cut);

  const CliRun resumed =
      RunCli("run " + suite + " --jobs 2 --no-html --out " + out.string() + " --resume");
  ASSERT_EQ(resumed.code, whole.code) << resumed.output;
  EXPECT_NE(resumed.output.find("4 of 6 runs already finished"), std::string::npos)
      << resumed.output;
  EXPECT_NE(resumed.output.find("running 2 (1 cut short)"), std::string::npos) << resumed.output;
  EXPECT_NE(resumed.output.find("6 runs (4 resumed)"), std::string::npos) << resumed.output;
  EXPECT_FALSE(fs::exists(staging));
  const std::string summary = ReadText(out / "summary.csv");
  EXPECT_EQ(WithoutWallTime(summary), WithoutWallTime(ReadText(one / "summary.csv")));
  for (const char* run : kSixRuns) {
    for (const char* file :
         {"steps.csv", "trajectory.csv", "meta.csv", "tracking.csv", "terrain.csv"}) {
      EXPECT_EQ(ReadText(one / run / file), ReadText(out / run / file)) << run << "/" << file;
    }
    EXPECT_FALSE(fs::exists(out / run / ".rabbit-run")) << run;  // the markers are gone
  }
  EXPECT_EQ(ReadText(one / "comparison.csv"), ReadText(out / "comparison.csv"));
  // The finished runs were not run again: their rows, wall time included, are the marker's.
  for (const auto& [run, marker] : before) {
    const std::string row = marker.substr(marker.find('\n') + 1);
    EXPECT_NE(summary.find(row), std::string::npos) << run;
  }
  // A plain run replaces the resumed report as usual.
  EXPECT_EQ(RunCli("run " + suite + " --no-html -q --out " + out.string()).code, 0);
}

TEST_F(CliTest, RunResumeRefusesAnotherPlanAndRunsEverythingWhenNothingIsLeft) {
  const std::string suite = Write("six.toml", SixRunSuite());
  const fs::path out = dir_ / "out", staging = dir_ / "out.partial";
  // Nothing to resume: every run runs, and the output says so.
  const CliRun fresh = RunCli("run " + suite + " --no-html --out " + out.string() + " --resume");
  ASSERT_EQ(fresh.code, 0) << fresh.output;
  EXPECT_NE(fresh.output.find("nothing to resume"), std::string::npos) << fresh.output;
  EXPECT_TRUE(fs::exists(out / "fifth" / "steps.csv"));

  const CliRun killed = RunCli("run " + suite + " --jobs 1 --no-html -q --out " + out.string(),
                               "RABBIT_RUN_KILL_AFTER=2");
  ASSERT_TRUE(killed.killed) << killed.code << killed.output;
  const std::map<std::string, std::string> before = FinishedRuns(staging);
  ASSERT_EQ(before.size(), 2u);
  // Another plan (another --filter) does not resume it: exit 2, nothing changed.
  const CliRun other =
      RunCli("run " + suite + " --filter ^walk$ --no-html --out " + out.string() + " --resume");
  EXPECT_EQ(other.code, 2) << other.output;
  EXPECT_NE(other.output.find("another plan"), std::string::npos) << other.output;
  EXPECT_EQ(FinishedRuns(staging), before);
  EXPECT_TRUE(fs::exists(out / "fifth" / "steps.csv"));  // the earlier report is still there
  // Without --resume the unfinished run is discarded (with a note) and all runs again.
  const CliRun plain = RunCli("run " + suite + " --filter ^walk$ --no-html --out " + out.string());
  EXPECT_EQ(plain.code, 0) << plain.output;
  EXPECT_NE(plain.output.find("discarded the unfinished run"), std::string::npos) << plain.output;
  EXPECT_FALSE(fs::exists(staging));
  EXPECT_FALSE(fs::exists(out / "fifth"));
  EXPECT_TRUE(fs::exists(out / "walk+nearest_gait" / "steps.csv"));
}

TEST_F(CliTest, RunOverItsWallTimeLimitEndsAsTimeoutAndTheBatchGoesOn) {
  const fs::path out = dir_ / "report";
  // The clock is read after 100 control periods: far beyond a microsecond.
  const std::string suite =
      Write("timeout.toml",
            SmallWalkerSuite("required = false\n[scenario.simulation]\nmax_wall_s = 1e-6\n"));
  const CliRun r = RunCli("run " + suite + " --no-html --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string summary = ReadText(out / "summary.csv");
  EXPECT_NE(summary.find("small,second,fuzzy_cmac,second,fuzzy_cmac,timeout,wall time "),
            std::string::npos)
      << summary;
  EXPECT_NE(summary.find("small,walk,fuzzy_cmac,walk,fuzzy_cmac,completed,"), std::string::npos);
  EXPECT_NE(summary.find("walk+nearest_gait,nearest_gait,completed,"), std::string::npos);
  EXPECT_NE(ReadText(out / "second" / "meta.csv").find("outcome,timeout\nreason,wall time"),
            std::string::npos);
  EXPECT_NE(r.output.find("outcome timeout (expected completed)"), std::string::npos) << r.output;
  for (const char* bad : {"0", "-1", "\"soon\""}) {
    const std::string file =
        Write("bad.toml",
              SmallWalkerSuite(std::string("[scenario.simulation]\nmax_wall_s = ") + bad + "\n"));
    const CliRun refused = RunCli("run " + file + " --no-html --out " + (dir_ / "bad").string());
    EXPECT_EQ(refused.code, 2) << bad << refused.output;
    EXPECT_NE(refused.output.find("max_wall_s"), std::string::npos) << refused.output;
  }
}

// The data root's rule (cli/data_root.h), from a folder outside any checkout: no path compiled
// into the binary is ever read; --data, then RABBIT_DATA, name it; a bad one is bad input.
TEST_F(CliTest, DataRootIsFoundByOneRuleAndNeverCompiledIn) {
  const std::string root = RABBIT_SOURCE_DIR;
  const std::string here = "cd " + dir_.string() + " && env -u RABBIT_DATA";
  const CliRun none = RunCli("run", here);
  EXPECT_EQ(none.code, 2) << none.output;
  EXPECT_NE(none.output.find("no data root"), std::string::npos) << none.output;
  EXPECT_FALSE(fs::exists(dir_ / "reports"));
  const CliRun version = RunCli("--version", here);
  EXPECT_EQ(version.code, 0);
  EXPECT_NE(version.output.find("data root: none found"), std::string::npos) << version.output;

  const CliRun flag = RunCli("gaits list --data " + root, here);
  EXPECT_EQ(flag.code, 0) << flag.output;
  EXPECT_NE(flag.output.find("vm_0.60 "), std::string::npos) << flag.output;
  EXPECT_NE(RunCli("--data " + root + " --version", here).output.find("(found by: --data)"),
            std::string::npos);
  const CliRun env = RunCli("--version", "cd " + dir_.string() + " && RABBIT_DATA=" + root);
  EXPECT_NE(env.output.find("data root: " + root + " (found by: RABBIT_DATA)"), std::string::npos)
      << env.output;
  // --data before RABBIT_DATA.
  const CliRun both = RunCli("--data " + root + " --version",
                             "cd " + dir_.string() + " && RABBIT_DATA=" + dir_.string());
  EXPECT_NE(both.output.find("(found by: --data)"), std::string::npos) << both.output;
  // A folder below the checkout finds the checkout.
  const CliRun below = RunCli("--version", "cd " + root + "/src/rabbit && env -u RABBIT_DATA");
  EXPECT_NE(below.output.find("data root: " + root + " (found by: checkout)"), std::string::npos)
      << below.output;

  const CliRun missing = RunCli(
      "gaits list", "cd " + dir_.string() + " && RABBIT_DATA=" + (dir_ / "nowhere").string());
  EXPECT_EQ(missing.code, 2) << missing.output;
  EXPECT_NE(missing.output.find("RABBIT_DATA"), std::string::npos) << missing.output;
  const CliRun not_data = RunCli("gaits list --data " + dir_.string(), here);
  EXPECT_EQ(not_data.code, 2) << not_data.output;
  EXPECT_NE(not_data.output.find("is not a data root"), std::string::npos) << not_data.output;
  // A path the user gives is the working directory's, whatever the data root.
  const CliRun given = RunCli("gaits list --dir " + root + "/gaits/reference", here);
  EXPECT_EQ(given.code, 0) << given.output;
}

// rabbit run ends with a verdict over the required and optional runs and each family's success
// with its Wilson interval; a family's passed runs are left out of the table unless -v.
TEST_F(CliTest, RunEndsWithVerdictAndSummarisesFamilies) {
  const std::string out = (dir_ / "report").string();
  const std::string args = "run " + Scenario("paper.toml") +
                           " --filter '^flat$|obstacle_anywhere-00[0-5]' --no-html -j 2 -o " + out;
  const CliRun run = RunCli(args);
  ASSERT_EQ(run.code, 0) << run.output;
  int family_runs = 0, family_passed = 0, required = 0, required_passed = 0;
  std::vector<std::string> passed_members;
  const rabbit::CsvTable summary = rabbit::CsvTable::Read(out + "/summary.csv");
  for (size_t r = 0; r < summary.num_rows(); ++r) {
    const std::string name = summary.Text(r, summary.Column("run"));
    if (name != summary.Text(r, summary.Column("scenario"))) continue;  // a baseline
    const bool passed = summary.Text(r, summary.Column("passed")) == "1";
    if (summary.Text(r, summary.Column("family")).empty()) {
      ++required;
      required_passed += passed ? 1 : 0;
    } else {
      ++family_runs;
      family_passed += passed ? 1 : 0;
      if (passed) passed_members.push_back(name);
    }
  }
  ASSERT_EQ(family_runs, 6);
  EXPECT_EQ(required, 1);
  // Both kinds of member, so that the table's checks below see rows left out and rows listed.
  ASSERT_GT(family_passed, 0);
  ASSERT_LT(family_passed, 6);
  const std::string rate = std::to_string(family_passed) + "/6 passed";
  EXPECT_NE(run.output.find("verdict    PASSED: required " + std::to_string(required_passed) +
                            "/1 passed; optional " + rate),
            std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("family obstacle_anywhere " + rate + " ("), std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("95% CI "), std::string::npos);
  EXPECT_NE(run.output.find("family     obstacle_anywhere: " + rate), std::string::npos);
  EXPECT_NE(run.output.find("NO = a required scenario failed"), std::string::npos);
  for (const std::string& member : passed_members) {
    EXPECT_EQ(run.output.find(member + " "), std::string::npos) << member << " is in the table";
  }
  const CliRun verbose = RunCli(args + " -v");
  ASSERT_EQ(verbose.code, 0) << verbose.output;
  for (const std::string& member : passed_members) {
    EXPECT_NE(verbose.output.find(member + " "), std::string::npos) << member << " is not listed";
  }
  EXPECT_NE(verbose.output.find("data root: "), std::string::npos) << verbose.output;
}
