// The rabbit CLI end to end: exit codes (0 success, 1 failed criteria, 2 bad input or usage), the
// error message naming file and key, and the CSV it writes, for simulate, gaits, fis and train.
// Runs the built binary; `rabbit run` and `rabbit report` have cli_run_test and cli_report_test.
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
  // An index with a bad row: named before the synthesis (which would print its result first).
  std::ofstream(dir_ / "db" / "index.csv", std::ios::app) << "junk,row\n";
  const CliRun index = RunCli("gaits synthesize --vm 0.5 --dir " + (dir_ / "db").string());
  EXPECT_EQ(index.code, 2) << index.output;
  EXPECT_NE(index.output.find("index.csv:3: expected 10 cells"), std::string::npos) << index.output;
  EXPECT_EQ(index.output.find("simulations"), std::string::npos) << index.output;
  EXPECT_FALSE(fs::exists(dir_ / "db" / "vm_0.50.csv"));
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

namespace {

// A copy of the shipped database with one library gait more: vm_0.70's swing, its e shifted by
// `shift` rad (beyond the speed gaits' range), named vm_0.70_l_0.45.
void WriteDatabaseWithALibraryGait(const fs::path& db, double shift) {
  const std::string root = RABBIT_SOURCE_DIR;
  fs::copy(root + "/gaits/reference", db);
  std::ifstream in(db / "vm_0.70.csv");
  std::ofstream out(db / "vm_0.70_l_0.45.csv");
  std::string line;
  bool header = false;
  while (std::getline(in, line)) {
    if (line == "# name = vm_0.70") line = "# name = vm_0.70_l_0.45";
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
      << "vm_0.70_l_0.45,vm_0.70_l_0.45.csv,0.7,0.684,0.452,0.601,32,synthesized,library,0.45\n";
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
  EXPECT_EQ(ReadText(dir_ / "p.fll"), ReadText(root + "/gaits/gait_pattern.fll"));
  const CliRun train = RunCli("train --gaits " + db.string() + " --out " + nets.string());
  ASSERT_EQ(train.code, 0) << train.output;
  for (const auto& entry : fs::directory_iterator(root + "/gaits/networks")) {
    const std::string file = entry.path().filename().string();
    if (file == "index.csv") continue;
    EXPECT_EQ(ReadText(nets / file), ReadText(entry.path())) << file;
  }
  EXPECT_TRUE(fs::exists(nets / "vm_0.70_l_0.45_q_i1.csv"));
  const CliRun list = RunCli("gaits list --dir " + db.string());
  EXPECT_EQ(list.code, 0);
  EXPECT_NE(list.output.find("vm_0.70_l_0.45   library"), std::string::npos) << list.output;
  // The same small suite on the shipped files and on the database with its library gait.
  std::string suite = SmallWalkerSuite("");
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
    EXPECT_EQ(ReadText(dir_ / "a" / file), ReadText(dir_ / "b" / file)) << file;
  }
}

// Usage mistakes get a message that names what was wrong: an empty option value (`--out ''`,
// which would otherwise fall back to a default folder), a misspelt command, a misspelt key or
// table beside the required one it hides, a bad value from a --params overlay (blamed on the
// overlay's file and line), and a setting out of range (named with the value given).
TEST_F(CliTest, MistakesAreNamed) {
  const std::string scenario = Scenario("drop_2cm.toml");
  for (const std::string& args : std::vector<std::string>{
           "run --out ''", "run ''", "simulate " + scenario + " --out ''", "train --gaits ''",
           "gaits build t.toml --out ''", "gaits report --out ''", "--data '' run"}) {
    SCOPED_TRACE(args);
    const CliRun run = RunCli(args);
    EXPECT_EQ(run.code, 2);
    EXPECT_NE(run.output.find("expected a value, got an empty text"), std::string::npos)
        << run.output;
  }
  const CliRun command = RunCli("simulat " + scenario);
  EXPECT_EQ(command.code, 2);
  EXPECT_NE(command.output.find("'simulat' is not a command of rabbit (its commands: simulate,"),
            std::string::npos)
      << command.output;
  // Another kind of TOML file rabbit reads, given to run or simulate: the command that takes it.
  const std::string root = RABBIT_SOURCE_DIR;
  const struct {
    std::string command;
    std::string expected;
  } kinds[] = {
      {"run " + root + "/optimizers/jobs/velocity_gains.toml --no-html -q --out " +
           (dir_ / "never").string(),
       "velocity_gains.toml: this is a tuning job, not a scenario or a suite: run it with "
       "`rabbit tune`"},
      {"simulate " + root + "/gaits/targets.toml --out " + (dir_ / "never").string(),
       "targets.toml: this is a gait targets file, not a scenario or a suite: build it with "
       "`rabbit gaits build`"},
      {"run -q --no-html " + Write("best.toml", "[params]\n\"controller.k_p\" = 0.1\n"),
       "best.toml: this is a parameter overlay, not a scenario or a suite: give it to a command "
       "with --params"},
      {"simulate " + root + "/scenarios/paper.toml --out " + (dir_ / "never").string(),
       "paper.toml: this is a suite of scenarios: run it with `rabbit run`"}};
  for (const auto& kind : kinds) {
    SCOPED_TRACE(kind.command);
    const CliRun run = RunCli(kind.command);
    EXPECT_EQ(run.code, 2);
    EXPECT_NE(run.output.find(kind.expected), std::string::npos) << run.output;
    EXPECT_FALSE(fs::exists(dir_ / "never"));
  }
  // A scenario (it has [simulation]) with a stray key of such a name: that key, with its line.
  const CliRun stray =
      RunCli("simulate " + Write("stray.toml",
                                 "gait = \"x\"\n[simulation]\nduration = 0.05\n[initial]\n"
                                 "foot_clearance = 0.02\n[controller]\ntype = \"pd_hold\"\n"));
  EXPECT_EQ(stray.code, 2);
  EXPECT_NE(stray.output.find("stray.toml:1: 'gait': unknown key"), std::string::npos)
      << stray.output;
  // A word after an option the level does not take may be its value: no guess.
  const CliRun value = RunCli("fis --vm 0.5");
  EXPECT_EQ(value.code, 2);
  EXPECT_EQ(value.output.find("is not a command"), std::string::npos) << value.output;
  const CliRun sub = RunCli("gaits lst");
  EXPECT_EQ(sub.code, 2);
  EXPECT_NE(sub.output.find("'lst' is not a command of rabbit gaits"), std::string::npos)
      << sub.output;

  const std::string rest = "[controller]\ntype = \"passive\"\n[initial]\ny = 1\n";
  const CliRun table = RunCli("simulate " + Write("t.toml", "[simulaton]\nduration = 1\n" + rest));
  EXPECT_EQ(table.code, 2);
  EXPECT_NE(table.output.find("missing required key 'duration' (no table 'simulation' is "
                              "written: is 'simulaton' at line 1 a misspelling of it?)"),
            std::string::npos)
      << table.output;
  const CliRun key = RunCli("simulate " + Write("k.toml", "[simulation]\nduratoin = 1\n" + rest));
  EXPECT_EQ(key.code, 2);
  EXPECT_NE(key.output.find("(is 'simulation.duratoin' at line 2 a misspelling of it?)"),
            std::string::npos)
      << key.output;
  // Far from any key asked for: no guess.
  const CliRun far = RunCli("simulate " + Write("f.toml", "[simulation]\nlength = 1\n" + rest));
  EXPECT_EQ(far.code, 2);
  EXPECT_EQ(far.output.find("misspelling"), std::string::npos) << far.output;

  const std::string overlay = Write("p.toml", "# mine\n[params]\n\"simulation.duration\" = 1e9\n");
  const CliRun blamed = RunCli("simulate " + scenario + " --params " + overlay);
  EXPECT_EQ(blamed.code, 2);
  EXPECT_EQ(blamed.output.find("rabbit: error: " + overlay + ":3: 'simulation.duration': must be"),
            0u)
      << blamed.output;

  // A table's check that names the setting first is blamed on the overlay too.
  const std::string gain_overlay = Write("q.toml", "[params]\n\"controller.hip_kp\" = -5\n");
  const CliRun table_blamed =
      RunCli("simulate " + Scenario("walk_pragmatic_0.60.toml") + " --params " + gain_overlay);
  EXPECT_EQ(table_blamed.code, 2);
  EXPECT_EQ(table_blamed.output.find("rabbit: error: " + gain_overlay +
                                     ":2: 'controller.hip_kp': hip_kp must be >= 0, got -5"),
            0u)
      << table_blamed.output;
  const CliRun gains = RunCli("simulate " + Write("g.toml",
                                                  "[simulation]\nduration = 1\n[controller]\n"
                                                  "type = \"pragmatic\"\nhip_kp = -5\n"));
  EXPECT_EQ(gains.code, 2);
  EXPECT_NE(gains.output.find("hip_kp must be >= 0, got -5"), std::string::npos) << gains.output;
  const CliRun beta = RunCli("train --method lms --beta 0 --out " + (dir_ / "nets").string());
  EXPECT_EQ(beta.code, 2);
  EXPECT_NE(beta.output.find("beta must be in (0, 1], got 0"), std::string::npos) << beta.output;
  EXPECT_FALSE(fs::exists(dir_ / "nets"));
}
