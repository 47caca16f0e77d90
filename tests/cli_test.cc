// The rabbit CLI end to end: exit codes (0 success, 1 failed criteria, 2 bad input or usage), the
// error message naming file and key, and the CSV it writes. Runs the built binary.
#include <gtest/gtest.h>
#include <sys/wait.h>
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

#include "rabbit/io/csv_table.h"

namespace {

namespace fs = std::filesystem;

struct CliRun {
  int code = -1;
  bool killed = false;  // by SIGKILL (directly, or as the shell reports it: 128 + 9)
  std::string output;   // stdout and stderr
};

// `env` is prefixed to the command, e.g. "RABBIT_RUN_KILL_AFTER=5".
CliRun RunCli(const std::string& args, const std::string& env = "") {
  const std::string command =
      (env.empty() ? "" : env + " ") + std::string(RABBIT_CLI_PATH) + " " + args + " 2>&1";
  CliRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) run.output.append(buffer, n);
  const int status = pclose(pipe);
  run.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.killed = (WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) || run.code == 128 + SIGKILL;
  return run;
}

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rabbit_cli_test_" + std::to_string(::getpid()) + "_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
  std::string Scenario(const std::string& name) const {
    return std::string(RABBIT_SOURCE_DIR) + "/scenarios/" + name;
  }
  fs::path dir_;
};

TEST_F(CliTest, HelpAndVersion) {
  const CliRun version = RunCli("--version");
  EXPECT_EQ(version.code, 0);
  EXPECT_NE(version.output.find("rabbit "), std::string::npos);
  const CliRun help = RunCli("simulate --help");
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.output.find("--out"), std::string::npos);
}

TEST_F(CliTest, UsageErrorsExitTwo) {
  EXPECT_EQ(RunCli("").code, 2);
  EXPECT_EQ(RunCli("frobnicate").code, 2);
  EXPECT_EQ(RunCli("simulate").code, 2);
  EXPECT_EQ(RunCli("simulate " + Scenario("drop_2cm.toml") + " --integrator euler").code, 2);
}

TEST_F(CliTest, SimulateWritesTrajectoryCsv) {
  const std::string out = (dir_ / "sub" / "drop.csv").string();
  const CliRun run = RunCli("simulate " + Scenario("drop_2cm.toml") + " --out " + out);
  ASSERT_EQ(run.code, 0) << run.output;
  EXPECT_NE(run.output.find("outcome    completed"), std::string::npos) << run.output;
  std::ifstream csv(out);
  std::string header;
  std::getline(csv, header);
  for (const char* column : {"t_s", "q0_rad", "q22d_rad_s", "tau_hip1_nm", "foot1_fn_n",
                             "foot2_mode", "total_energy_j"}) {
    EXPECT_NE(header.find(column), std::string::npos) << column;
  }
  size_t rows = 0;
  for (std::string line; std::getline(csv, line);) ++rows;
  EXPECT_EQ(rows, 1501u);  // 1.5 s at 1 kHz, both ends
  // No temporary left behind.
  for (const auto& entry : fs::directory_iterator(dir_ / "sub")) {
    EXPECT_EQ(entry.path().filename(), "drop.csv");
  }
}

TEST_F(CliTest, ExpectedOutcomeMismatchExitsOne) {
  const std::string path = Write("expect.toml", R"(
expect_outcome = "completed"
[simulation]
duration = 2.0
[initial]
foot_clearance = 0.0
q11_deg = 20
q12_deg = -20
q21_deg = -10
q22_deg = -20
)");
  const CliRun run = RunCli("simulate " + path + " --out " + (dir_ / "t.csv").string());
  EXPECT_EQ(run.code, 1) << run.output;
  EXPECT_NE(run.output.find("fell"), std::string::npos) << run.output;
}

TEST_F(CliTest, BadInputExitsTwoNamingFileAndKeyAndWritesNothing) {
  const std::string path =
      Write("bad.toml", "[simulation]\nduration = 1\nrtoll = 1e-6\n[initial]\ny = 1\n");
  const std::string out = (dir_ / "never.csv").string();
  const CliRun run = RunCli("simulate " + path + " --out " + out);
  EXPECT_EQ(run.code, 2);
  EXPECT_NE(run.output.find(path + ":3"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("simulation.rtoll"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(out));
  const CliRun missing = RunCli("simulate " + (dir_ / "nope.toml").string());
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.output.find("no such file"), std::string::npos) << missing.output;
}

TEST_F(CliTest, GaitsListSynthesizeAndReport) {
  const CliRun list =
      RunCli("gaits list --dir " + std::string(RABBIT_SOURCE_DIR) + "/gaits/reference");
  EXPECT_EQ(list.code, 0) << list.output;
  EXPECT_NE(list.output.find("vm_0.60"), std::string::npos) << list.output;
  // A quick synthesis (the start point already walks at 0.45 m/s): writes the gait and index.
  const CliRun synth = RunCli("gaits synthesize --vm 0.45 -q --dir " + (dir_ / "db").string());
  EXPECT_EQ(synth.code, 0) << synth.output;
  EXPECT_TRUE(fs::exists(dir_ / "db" / "vm_0.45.csv"));
  EXPECT_TRUE(fs::exists(dir_ / "db" / "index.csv"));
  const CliRun report = RunCli("gaits report --dir " + (dir_ / "db").string() + " --out " +
                               (dir_ / "report").string());
  EXPECT_EQ(report.code, 0) << report.output;
  EXPECT_TRUE(fs::exists(dir_ / "report" / "index.html"));
}

TEST_F(CliTest, FisEvalAndTrain) {
  const std::string root = RABBIT_SOURCE_DIR;
  const CliRun eval = RunCli("fis eval " + root +
                             "/gaits/gait_pattern.fll --vm 0.55 --dobs 0.2 "
                             "--e-deg 5 --networks " +
                             root + "/gaits/networks");
  EXPECT_EQ(eval.code, 0) << eval.output;
  EXPECT_NE(eval.output.find("then gait is O8"), std::string::npos) << eval.output;  // Small
  EXPECT_NE(eval.output.find("q_i1"), std::string::npos) << eval.output;
  const CliRun train =
      RunCli("train --gaits " + root + "/gaits/reference --out " + (dir_ / "networks").string());
  EXPECT_EQ(train.code, 0) << train.output;
  EXPECT_TRUE(fs::exists(dir_ / "networks" / "index.csv"));
  EXPECT_TRUE(fs::exists(dir_ / "networks" / "vm_0.80_qd_i2.csv"));
  const std::string bad = Write("bad.fll", "Engine: x\nInputVariable: a\n  term: A Triangle 0 1\n");
  const CliRun refused = RunCli("fis eval " + bad + " --vm 0.5");
  EXPECT_EQ(refused.code, 2) << refused.output;
  EXPECT_NE(refused.output.find(bad), std::string::npos) << refused.output;
}

TEST_F(CliTest, FisEvalReadsInputsByNameAndRefusesBadValues) {
  const std::string root = RABBIT_SOURCE_DIR;
  // The shipped FLL with its two input blocks swapped: the same answer.
  std::ifstream in(root + "/gaits/gait_pattern.fll");
  std::stringstream text;
  text << in.rdbuf();
  std::string fll = text.str();
  const size_t v = fll.find("InputVariable: V_M"), d = fll.find("InputVariable: d_obs");
  const size_t end = fll.find("OutputVariable:");
  ASSERT_TRUE(v < d && d < end);
  const std::string swapped =
      fll.substr(0, v) + fll.substr(d, end - d) + fll.substr(v, d - v) + fll.substr(end);
  const std::string path = Write("swapped.fll", swapped);
  const CliRun a = RunCli("fis eval " + root + "/gaits/gait_pattern.fll --vm 0.6 --dobs 1");
  const CliRun b = RunCli("fis eval " + path + " --vm 0.6 --dobs 1");
  ASSERT_EQ(a.code, 0) << a.output;
  ASSERT_EQ(b.code, 0) << b.output;
  EXPECT_EQ(a.output.substr(a.output.find("output gait")),
            b.output.substr(b.output.find("output gait")));
  EXPECT_EQ(RunCli("fis eval --vm nan").code, 2);
  EXPECT_EQ(RunCli("fis eval --vm 0.5 --dobs -1").code, 2);
}

TEST_F(CliTest, TrainRefusesUnsafeGaitNamesAndWritesNothing) {
  const std::string root = RABBIT_SOURCE_DIR;
  fs::create_directories(dir_ / "g");
  fs::copy_file(root + "/gaits/reference/vm_0.60.csv", dir_ / "g" / "vm_0.60.csv");
  std::ifstream in(dir_ / "g" / "vm_0.60.csv");
  std::stringstream text;
  text << in.rdbuf();
  std::string gait = text.str();
  gait.replace(gait.find("# name = vm_0.60"), 16, "# name = ../../escape");
  std::ofstream(dir_ / "g" / "vm_0.60.csv") << gait;
  std::ofstream(dir_ / "g" / "index.csv")
      << "name,file,target_v_m,measured_v_m,l_step_m,t_step_s,steps,source\n"
      << "vm_0.60,vm_0.60.csv,0.6,0.58,0.35,0.6,32,test\n";
  const CliRun run =
      RunCli("train --gaits " + (dir_ / "g").string() + " --out " + (dir_ / "nets").string());
  EXPECT_EQ(run.code, 2) << run.output;
  EXPECT_FALSE(fs::exists(dir_ / "nets"));
  EXPECT_FALSE(fs::exists(dir_.parent_path() / "escape_q_i1.csv"));
}

TEST_F(CliTest, GaitsBadInputExitsTwo) {
  EXPECT_EQ(RunCli("gaits synthesize --vm -1 -q --dir " + (dir_ / "x").string()).code, 2);
  EXPECT_EQ(RunCli("gaits synthesize").code, 2);
  EXPECT_EQ(
      RunCli("gaits synthesize --vm 0.5 --name ../../escape -q --dir " + (dir_ / "y").string())
          .code,
      2);
  EXPECT_FALSE(fs::exists(dir_ / "escape.csv"));
  EXPECT_EQ(RunCli("gaits list --dir " + (dir_ / "none").string()).code, 2);
  const std::string config = Write("targets.toml", "[[gait]]\nv_m = 0.5\nspeed = 2\n");
  const CliRun run = RunCli("gaits generate " + config + " --dir " + (dir_ / "db").string());
  EXPECT_EQ(run.code, 2);
  EXPECT_NE(run.output.find("gait[1].speed"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(dir_ / "db"));
}

}  // namespace

namespace {

// A small walker suite on the shipped gaits: two short scenarios, one with a baseline; `extra`
// lands in the second scenario's own table.
std::string SmallSuite(const std::string& extra) {
  const std::string root = RABBIT_SOURCE_DIR;
  return "[suite]\nname = \"small\"\n[defaults]\nexpect_outcome = \"completed\"\n"
         "[defaults.simulation]\nduration = 6.0\nrecord_every = 20\n"
         "[defaults.velocity]\nvalue = 0.6\n"
         "[defaults.controller]\ntype = \"fuzzy_cmac\"\nfll = \"" +
         root + "/gaits/gait_pattern.fll\"\nnetworks = \"" + root +
         "/gaits/networks\"\ngaits = \"" + root +
         "/gaits/reference\"\n"
         "[[scenario]]\nname = \"walk\"\n[scenario.controller]\nbaselines = [\"nearest_gait\"]\n"
         "[[scenario]]\nname = \"second\"\n" +
         extra;
}

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// summary.csv without its last two columns (wall_s, real_time_factor).
std::string WithoutWallTime(const std::string& csv) {
  std::stringstream in(csv), out;
  std::string line;
  while (std::getline(in, line)) {
    for (int k = 0; k < 2; ++k) line = line.substr(0, line.rfind(','));
    out << line << "\n";
  }
  return out.str();
}

}  // namespace

TEST_F(CliTest, RunWritesTheReportAndIsTheSameOnOneAndTwoThreads) {
  const std::string suite = Write("small.toml", SmallSuite(""));
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
  const std::string summary = ReadFile(one / "summary.csv");
  EXPECT_EQ(WithoutWallTime(summary), WithoutWallTime(ReadFile(two / "summary.csv")));
  EXPECT_EQ(ReadFile(one / "walk" / "steps.csv"), ReadFile(two / "walk" / "steps.csv"));
  EXPECT_NE(summary.find("small,walk,nearest_gait,walk+nearest_gait"), std::string::npos);
  EXPECT_NE(b.output.find("3 runs"), std::string::npos) << b.output;
  // No staging folder is left beside the reports.
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().filename().string().find(".partial"), std::string::npos);
  }
}

TEST_F(CliTest, RunWithTheMultiCmacBaselineWritesItsRunFolderTheSameOnOneAndTwoThreads) {
  const std::string suite =
      Write("multi.toml", SmallSuite("[scenario.controller]\nbaselines = [\"multi_cmac\"]\n"));
  const fs::path one = dir_ / "one", two = dir_ / "two";
  const CliRun a = RunCli("run " + suite + " --jobs 1 --no-html -q --out " + one.string());
  ASSERT_EQ(a.code, 0) << a.output;
  const CliRun b = RunCli("run " + suite + " --jobs 2 --no-html -q --out " + two.string());
  ASSERT_EQ(b.code, 0) << b.output;
  for (const char* file : {"steps.csv", "trajectory.csv", "tracking.csv", "meta.csv"}) {
    EXPECT_TRUE(fs::exists(one / "second+multi_cmac" / file)) << file;
    EXPECT_EQ(ReadFile(one / "second+multi_cmac" / file),
              ReadFile(two / "second+multi_cmac" / file))
        << file;
  }
  const std::string summary = ReadFile(one / "summary.csv");
  EXPECT_NE(summary.find("small,second,multi_cmac,second+multi_cmac"), std::string::npos);
  EXPECT_EQ(WithoutWallTime(summary), WithoutWallTime(ReadFile(two / "summary.csv")));
  // No per-gait weights: the columns of the other variants, all nan; no rules.
  std::stringstream steps(ReadFile(one / "second+multi_cmac" / "steps.csv"));
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
      "run " + Write("bad.toml", SmallSuite("[scenario.controller.multi_cmac]\nv_m_width = 2\n")) +
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
      Write("fail.toml", SmallSuite("[scenario.criteria]\nmin_steps = 40\n"));
  const CliRun r = RunCli("run " + failing + " --no-html --out " + out.string());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("steps after the warm-up (at least 40 required)"), std::string::npos)
      << r.output;
  EXPECT_TRUE(fs::exists(out / "summary.csv"));  // the report is still written
  const std::string optional =
      Write("optional.toml", SmallSuite("required = false\n[scenario.criteria]\nmin_steps = 40\n"));
  EXPECT_EQ(RunCli("run " + optional + " --no-html -q --out " + out.string()).code, 0);
  // --filter: only the matching scenario runs.
  const CliRun filtered =
      RunCli("run " + failing + " --filter ^walk$ --no-html --out " + out.string());
  EXPECT_EQ(filtered.code, 0) << filtered.output;
  EXPECT_EQ(ReadFile(out / "summary.csv").find("second"), std::string::npos);
}

TEST_F(CliTest, RunOfSeveralSuitesReplacesNothingWhenOneIsBad) {
  const fs::path out = dir_ / "reports";
  const std::string good = Write("good.toml", SmallSuite(""));
  std::string bad_text = SmallSuite("");
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
    const std::string suite = Write("bad.toml", SmallSuite(extra));
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
  const CliRun refused = RunCli("run " + Write("ok.toml", SmallSuite("")) + " --out " +
                                (dir_ / "precious").string() + "/");
  EXPECT_EQ(refused.code, 2) << refused.output;
  EXPECT_NE(refused.output.find("refusing to replace"), std::string::npos) << refused.output;
  EXPECT_TRUE(fs::exists(dir_ / "precious" / "thesis.tex"));
  EXPECT_EQ(RunCli("run " + Write("ok.toml", SmallSuite("")) + " --out .").code, 2);
  // A report of rabbit run is replaced; a suite given to simulate is pointed to rabbit run.
  const fs::path report = dir_ / "report_twice";
  ASSERT_EQ(
      RunCli("run " + Write("ok.toml", SmallSuite("")) + " --no-html -q --out " + report.string())
          .code,
      0);
  EXPECT_EQ(RunCli("run " + Write("ok.toml", SmallSuite("")) + " --no-html -q --out " +
                   report.string() + "/")
                .code,
            0);
  EXPECT_TRUE(fs::exists(report / ".rabbit-report"));
  const CliRun suite_to_simulate = RunCli("simulate " + Write("ok.toml", SmallSuite("")));
  EXPECT_EQ(suite_to_simulate.code, 2);
  EXPECT_NE(suite_to_simulate.output.find("rabbit run"), std::string::npos);
  EXPECT_EQ(
      RunCli("run " + Write("ok.toml", SmallSuite("")) + " --filter '(' --out " + out.string())
          .code,
      2);
  EXPECT_FALSE(fs::exists(out));
}

namespace {

// The cells of a CSV line (RFC 4180 quotes; no cell spans lines in rabbit's files).
std::vector<std::string> CsvCells(const std::string& line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
      cells.back() += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      cells.emplace_back();
    } else {
      cells.back() += c;
    }
  }
  return cells;
}

// Occurrences of needle in text.
int Count(const std::string& text, const std::string& needle) {
  int n = 0;
  for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++n;
  return n;
}

// A CSV file as rows of column name -> cell.
std::vector<std::map<std::string, std::string>> CsvRows(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = CsvCells(line);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = CsvCells(line);
    EXPECT_EQ(cells.size(), header.size()) << line;
    std::map<std::string, std::string> row;
    for (size_t k = 0; k < header.size() && k < cells.size(); ++k) row[header[k]] = cells[k];
    rows.push_back(row);
  }
  return rows;
}

// SmallSuite and a family of four pushed walks beside the pragmatic rules: 11 runs.
std::string SuiteWithAFamily() {
  return SmallSuite("") +
         "[[family]]\nname = \"pushed\"\ncount = 4\nseed = 3\n[family.scenario]\n"
         "required = false\n[family.scenario.controller]\nbaselines = [\"pragmatic\"]\n"
         "[[family.scenario.push]]\nstart = 4.0\nduration = 0.1\nforce_x = 0.0\nheight = 0.2\n"
         "[family.vary]\n\"push.1.force_x\" = [-250.0, 250.0]\n";
}

}  // namespace

TEST_F(CliTest, HeadToHeadOfAFamilyIsTheSummarysAndRabbitReportRebuildsIt) {
  const std::string suite = Write("family.toml", SuiteWithAFamily());
  const fs::path out = dir_ / "out", csv_only = dir_ / "csv_only";
  const CliRun run = RunCli("run " + suite + " -q --out " + out.string());
  ASSERT_EQ(run.code, 0) << run.output;
  const std::string comparison = ReadFile(out / "comparison.csv");
  const auto summary = CsvRows(ReadFile(out / "summary.csv"));
  ASSERT_EQ(summary.size(), 11u);

  // The same figures computed here from summary.csv: per group (family, or plain scenario) and
  // variant, the counts, passed / runs with the Wilson interval (as the roots of the score
  // test's quadratic), and the speed error over the completed runs.
  struct Expected {
    int runs = 0, passed = 0, completed = 0, fell = 0, tripped = 0;
    std::vector<double> speed_errors;
  };
  std::map<std::string, Expected> expected;  // "group/kind/variant"
  for (const auto& r : summary) {
    const bool member = !r.at("family").empty();
    const std::string key = (member ? r.at("family") : r.at("scenario")) + "/" +
                            (member ? "family" : "scenario") + "/" + r.at("variant");
    Expected& e = expected[key];
    ++e.runs;
    e.passed += r.at("passed") == "1" ? 1 : 0;
    e.completed += r.at("outcome") == "completed" ? 1 : 0;
    e.fell += r.at("outcome") == "fell" ? 1 : 0;
    e.tripped += r.at("outcome") == "tripped" ? 1 : 0;
    if (r.at("outcome") == "completed") {
      e.speed_errors.push_back(std::stod(r.at("mean_abs_speed_error_m_s")));
    }
    EXPECT_EQ(r.at("pattern_memory_bytes") == "0", r.at("variant") == "pragmatic");
  }
  EXPECT_EQ(expected.count("pushed/family/fuzzy_cmac"), 1u);
  EXPECT_EQ(expected.at("pushed/family/fuzzy_cmac").runs, 4);
  const auto rows = CsvRows(comparison);
  ASSERT_EQ(rows.size(), expected.size());  // walk x 2, second, pushed x 2
  const double kTolerance = 1e-9;           // the files' 10 significant digits
  const double z = 1.959963984540054;
  for (const auto& c : rows) {
    const std::string key = c.at("group") + "/" + c.at("group_kind") + "/" + c.at("variant");
    ASSERT_EQ(expected.count(key), 1u) << key;
    const Expected& e = expected.at(key);
    EXPECT_EQ(std::stoi(c.at("runs")), e.runs) << key;
    EXPECT_EQ(std::stoi(c.at("passed")), e.passed) << key;
    EXPECT_EQ(std::stoi(c.at("completed")), e.completed) << key;
    EXPECT_EQ(std::stoi(c.at("fell")), e.fell) << key;
    EXPECT_EQ(std::stoi(c.at("tripped")), e.tripped) << key;
    const double n = e.runs, p = e.passed / n;
    EXPECT_NEAR(std::stod(c.at("success_rate")), p, kTolerance) << key;
    const double a = 1.0 + z * z / n, b = -(2.0 * p + z * z / n);
    const double root = std::sqrt(b * b - 4.0 * a * p * p);
    EXPECT_NEAR(std::stod(c.at("ci_low")), (-b - root) / (2.0 * a), kTolerance) << key;
    EXPECT_NEAR(std::stod(c.at("ci_high")), (-b + root) / (2.0 * a), kTolerance) << key;
    EXPECT_EQ(std::stoi(c.at("speed_error_runs")), static_cast<int>(e.speed_errors.size()));
    if (!e.speed_errors.empty()) {
      double mean = 0.0;
      for (double v : e.speed_errors) mean += v / static_cast<double>(e.speed_errors.size());
      EXPECT_NEAR(std::stod(c.at("speed_error_mean_m_s")), mean, kTolerance) << key;
    } else {
      EXPECT_EQ(c.at("speed_error_mean_m_s"), "nan") << key;
    }
  }
  // The family's outcomes are mixed (else this test would check little).
  const Expected& walker = expected.at("pushed/family/fuzzy_cmac");
  const Expected& rules = expected.at("pushed/family/pragmatic");
  EXPECT_LT(walker.completed + rules.completed, 8);
  EXPECT_GT(walker.completed + rules.completed, 0);

  // The page opens with the head-to-head: a table per group, the family's chart.
  const std::string page = ReadFile(out / "index.html");
  EXPECT_NE(page.find("<section id=\"head-to-head\">"), std::string::npos);
  EXPECT_EQ(Count(page, "<table class=\"comparison\">"), 3);
  if (run.output.find("figures left out") == std::string::npos) {
    EXPECT_EQ(Count(page, "alt=\"head-to-head of pushed\""), 1);
  }
  // rabbit report rebuilds comparison.csv from summary.csv alone; --no-html writes it too.
  fs::remove(out / "comparison.csv");
  fs::remove(out / "index.html");
  ASSERT_EQ(RunCli("report -q " + out.string()).code, 0);
  EXPECT_EQ(ReadFile(out / "comparison.csv"), comparison);
  EXPECT_TRUE(fs::exists(out / "index.html"));
  ASSERT_EQ(RunCli("run " + suite + " --no-html -q --out " + csv_only.string()).code, 0);
  EXPECT_EQ(ReadFile(csv_only / "comparison.csv"), comparison);
  EXPECT_FALSE(fs::exists(csv_only / "index.html"));
}

TEST_F(CliTest, ShardsMergedByReportEqualAnUnshardedRun) {
  const std::string suite = Write("small.toml", SmallSuite(""));
  const fs::path one = dir_ / "one", merged = dir_ / "merged";
  ASSERT_EQ(RunCli("run " + suite + " --no-html -q --out " + one.string()).code, 0);
  // Shard 1 of 2 takes jobs 0 and 2 (walk, second), shard 2 job 1 (walk+nearest_gait).
  const CliRun first = RunCli("run " + suite + " --shard 1/2 --out " + merged.string());
  ASSERT_EQ(first.code, 0) << first.output;
  EXPECT_NE(first.output.find("shard 1/2, 2 of 3 runs"), std::string::npos) << first.output;
  const fs::path shard1 = merged / "shards" / "1-of-2";
  for (const char* file : {".rabbit-shard", "summary.csv", "walk/steps.csv", "second/meta.csv"}) {
    EXPECT_TRUE(fs::exists(shard1 / file)) << file;
  }
  EXPECT_FALSE(fs::exists(shard1 / "walk+nearest_gait"));
  EXPECT_FALSE(fs::exists(shard1 / "index.html"));
  EXPECT_FALSE(fs::exists(merged / "summary.csv"));  // the main report is not touched
  const std::string marker = ReadFile(shard1 / ".rabbit-shard");
  EXPECT_EQ(marker.rfind("rabbit-shard/1\nsuite = small\nshard = 1/2\nplan = ", 0), 0u) << marker;
  EXPECT_NE(marker.find("\njobs = 3\nruns = 2\n"), std::string::npos) << marker;
  EXPECT_EQ(ReadFile(shard1 / "summary.csv").find("\n1,"), std::string::npos);  // not its job
  ASSERT_EQ(RunCli("run " + suite + " --shard 2/2 -q --out " + merged.string() + "/").code, 0);
  EXPECT_TRUE(fs::exists(shard1 / "walk")) << "shard 2 touched shard 1";

  const CliRun report = RunCli("report " + merged.string());
  ASSERT_EQ(report.code, 0) << report.output;
  EXPECT_NE(report.output.find("merged 2 shard(s) of suite small: 3 runs"), std::string::npos)
      << report.output;
  EXPECT_EQ(WithoutWallTime(ReadFile(one / "summary.csv")),
            WithoutWallTime(ReadFile(merged / "summary.csv")));
  for (const char* run : {"walk", "walk+nearest_gait", "second"}) {
    for (const char* file : {"steps.csv", "trajectory.csv", "meta.csv", "tracking.csv"}) {
      EXPECT_EQ(ReadFile(one / run / file), ReadFile(merged / run / file)) << run << "/" << file;
    }
  }
  EXPECT_FALSE(fs::exists(merged / "shards"));
  EXPECT_TRUE(fs::exists(merged / "index.html"));
  EXPECT_EQ(ReadFile(one / "comparison.csv"), ReadFile(merged / "comparison.csv"));
  EXPECT_EQ(ReadFile(merged / ".rabbit-report"), ReadFile(one / ".rabbit-report"));
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().filename().string().find(".partial"), std::string::npos);
  }
  // The merged folder is a report again: rebuilt by rabbit report, replaced by rabbit run.
  EXPECT_EQ(RunCli("report -q " + merged.string()).code, 0);
  EXPECT_EQ(RunCli("run " + suite + " --no-html -q --out " + merged.string()).code, 0);
}

TEST_F(CliTest, ShardBadInputExitsTwoAndWritesNothing) {
  const std::string suite = Write("small.toml", SmallSuite(""));
  const fs::path out = dir_ / "report";
  for (const char* shard : {"3/2", "0/2", "1/0", "2", "a/b", "1/2/3"}) {
    const CliRun r = RunCli("run " + suite + " --shard " + shard + " --out " + out.string());
    EXPECT_EQ(r.code, 2) << shard << r.output;
    EXPECT_NE(r.output.find("--shard expects I/N"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out)) << shard;
  }
  // A folder that is neither a report nor a folder of shards is not written into.
  fs::create_directories(dir_ / "precious");
  std::ofstream(dir_ / "precious" / "thesis.tex") << "keep me";
  const CliRun refused =
      RunCli("run " + suite + " --shard 1/2 --out " + (dir_ / "precious").string());
  EXPECT_EQ(refused.code, 2) << refused.output;
  EXPECT_FALSE(fs::exists(dir_ / "precious" / "shards"));
  // An unsharded run does not replace a folder of shards: merge it first.
  ASSERT_EQ(RunCli("run " + suite + " --shard 1/2 -q --out " + out.string()).code, 0);
  const CliRun unsharded = RunCli("run " + suite + " --no-html --out " + out.string());
  EXPECT_EQ(unsharded.code, 2) << unsharded.output;
  EXPECT_NE(unsharded.output.find("rabbit report"), std::string::npos) << unsharded.output;
  EXPECT_TRUE(fs::exists(out / "shards" / "1-of-2" / "walk"));
}

TEST_F(CliTest, ReportRefusesAnIncompleteOrMixedSetOfShards) {
  const std::string suite = Write("small.toml", SmallSuite(""));
  const fs::path out = dir_ / "report";
  ASSERT_EQ(RunCli("run " + suite + " --shard 1/3 -q --out " + out.string()).code, 0);
  ASSERT_EQ(RunCli("run " + suite + " --shard 3/3 -q --out " + out.string()).code, 0);
  const CliRun missing = RunCli("report " + out.string());
  EXPECT_EQ(missing.code, 2) << missing.output;
  EXPECT_NE(missing.output.find("missing shard(s) 2-of-3"), std::string::npos) << missing.output;
  // Nothing changed.
  EXPECT_TRUE(fs::exists(out / "shards" / "1-of-3" / "walk" / "steps.csv"));
  EXPECT_TRUE(fs::exists(out / "shards" / "3-of-3" / "second" / "steps.csv"));
  EXPECT_FALSE(fs::exists(out / "summary.csv"));
  EXPECT_FALSE(fs::exists(out / "index.html"));
  // Shard 2 of another plan (another --filter) does not complete the set; nor does another N.
  ASSERT_EQ(RunCli("run " + suite + " --filter walk --shard 2/3 -q --out " + out.string()).code, 0);
  const CliRun mixed = RunCli("report " + out.string());
  EXPECT_EQ(mixed.code, 2) << mixed.output;
  EXPECT_NE(mixed.output.find("another plan"), std::string::npos) << mixed.output;
  ASSERT_EQ(RunCli("run " + suite + " --shard 2/2 -q --out " + out.string()).code, 0);
  const CliRun counts = RunCli("report " + out.string());
  EXPECT_EQ(counts.code, 2) << counts.output;
  EXPECT_NE(counts.output.find("different counts"), std::string::npos) << counts.output;
  EXPECT_FALSE(fs::exists(out / "summary.csv"));
  // With the stray shards gone and shard 2 run again, the set merges.
  fs::remove_all(out / "shards" / "2-of-2");
  ASSERT_EQ(RunCli("run " + suite + " --shard 2/3 -q --out " + out.string()).code, 0);
  const CliRun complete = RunCli("report -q " + out.string());
  EXPECT_EQ(complete.code, 0) << complete.output;
  EXPECT_TRUE(fs::exists(out / "walk+nearest_gait" / "steps.csv"));
}

namespace {

// SmallSuite with three more scenarios: six runs (walk, walk+nearest_gait, second, third, fourth,
// fifth).
std::string SixRunSuite() {
  return SmallSuite("") +
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
      finished[entry.path().filename().string()] = ReadFile(entry.path() / ".rabbit-run");
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
  const std::string summary = ReadFile(out / "summary.csv");
  EXPECT_EQ(WithoutWallTime(summary), WithoutWallTime(ReadFile(one / "summary.csv")));
  for (const char* run : kSixRuns) {
    for (const char* file :
         {"steps.csv", "trajectory.csv", "meta.csv", "tracking.csv", "terrain.csv"}) {
      EXPECT_EQ(ReadFile(one / run / file), ReadFile(out / run / file)) << run << "/" << file;
    }
    EXPECT_FALSE(fs::exists(out / run / ".rabbit-run")) << run;  // the markers are gone
  }
  EXPECT_EQ(ReadFile(one / "comparison.csv"), ReadFile(out / "comparison.csv"));
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
  const std::string suite = Write(
      "timeout.toml", SmallSuite("required = false\n[scenario.simulation]\nmax_wall_s = 1e-6\n"));
  const CliRun r = RunCli("run " + suite + " --no-html --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string summary = ReadFile(out / "summary.csv");
  EXPECT_NE(summary.find("small,second,fuzzy_cmac,second,fuzzy_cmac,timeout,wall time "),
            std::string::npos)
      << summary;
  EXPECT_NE(summary.find("small,walk,fuzzy_cmac,walk,fuzzy_cmac,completed,"), std::string::npos);
  EXPECT_NE(summary.find("walk+nearest_gait,nearest_gait,completed,"), std::string::npos);
  EXPECT_NE(ReadFile(out / "second" / "meta.csv").find("outcome,timeout\nreason,wall time"),
            std::string::npos);
  EXPECT_NE(r.output.find("outcome timeout (expected completed)"), std::string::npos) << r.output;
  for (const char* bad : {"0", "-1", "\"soon\""}) {
    const std::string file = Write(
        "bad.toml", SmallSuite(std::string("[scenario.simulation]\nmax_wall_s = ") + bad + "\n"));
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

namespace {

// A copy of the shipped database with one library gait more: vm_0.70's swing, its e shifted by
// `shift` rad (beyond the speed gaits' range), named vm_0.70_l_0.41.
void WriteDatabaseWithALibraryGait(const fs::path& db, double shift) {
  const std::string root = RABBIT_SOURCE_DIR;
  fs::copy(root + "/gaits/reference", db);
  std::ifstream in(db / "vm_0.70.csv");
  std::ofstream out(db / "vm_0.70_l_0.41.csv");
  std::string line;
  bool header = false;
  while (std::getline(in, line)) {
    if (line == "# name = vm_0.70") line = "# name = vm_0.70_l_0.41";
    if (line == "# source = synthesized") line += "\n# role = library";
    if (header) {
      const size_t comma = line.find(',');
      char e[32];
      std::snprintf(e, sizeof e, "%.12g", std::stod(line.substr(0, comma)) + shift);
      line = e + line.substr(comma);
    }
    if (line.rfind("e_rad,", 0) == 0) header = true;
    out << line << "\n";
  }
  std::ofstream(db / "index.csv", std::ios::app)
      << "vm_0.70_l_0.41,vm_0.70_l_0.41.csv,0.7,0.684,0.412,0.601,32,synthesized,library,0.41\n";
}

}  // namespace

// Library gaits (other step lengths at a speed) take no part in the chapter's walker: the gait
// pattern generated over such a database is the shipped one byte for byte, the speed gaits'
// networks are the shipped ones, and a walk on that database is the walk on the shipped one.
TEST_F(CliTest, LibraryGaitsLeaveTheGaitPatternTheNetworksAndTheWalkerAsTheyAre) {
  const std::string root = RABBIT_SOURCE_DIR;
  const fs::path db = dir_ / "db", nets = dir_ / "nets";
  WriteDatabaseWithALibraryGait(db, -0.2);
  const CliRun fis =
      RunCli("fis generate --gaits " + db.string() + " --out " + (dir_ / "p.fll").string());
  ASSERT_EQ(fis.code, 0) << fis.output;
  EXPECT_EQ(ReadFile(dir_ / "p.fll"), ReadFile(root + "/gaits/gait_pattern.fll"));
  const CliRun train = RunCli("train --gaits " + db.string() + " --out " + nets.string());
  ASSERT_EQ(train.code, 0) << train.output;
  for (const auto& entry : fs::directory_iterator(root + "/gaits/networks")) {
    const std::string file = entry.path().filename().string();
    if (file == "index.csv") continue;
    EXPECT_EQ(ReadFile(nets / file), ReadFile(entry.path())) << file;
  }
  EXPECT_TRUE(fs::exists(nets / "vm_0.70_l_0.41_q_i1.csv"));
  const CliRun list = RunCli("gaits list --dir " + db.string());
  EXPECT_EQ(list.code, 0);
  EXPECT_NE(list.output.find("vm_0.70_l_0.41   library"), std::string::npos) << list.output;
  // The same small suite on the shipped files and on the database with its library gait.
  std::string suite = SmallSuite("");
  const std::string shipped = Write("shipped.toml", suite);
  for (const auto& [from, to] :
       {std::pair<std::string, std::string>{root + "/gaits/networks", nets.string()},
        {root + "/gaits/reference", db.string()},
        {root + "/gaits/gait_pattern.fll", (dir_ / "p.fll").string()}}) {
    suite.replace(suite.find(from), from.size(), to);
  }
  const std::string library = Write("library.toml", suite);
  const CliRun a =
      RunCli("run " + shipped + " --jobs 1 --no-html -q --out " + (dir_ / "a").string());
  ASSERT_EQ(a.code, 0) << a.output;
  const CliRun b =
      RunCli("run " + library + " --jobs 1 --no-html -q --out " + (dir_ / "b").string());
  ASSERT_EQ(b.code, 0) << b.output;
  for (const char* file : {"walk/steps.csv", "second/steps.csv", "walk+nearest_gait/steps.csv"}) {
    EXPECT_EQ(ReadFile(dir_ / "a" / file), ReadFile(dir_ / "b" / file)) << file;
  }
}
