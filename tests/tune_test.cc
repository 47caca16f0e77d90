// Tuning jobs (optimizers/tune_job.h, tuner.h): bad jobs are InputErrors naming the job file, line
// and key (exit 2 from the CLI); the result does not depend on the number of threads; a job killed
// midway (SIGKILL, a row half written) resumes to the same log and best.toml as an uninterrupted
// run; shards merge to the same result; best.toml given to `rabbit run --params` reproduces the
// best evaluation's runs; the objective's terms follow their definitions.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>

#include "cli_fixture.h"
#include "rabbit/io/csv_table.h"
#include "rabbit/io/error.h"
#include "rabbit/scenario/batch.h"
#include "tune_job.h"
#include "tuner.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

const std::string kRoot = RABBIT_SOURCE_DIR;

using testing::ReadText;
using testing::RunCliCode;
using testing::WithoutLastColumn;

class TuneTest : public testing::ScratchDirTest {
 protected:
  TuneTest() : ScratchDirTest("rabbit_tune_test") {}
  void SetUp() override {
    ScratchDirTest::SetUp();
    // A short walker scenario: 12 s of the ramp up (about 15 steps), two gains.
    Write("base.toml", "[params]\n\"simulation.duration\" = 12\n\"criteria.min_steps\" = 5\n");
  }
  // A small job: `extra_job` lines go into [job], `parameters` replaces the two gains.
  std::string Job(const std::string& extra_job = "", const std::string& parameters = "") {
    return Write(
        "job.toml",
        "[job]\n"                                                              // 1
        "suites = [\"" + kRoot + "/scenarios/tune_ramp.toml\"]\n"              // 2
        "filter = \"^ramp_up$\"\n"                                             // 3
        "params = \"base.toml\"\n"                                             // 4
        "max_evaluations = 6\n" +                                              // 5
            extra_job +
            "[objective]\nspeed_error = 1.0\nfailure_rate = 0.2\n" +
            (parameters.empty() ? "[[parameter]]\npath = \"controller.k_p\"\nlower = 0.0\n"
                                  "upper = 0.6\n[[parameter]]\npath = \"controller.k_v\"\n"
                                  "lower = 0.0\nupper = 0.4\n"
                                : parameters));
  }
  // The error LoadTuneJob gives for the job at `path` (if none, a test failure and a placeholder).
  static InputError LoadError(const std::string& path) {
    try {
      LoadTuneJob(path);
    } catch (const InputError& e) {
      return e;
    }
    ADD_FAILURE() << "no error for " << path;
    return InputError(path, -1, "", "(LoadTuneJob gave no error)");
  }
  void ExpectJobError(const std::string& extra_job, const std::string& parameters, int line,
                      const std::string& key, const std::string& fragment) {
    const std::string path = Job(extra_job, parameters);
    SCOPED_TRACE(extra_job + parameters);
    const InputError e = LoadError(path);
    EXPECT_EQ(e.file(), path) << e.what();
    if (line >= 0) {
      EXPECT_EQ(e.line(), line) << e.what();
    }
    EXPECT_EQ(e.key(), key) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
};

TEST_F(TuneTest, JobLoadsWithCurrentValuesAsInitial) {
  const TuneJob job = LoadTuneJob(Job());
  EXPECT_EQ(job.name, "job");
  ASSERT_EQ(job.parameters.size(), 2u);
  EXPECT_EQ(job.parameters[0].initial, 0.2);  // tune_ramp.toml's k_p
  EXPECT_EQ(job.parameters[1].initial, 0.10);
  EXPECT_EQ(job.algorithm, TuneAlgorithm::kBobyqa);
  EXPECT_EQ(job.fingerprint.size(), 16u);
}

TEST_F(TuneTest, BadJobsAreInputErrors) {
  const std::string one = "[[parameter]]\npath = \"controller.k_p\"\nlower = 0.0\nupper = 0.6\n";
  // Parameters start at line 10 (after 5 [job] lines, the algorithm and 3 [objective] lines).
  const std::string sbplx = "algorithm = \"sbplx\"\n";
  ExpectJobError(sbplx, "[[parameter]]\npath = \"controller.k_pp\"\nlower = 0\nupper = 1\n", 10,
                 "controller.k_pp", "names no numeric setting of scenario \"ramp_up\"");
  ExpectJobError(sbplx, "[[parameter]]\npath = \"controller.k_p\"\nlower = 1.0\nupper = 0.5\n",
                 12, "parameter[1].lower", "lower < upper");
  ExpectJobError("algorithm = \"simplex\"\n", one, 6, "job.algorithm", "unknown algorithm");
  ExpectJobError("", one, -1, "job.algorithm", "BOBYQA needs at least 2 parameters");
  ExpectJobError("algorithm = \"sbplx\"\n",
                 "[[parameter]]\npath = \"controller.k_p\"\nlower = 0.3\nupper = 0.6\n", 10,
                 "controller.k_p", "outside [lower, upper]");
  ExpectJobError("algorithm = \"sbplx\"\n",
                 "[[parameter]]\npath = \"controller.k_p\"\nlower = 0\nupper = 1\ninitial = 2\n",
                 14, "parameter[1].initial", "within [lower, upper]");
  ExpectJobError("budget = 5\n", one, 6, "job.budget", "unknown key");
  ExpectJobError(sbplx, "[[parameter]]\npath = \"controller.warmup_steps\"\nlower = 2\nupper = 8\n",
                 10, "controller.warmup_steps", "integer setting");
  ExpectJobError(sbplx, "[[parameter]]\npath = \"controller.k_p\"\nlower = -1e308\nupper = 1e308\n",
                 13, "parameter[1].upper", "overflows");
  ExpectJobError("algorithm = \"sbplx\"\n", one + one, -1, "parameter[2].path", "tuned twice");
  // A name taken by evaluations.csv's own columns would make the log unreadable (no resume, no
  // report).
  ExpectJobError(sbplx,
                 "[[parameter]]\npath = \"controller.k_p\"\nname = \"objective\"\nlower = 0\n"
                 "upper = 1\n",
                 12, "parameter[1].name", "a column of evaluations.csv");
}

TEST_F(TuneTest, MoreBadJobs) {
  const std::string one = "[[parameter]]\npath = \"controller.k_p\"\nlower = 0.0\nupper = 0.6\n";
  // No weight > 0.
  const std::string zero = Write(
      "zero.toml", "[job]\nsuites = [\"" + kRoot + "/scenarios/tune_ramp.toml\"]\n"
                   "algorithm = \"sbplx\"\n[objective]\nenergy = 0\n" + one);
  EXPECT_THROW(LoadTuneJob(zero), InputError);
  // Ceres needs a sum of squares.
  const std::string ceres = Write(
      "ceres.toml", "[job]\nsuites = [\"" + kRoot + "/scenarios/tune_ramp.toml\"]\n"
                    "algorithm = \"ceres\"\n[objective]\nform = \"mean\"\nenergy = 1\n" + one);
  {
    const InputError e = LoadError(ceres);
    EXPECT_EQ(e.key(), "objective.form");
    EXPECT_EQ(e.line(), 5);
  }
  // A suite that does not exist, and a guard that is another kind of file: named at the key that
  // lists them, with the path resolved from the job's folder.
  const std::string missing =
      Write("missing.toml", "[job]\nsuites = [\"nowhere.toml\"]\nalgorithm = \"sbplx\"\n"
                            "[objective]\nenergy = 1\n" + one);
  {
    const InputError e = LoadError(missing);
    EXPECT_EQ(e.key(), "job.suites");
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(std::string(e.what()).find(
                  "'job.suites': " + (fs::path(missing).parent_path() / "nowhere.toml").string() +
                  ": cannot open the file: no such file"),
              std::string::npos)
        << e.what();
  }
  const std::string guard =
      Write("guard.toml", "[job]\nsuites = [\"" + kRoot +
                              "/scenarios/tune_ramp.toml\"]\nguards = [\"" + kRoot +
                              "/optimizers/jobs/velocity_gains.toml\"]\nalgorithm = \"sbplx\"\n"
                              "[objective]\nenergy = 1\n" +
                              one);
  {
    const InputError e = LoadError(guard);
    EXPECT_EQ(e.key(), "job.guards");
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find("velocity_gains.toml: this is a tuning job, not a "
                                         "scenario or a suite: run it with `rabbit tune`"),
              std::string::npos)
        << e.what();
  }
  // An empty suite path, and a suite listed twice (its runs would be mixed in the logs).
  const std::string empty =
      Write("empty.toml", "[job]\nsuites = [\"\"]\nalgorithm = \"sbplx\"\n"
                          "[objective]\nenergy = 1\n" + one);
  {
    const InputError e = LoadError(empty);
    EXPECT_EQ(e.file(), empty);
    EXPECT_EQ(e.key(), "job.suites");
    EXPECT_EQ(e.line(), 2);
  }
  const std::string twice = Write(
      "twice.toml", "[job]\nsuites = [\"" + kRoot + "/scenarios/tune_ramp.toml\", \"" + kRoot +
                        "/scenarios/../scenarios/tune_ramp.toml\"]\nalgorithm = \"sbplx\"\n"
                        "[objective]\nenergy = 1\n" + one);
  {
    const InputError e = LoadError(twice);
    EXPECT_EQ(e.key(), "job.suites");
    EXPECT_NE(std::string(e.what()).find("two suites named \"tune_ramp\""), std::string::npos)
        << e.what();
  }
  // A candidate's values apply to every scenario of each suite and guard file: a tuned path that a
  // scenario outside the filter, or a guard's, lacks stops the job at load, at the parameter's
  // line (it made every candidate invalid, the whole budget run for no result).
  const std::string mixed =
      Write("mixed.toml",
            "[suite]\nname = \"mixed\"\n[defaults.simulation]\nduration = 1.0\n"
            "[defaults.initial]\ny = 0.9\n[[scenario]]\nname = \"held\"\n[scenario.controller]\n"
            "type = \"pd_hold\"\nkp = 600.0\n[[scenario]]\nname = \"passive\"\n"
            "[scenario.controller]\ntype = \"passive\"\n");
  const std::string kp = "[[parameter]]\npath = \"controller.kp\"\nlower = 100\nupper = 900\n";
  const std::string outside = Write("outside.toml",
                                    "[job]\nsuites = [\"mixed.toml\"]\nfilter = \"^held$\"\n"
                                    "algorithm = \"sbplx\"\n[objective]\nenergy = 1\n" +
                                        kp);
  const std::string guarded =
      Write("guarded.toml", "[job]\nsuites = [\"" + kRoot +
                                "/scenarios/tune_ramp.toml\"]\nguards = [\"" + kRoot +
                                "/scenarios/reference_gaits.toml\"]\nalgorithm = \"sbplx\"\n"
                                "[objective]\nenergy = 1\n" +
                                one);
  for (const auto& [job, key, text] :
       {std::tuple{outside, "controller.kp",
                   "names no numeric setting of scenario \"passive\" in " + mixed +
                       "; the filter leaves this scenario out, but a candidate's values apply to "
                       "every scenario of the file"},
        std::tuple{guarded, "controller.k_p",
                   "names no numeric setting of scenario \"vm_0.40\" in " + kRoot +
                       "/scenarios/reference_gaits.toml"}}) {
    SCOPED_TRACE(job);
    const InputError e = LoadError(job);
    EXPECT_EQ(e.key(), key);
    EXPECT_EQ(e.line(), 7);  // the [[parameter]]
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
  // A filter matching no scenario.
  const std::string nothing = Write(
      "nothing.toml", "[job]\nsuites = [\"" + kRoot + "/scenarios/tune_ramp.toml\"]\n"
                      "filter = \"^nothing$\"\nalgorithm = \"sbplx\"\n[objective]\nenergy = 1\n" +
                          one);
  {
    const InputError e = LoadError(nothing);
    EXPECT_EQ(e.key(), "job.filter");
  }
  // Filters are RE2 expressions: a back-reference and repeats above 1000 are refused with RE2's
  // reason, naming the key. (The input fuzz_tune_job once found to overflow std::regex,
  // tests/fuzz/regressions/fuzz_tune_job/, "\4444...", is an octal escape to RE2: a valid filter
  // that matches no scenario, refused as such.)
  for (const std::string filter : {"^vm_0(1)\\\\1$", "a{99999}", "a{2,1001}"}) {
    const std::string huge = Write(
        "huge.toml", "[job]\nsuites = [\"" + kRoot + "/scenarios/tune_ramp.toml\"]\nfilter = \"" +
                         filter + "\"\nalgorithm = \"sbplx\"\n[objective]\nenergy = 1\n" + one);
    SCOPED_TRACE(filter);
    const InputError e = LoadError(huge);
    EXPECT_EQ(e.key(), "job.filter");
    EXPECT_NE(std::string(e.what()).find("RE2 syntax"), std::string::npos) << e.what();
  }
  {
    const std::string octal = Write(
        "octal.toml", "[job]\nsuites = [\"" + kRoot + "/scenarios/tune_ramp.toml\"]\n"
                      "filter = \"^vm_0\\\\4444444444444444444444$\"\n"
                      "algorithm = \"sbplx\"\n[objective]\nenergy = 1\n" + one);
    const InputError e = LoadError(octal);
    EXPECT_EQ(e.key(), "job.filter");
    EXPECT_NE(std::string(e.what()).find("no scenario"), std::string::npos) << e.what();
  }
  EXPECT_NE(RegexFilterProblem("^ramp_(up|down){1,2}[0-9]\\1$"), "");  // no back-references
  EXPECT_EQ(RegexFilterProblem("^ramp_(up|down){1,2}[0-9]$"), "");
  EXPECT_EQ(RegexFilterProblem("\\\\99999"), "");  // an escaped backslash, then digits
  EXPECT_EQ(RegexFilterProblem("x{2,1000}"), "");
  EXPECT_NE(RegexFilterProblem("x{1000,99999}"), "");
  // The CLI: exit 2, the file and the key in the message, nothing written.
  std::string output;
  EXPECT_EQ(RunCliCode("tune " +
                       Job("algorithm = \"sbplx\"\n",
                           "[[parameter]]\npath = \"controller.k_pp\"\nlower = 0\nupper = 1\n") +
                       " --out " + (dir_ / "out").string(),
                   &output),
            2);
  EXPECT_NE(output.find("job.toml:10: 'controller.k_pp'"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
  EXPECT_EQ(RunCliCode("tune " + Job("algorithm = \"simplex\"\n"), &output), 2);
  EXPECT_EQ(RunCliCode("tune " + Job() + " --shard 3/2", &output), 2);
  EXPECT_EQ(RunCliCode("tune " + Job() + " --resume --force", &output), 2);
}

TEST_F(TuneTest, ObjectiveTermsFollowTheirDefinitions) {
  TuneObjective o;
  o.weight[kFailureRate] = 2.0;
  o.weight[kSpeedError] = 10.0;
  o.missing[kSpeedError] = 1.0;
  Evaluation e;
  RunScore a, b;
  a.passed = true;
  a.value = {0.0, 0.03, 0.01, 100.0, 0.4, 1.0, 0.0};
  b.passed = false;
  b.value = {1.0, std::nan(""), 0.02, 50.0, std::nan(""), 0.0, 1.0};
  e.scores = {a, b};
  ScoreEvaluation(o, &e);
  EXPECT_EQ(e.runs, 2);
  EXPECT_EQ(e.failed, 1);
  EXPECT_DOUBLE_EQ(e.terms[kFailureRate], 0.5);
  EXPECT_DOUBLE_EQ(e.terms[kSpeedError], (0.03 + 1.0) / 2);  // the missing value counts 1.0
  EXPECT_DOUBLE_EQ(e.objective, 2.0 * 0.5 + 10.0 * (0.03 + 1.0) / 2);
  EXPECT_DOUBLE_EQ(e.terms[kIncompleteRate], 0.5);  // a term without weight is still reported
  o.weight[kIncompleteRate] = 3.0;                  // a run that did not complete counts extra
  ScoreEvaluation(o, &e);
  EXPECT_DOUBLE_EQ(e.objective, 2.0 * 0.5 + 10.0 * (0.03 + 1.0) / 2 + 3.0 * 0.5);
  o.weight[kIncompleteRate] = 0.0;
  o.squares = true;
  ScoreEvaluation(o, &e);
  EXPECT_DOUBLE_EQ(e.objective, 2.0 * 0.5 + 10.0 * (0.03 * 0.03 + 1.0) / 2);
  Evaluation invalid;
  invalid.error = "bad";
  ScoreEvaluation(o, &invalid);
  EXPECT_EQ(invalid.objective, kInvalidObjective);
}

// incomplete_rate is 1 for a run whose outcome is not `completed` (here the stall watch ends
// the run when the tuned minimum advance is out of reach), 0 otherwise, whether or not the run
// passed its criteria; evaluations.csv holds its mean over the candidate's runs.
TEST_F(TuneTest, IncompleteRateCountsTheRunsThatDidNotComplete) {
  const std::string job =
      Job("algorithm = \"crs2\"\nseed = 3\n",
          "[[parameter]]\npath = \"criteria.stall_min_advance_m\"\nlower = 0.05\n"
          "upper = 5.0\n");
  TuneOptions options;
  options.out = (dir_ / "out").string();
  options.threads = 2;
  options.html = false;
  const TuneResult result = RunTune(LoadTuneJob(job), options);
  ASSERT_EQ(result.evaluations.size(), 6u);
  const CsvTable runs = CsvTable::Read((dir_ / "out" / "runs.csv").string());
  int completed = 0, incomplete = 0;
  for (size_t r = 0; r < runs.num_rows(); ++r) {
    const bool done = runs.Text(r, runs.Column("outcome")) == "completed";
    EXPECT_EQ(runs.Number(r, runs.Column("incomplete_rate")), done ? 0.0 : 1.0) << r;
    if (!done) {
      EXPECT_EQ(runs.Number(r, runs.Column("failure_rate")), 1.0) << r;
    }
    (done ? completed : incomplete) += 1;
  }
  EXPECT_GT(completed, 0);
  EXPECT_GT(incomplete, 0);
  const CsvTable log = CsvTable::Read((dir_ / "out" / "evaluations.csv").string());
  ASSERT_EQ(log.num_rows(), runs.num_rows());  // one run per candidate
  for (size_t r = 0; r < log.num_rows(); ++r) {
    EXPECT_EQ(log.Number(r, log.Column("incomplete_rate")),
              result.evaluations[r].terms[kIncompleteRate]);
  }
}

TEST_F(TuneTest, ThreadsDoNotChangeTheResultAndTheBestIsTheMinimum) {
  const TuneJob job = LoadTuneJob(Job());
  TuneOptions one, two;
  one.out = (dir_ / "one").string();
  one.threads = 1;
  one.html = false;
  two = one;
  two.out = (dir_ / "two").string();
  two.threads = 2;
  const TuneResult a = RunTune(job, one), b = RunTune(job, two);
  ASSERT_EQ(a.evaluations.size(), 6u);
  ASSERT_EQ(b.evaluations.size(), 6u);
  for (size_t i = 0; i < a.evaluations.size(); ++i) {
    EXPECT_EQ(a.evaluations[i].x, b.evaluations[i].x);
    EXPECT_EQ(a.evaluations[i].objective, b.evaluations[i].objective);
    EXPECT_LE(a.evaluations[a.best].objective, a.evaluations[i].objective);
  }
  EXPECT_EQ(a.evaluations[a.initial].x, (std::vector<double>{0.2, 0.1}));
  EXPECT_EQ(ReadText(dir_ / "one" / "best.toml"), ReadText(dir_ / "two" / "best.toml"));
  // The log holds what the result holds.
  const CsvTable log = CsvTable::Read((dir_ / "one" / "evaluations.csv").string());
  ASSERT_EQ(log.num_rows(), 6u);
  EXPECT_EQ(log.Number(3, log.Column("objective")), a.evaluations[3].objective);
  // Without --resume or --force an existing log is not touched.
  EXPECT_THROW(RunTune(job, one), InputError);
}

TEST_F(TuneTest, KilledJobResumesToTheSameResult) {
  const std::string job = Job();
  const std::string whole = (dir_ / "whole").string(), cut = (dir_ / "cut").string();
  ASSERT_EQ(RunCliCode("tune " + job + " -q --no-html --out " + whole), 0);
  // Killed (SIGKILL) after 3 evaluations, in the middle of writing the 4th row.
  const std::string command = "RABBIT_TUNE_KILL_AFTER=3 " + std::string(RABBIT_CLI_PATH) +
                              " tune " + job + " -q --no-html --out " + cut + " > /dev/null 2>&1";
  const int killed = std::system(command.c_str());
  EXPECT_TRUE(WIFSIGNALED(killed) || (WIFEXITED(killed) && WEXITSTATUS(killed) == 128 + SIGKILL))
      << killed;
  EXPECT_FALSE(fs::exists(fs::path(cut) / "best.toml"));
  const std::string partial = ReadText(fs::path(cut) / "evaluations.csv");
  EXPECT_NE(partial.back(), '\n');  // a row cut short
  std::string output;
  ASSERT_EQ(RunCliCode("tune " + job + " --no-html --resume --out " + cut, &output), 0) << output;
  EXPECT_NE(output.find("replayed   3 evaluations"), std::string::npos) << output;
  EXPECT_EQ(ReadText(fs::path(cut) / "best.toml"), ReadText(fs::path(whole) / "best.toml"));
  EXPECT_EQ(WithoutLastColumn(ReadText(fs::path(cut) / "evaluations.csv")),
            WithoutLastColumn(ReadText(fs::path(whole) / "evaluations.csv")));
  EXPECT_EQ(ReadText(fs::path(cut) / "runs.csv"), ReadText(fs::path(whole) / "runs.csv"));
  // A second resume replays everything and runs nothing.
  ASSERT_EQ(RunCliCode("tune " + job + " --no-html --resume --out " + cut, &output), 0);
  EXPECT_NE(output.find("replayed   6 evaluations"), std::string::npos) << output;
  // A changed job does not resume another's log.
  const std::string changed = Job("seed = 2\n");
  EXPECT_EQ(RunCliCode("tune " + changed + " --no-html --resume --out " + cut, &output), 2);
  EXPECT_NE(output.find("fingerprint"), std::string::npos) << output;
}

TEST_F(TuneTest, ResumeDropsTheRunsOfAFirstEvaluationWithoutItsRow) {
  // Killed after the first evaluation's runs reached runs.csv, before its row: the resumed log
  // must not hold those runs twice (a later resume would refuse it).
  const std::string job = Job();
  const std::string whole = (dir_ / "whole").string(), cut = (dir_ / "cut").string();
  ASSERT_EQ(RunCliCode("tune " + job + " -q --no-html --out " + whole), 0);
  ASSERT_EQ(RunCliCode("tune " + job + " -q --no-html --out " + cut), 0);
  for (const char* name : {"best.toml", "comparison.csv", "parameters.csv", "meta.csv"}) {
    fs::remove(fs::path(cut) / name);
  }
  std::istringstream evaluations(ReadText(fs::path(cut) / "evaluations.csv"));
  std::string header;
  std::getline(evaluations, header);
  std::ofstream(fs::path(cut) / "evaluations.csv") << header << "\n";
  std::istringstream runs(ReadText(fs::path(cut) / "runs.csv"));
  std::string runs_header, first_run;
  std::getline(runs, runs_header);
  std::getline(runs, first_run);  // evaluation 0's one run (ramp_up)
  ASSERT_EQ(first_run.rfind("0,", 0), 0u) << first_run;
  std::ofstream(fs::path(cut) / "runs.csv") << runs_header << "\n" << first_run << "\n";
  std::string output;
  ASSERT_EQ(RunCliCode("tune " + job + " --no-html --resume --out " + cut, &output), 0) << output;
  EXPECT_EQ(ReadText(fs::path(cut) / "runs.csv"), ReadText(fs::path(whole) / "runs.csv"));
  ASSERT_EQ(RunCliCode("tune " + job + " --no-html --resume --out " + cut, &output), 0) << output;
  EXPECT_NE(output.find("replayed   6 evaluations"), std::string::npos) << output;
  EXPECT_EQ(ReadText(fs::path(cut) / "best.toml"), ReadText(fs::path(whole) / "best.toml"));
}

TEST_F(TuneTest, ResumeWithSomeShardsMissingLogsInTheOrderOfOneRun) {
  // Only shard 2/2 has run: --resume runs search 0 and replays search 1, numbering and logging
  // both in request order, as one run does.
  const std::string job = Job("starts = 2\n");
  const std::string whole = (dir_ / "whole").string(), sharded = (dir_ / "sharded").string();
  ASSERT_EQ(RunCliCode("tune " + job + " -q --no-html --out " + whole), 0);
  ASSERT_EQ(RunCliCode("tune " + job + " -q --no-html --shard 2/2 --out " + sharded), 0);
  std::string output;
  ASSERT_EQ(RunCliCode("tune " + job + " --no-html --resume --out " + sharded, &output), 0)
      << output;
  EXPECT_NE(output.find("replayed   3 evaluations"), std::string::npos) << output;
  EXPECT_EQ(WithoutLastColumn(ReadText(fs::path(sharded) / "evaluations.csv")),
            WithoutLastColumn(ReadText(fs::path(whole) / "evaluations.csv")));
  EXPECT_EQ(ReadText(fs::path(sharded) / "runs.csv"), ReadText(fs::path(whole) / "runs.csv"));
  EXPECT_EQ(ReadText(fs::path(sharded) / "best.toml"), ReadText(fs::path(whole) / "best.toml"));
}

TEST_F(TuneTest, ShardsMergeToTheSameResult) {
  const std::string job = Job("starts = 2\n");
  const std::string whole = (dir_ / "whole").string(), sharded = (dir_ / "sharded").string();
  ASSERT_EQ(RunCliCode("tune " + job + " -q --no-html --out " + whole), 0);
  ASSERT_EQ(RunCliCode("tune " + job + " -q --no-html --shard 2/2 --out " + sharded), 0);
  ASSERT_EQ(RunCliCode("tune " + job + " -q --no-html --shard 1/2 --out " + sharded), 0);
  EXPECT_FALSE(fs::exists(fs::path(sharded) / "best.toml"));
  std::string output;
  ASSERT_EQ(RunCliCode("tune " + job + " --no-html --resume --out " + sharded, &output), 0)
      << output;
  EXPECT_NE(output.find("replayed   6 evaluations"), std::string::npos) << output;
  EXPECT_EQ(ReadText(fs::path(sharded) / "best.toml"), ReadText(fs::path(whole) / "best.toml"));
  EXPECT_EQ(WithoutLastColumn(ReadText(fs::path(sharded) / "evaluations.csv")),
            WithoutLastColumn(ReadText(fs::path(whole) / "evaluations.csv")));
}

TEST_F(TuneTest, BestTomlReproducesTheBestEvaluationInRabbitRun) {
  const std::string job = Job();
  const fs::path out = dir_ / "tune";
  ASSERT_EQ(RunCliCode("tune " + job + " -q --no-html --out " + out.string()), 0);
  // The suite with the job's base overlay and best.toml's values: rabbit run sees one overlay,
  // so merge them (best.toml holds the base's values too).
  const std::string best = ReadText(out / "best.toml");
  EXPECT_NE(best.find("\"simulation.duration\" = 12"), std::string::npos) << best;
  const fs::path report = dir_ / "report";
  ASSERT_EQ(
      RunCliCode("run " + kRoot + "/scenarios/tune_ramp.toml --filter '^ramp_up$' -q --no-html" +
                 " --params " + (out / "best.toml").string() + " --out " + report.string()),
      0);
  const CsvTable summary = CsvTable::Read((report / "summary.csv").string());
  const CsvTable meta = CsvTable::Read((out / "meta.csv").string());
  const CsvTable runs = CsvTable::Read((out / "runs.csv").string());
  int best_eval = -1;
  for (size_t r = 0; r < meta.num_rows(); ++r) {
    if (meta.Text(r, 0) == "best_eval") best_eval = std::stoi(meta.Text(r, 1));
  }
  ASSERT_GE(best_eval, 0);
  bool found = false;
  for (size_t r = 0; r < runs.num_rows(); ++r) {
    if (runs.Integer(r, 0) != best_eval) continue;
    found = true;
    // summary.csv writes 9 significant digits.
    EXPECT_NEAR(runs.Number(r, runs.Column("speed_error")),
                summary.Number(0, summary.Column("mean_abs_speed_error_m_s")), 1e-8);
  }
  EXPECT_TRUE(found);
}

TEST_F(TuneTest, InvalidCandidatesAreResultsNotCrashes) {
  // d_obs Small's peak beyond its right foot (0.3 m) is invalid: the initial point is.
  const TuneJob job = LoadTuneJob(
      Job("algorithm = \"sbplx\"\n",
          "[[parameter]]\npath = \"controller.sets.d_obs.Small.2\"\nlower = 0.0\nupper = 0.5\n"
          "initial = 0.45\n"));
  TuneOptions options;
  options.out = (dir_ / "out").string();
  options.html = false;
  const TuneResult r = RunTune(job, options);
  ASSERT_FALSE(r.evaluations.empty());
  const Evaluation& first = r.evaluations[r.initial];
  EXPECT_EQ(first.objective, kInvalidObjective);
  EXPECT_NE(first.error.find("Small"), std::string::npos) << first.error;
  EXPECT_EQ(first.runs, 0);
}

}  // namespace
}  // namespace rabbit
