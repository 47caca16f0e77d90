// Guard suites of tuning jobs (tune_guards.h, `guards = [...]`): a candidate that fails a
// required scenario of a guard suite is never the best (a constraint: the searches see the same
// objectives as without guards, so the best is the lowest objective among the candidates that keep
// the guards); the log says which candidates ran the guards and what they broke; the result does
// not depend on the number of threads; a killed guarded job resumes to the same log; a changed
// guard suite changes the fingerprint.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "cli_fixture.h"
#include "rabbit/io/csv_table.h"
#include "rabbit/io/error.h"
#include "tune_job.h"
#include "tuner.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

const std::string kRoot = RABBIT_SOURCE_DIR;

using testing::ReadText;
using testing::RunCliCode;
using testing::WithoutLastColumn;

class TuneGuardsTest : public testing::ScratchDirTest {
 protected:
  TuneGuardsTest() : ScratchDirTest("rabbit_tune_guards_test") {}
  void SetUp() override {
    ScratchDirTest::SetUp();
    // A short walker scenario: 12 s of the ramp up (about 15 steps), two gains.
    Write("base.toml", "[params]\n\"simulation.duration\" = 12\n\"criteria.min_steps\" = 5\n");
  }
  // A guard suite of one required scenario: the tuning scenario itself (ramp_up with
  // tune_ramp.toml's walker, under the job's base overlay, so its runs are the objective's runs)
  // with `criteria` added; and an optional scenario that always fails (optional scenarios never
  // break a guard).
  std::string Guard(const std::string& criteria, const std::string& name = "guard") {
    return Write(name + ".toml",
                 "[suite]\nname = \"" + name +
                     "\"\n[defaults]\nexpect_outcome = \"completed\"\nseed = 1\n"
                     "[defaults.simulation]\nduration = 36.0\nrecord_every = 10\n"
                     "[defaults.controller]\ntype = \"fuzzy_cmac\"\ndatabase = \"" +
                     kRoot +
                     "/gaits\"\npreset = \"chapter\"\nwarmup_steps = 6\nk_p = 0.2\nk_v = 0.10\n"
                     "[[scenario]]\nname = \"ramp_up\"\n[scenario.criteria]\n" +
                     criteria +
                     "\n[scenario.velocity]\nprofile = \"steps\"\n"
                     "points = [[0, 0.4], [6, 0.5], [12, 0.6], [18, 0.7], [24, 0.8]]\n"
                     "[[scenario]]\nname = \"never\"\nrequired = false\n[scenario.criteria]\n"
                     "min_distance_m = 1000\n[scenario.velocity]\nprofile = \"steps\"\n"
                     "points = [[0, 0.4]]\n");
  }
  // The tuning test's small job, with `guards` (TOML array text, or "" for none).
  std::string Job(const std::string& guards, const std::string& name = "job.toml") {
    return Write(name, "[job]\nsuites = [\"" + kRoot +
                           "/scenarios/tune_ramp.toml\"]\nfilter = \"^ramp_up$\"\n"
                           "params = \"base.toml\"\nmax_evaluations = 6\n" +
                           (guards.empty() ? "" : "guards = " + guards + "\n") +
                           "[objective]\nspeed_error = 1.0\nfailure_rate = 0.2\n"
                           "[[parameter]]\npath = \"controller.k_p\"\nlower = 0.0\nupper = 0.6\n"
                           "[[parameter]]\npath = \"controller.k_v\"\nlower = 0.0\nupper = 0.4\n");
  }
  TuneResult Run(const std::string& job, const std::string& out, int threads = 2) {
    TuneOptions options;
    options.out = (dir_ / out).string();
    options.threads = threads;
    options.html = false;
    return RunTune(LoadTuneJob(job), options);
  }
};

TEST_F(TuneGuardsTest, ABrokenGuardIsNeverTheBest) {
  const TuneResult free = Run(Job(""), "free");
  ASSERT_EQ(free.evaluations.size(), 6u);
  ASSERT_GE(free.best, 0);
  // A guard whose L_step spread bound the unguarded best just misses: the best breaks it.
  double best_spread = std::numeric_limits<double>::quiet_NaN();
  for (const RunScore& s : free.evaluations[free.best].scores)
    best_spread = s.value[kStepLengthSpread];
  ASSERT_TRUE(std::isfinite(best_spread));
  const double bound = best_spread * (1.0 - 1e-9);
  char criteria[64];
  std::snprintf(criteria, sizeof criteria, "max_l_step_spread_m = %.17g", bound);
  const std::string guard = Guard(criteria);
  const TuneResult guarded = Run(Job("[\"guard.toml\"]"), "guarded");
  ASSERT_EQ(guarded.evaluations.size(), 6u);
  // The searches saw the same objectives: the same candidates in the same order.
  double expected = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < 6; ++i) {
    const Evaluation& a = free.evaluations[i];
    const Evaluation& b = guarded.evaluations[i];
    EXPECT_EQ(a.x, b.x) << i;
    EXPECT_EQ(a.objective, b.objective) << i;
    // Independent of the tuner: a candidate keeps the guard when its (identical) run passed and
    // its spread is within the bound.
    const RunScore& s = a.scores.at(0);
    const bool keeps = s.passed && s.value[kStepLengthSpread] <= bound;
    if (keeps) expected = std::min(expected, a.objective);
    if (b.guards_run) {
      EXPECT_EQ(b.guard_broken.empty(), keeps) << i << ": " << b.guard_broken;
      if (!keeps) {
        EXPECT_EQ(b.guard_broken, "guard/ramp_up") << i;  // not the optional one
      }
    }
  }
  const Evaluation& first = guarded.evaluations[free.best];
  EXPECT_TRUE(first.guards_run);  // the unguarded best beat every earlier candidate
  EXPECT_EQ(first.guard_broken, "guard/ramp_up");
  EXPECT_TRUE(guarded.evaluations[0].guards_run);  // the first candidate of a search always runs
  if (std::isfinite(expected)) {
    ASSERT_GE(guarded.best, 0);
    EXPECT_NE(guarded.best, free.best);
    EXPECT_EQ(guarded.evaluations[guarded.best].objective, expected);
    EXPECT_TRUE(EligibleAsBest(LoadTuneJob(dir_ / "job.toml"), guarded.evaluations[guarded.best]));
  } else {
    EXPECT_EQ(guarded.best, -1);
    EXPECT_FALSE(fs::exists(dir_ / "guarded" / "best.toml"));
  }
  // The log records it.
  const CsvTable log = CsvTable::Read((dir_ / "guarded" / "evaluations.csv").string());
  EXPECT_EQ(log.Integer(free.best, log.Column("guards_run")), 1);
  EXPECT_EQ(log.Text(free.best, log.Column("guard_broken")), "guard/ramp_up");
}

TEST_F(TuneGuardsTest, NoCandidateKeepsAnImpossibleGuard) {
  Guard("min_distance_m = 1000");  // (min_steps: the base overlay sets it)
  std::string output;
  const std::string out = (dir_ / "out").string();
  // No result: exit 1, with the reason, also under -q.
  ASSERT_EQ(RunCliCode("tune " + Job("[\"guard.toml\"]") + " -q --out " + out + " -j 2", &output),
            1)
      << output;
  EXPECT_NE(output.find("no candidate kept the required scenarios of the guard suites passing "
                        "(6 broke a guard, 0 invalid)"),
            std::string::npos)
      << output;
  EXPECT_FALSE(fs::exists(fs::path(out) / "best.toml"));
  // Every valid candidate beats the best eligible objective (none): each ran the guards.
  const CsvTable log = CsvTable::Read(out + "/evaluations.csv");
  ASSERT_EQ(log.num_rows(), 6u);
  for (size_t r = 0; r < log.num_rows(); ++r) {
    EXPECT_EQ(log.Integer(r, log.Column("guards_run")), 1) << r;
    EXPECT_EQ(log.Text(r, log.Column("guard_broken")), "guard/ramp_up") << r;
  }
  // The page says so, and lists the candidates that broke a guard.
  const std::string page = ReadText(fs::path(out) / "index.html");
  EXPECT_NE(page.find("no candidate kept them"), std::string::npos);
  EXPECT_NE(page.find("<tr class=\"guard\"><td><a href=\"#eval-5\">5</a>"), std::string::npos);
}

// A guarded job whose every candidate is invalid (an rtol the simulator refuses) never reaches
// the guards: exit 1, and the message counts them as invalid, not as guard breakers.
TEST_F(TuneGuardsTest, AJobOfInvalidCandidatesSaysSo) {
  const std::string job =
      Write("invalid.toml", "[job]\nsuites = [\"" + kRoot +
                                "/scenarios/tune_ramp.toml\"]\nfilter = \"^ramp_up$\"\n"
                                "params = \"base.toml\"\nmax_evaluations = 3\nalgorithm = "
                                "\"sbplx\"\nguards = [\"" +
                                Guard("min_steps = 5") +
                                "\"]\n[objective]\nspeed_error = 1.0\n[[parameter]]\npath = "
                                "\"simulation.rtol\"\nlower = -1\nupper = -0.1\ninitial = -0.5\n");
  std::string output;
  const std::string out = (dir_ / "out").string();
  ASSERT_EQ(RunCliCode("tune " + job + " -q --out " + out, &output), 1) << output;
  EXPECT_NE(output.find("(0 broke a guard, 3 invalid)"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(fs::path(out) / "best.toml"));
  const CsvTable log = CsvTable::Read(out + "/evaluations.csv");
  ASSERT_EQ(log.num_rows(), 3u);
  for (size_t r = 0; r < log.num_rows(); ++r) {
    EXPECT_EQ(log.Integer(r, log.Column("guards_run")), 0) << r;
    EXPECT_NE(log.Text(r, log.Column("error")).find("rtol must be in (0, 1)"), std::string::npos);
  }
}

// A bound some candidates keep and some break (their L_step spreads run from 0.047 to 0.067 m).
constexpr double kMidBound = 0.055;
const std::string kMidGuard = "max_l_step_spread_m = " + std::to_string(kMidBound);

TEST_F(TuneGuardsTest, ThreadsDoNotChangeTheGuardedLog) {
  Guard(kMidGuard);
  const std::string job = Job("[\"guard.toml\"]");
  const TuneResult a = Run(job, "one", 1), b = Run(job, "two", 2);
  ASSERT_GE(a.best, 0);
  EXPECT_EQ(a.best, b.best);
  EXPECT_EQ(WithoutLastColumn(ReadText(dir_ / "one" / "evaluations.csv")),
            WithoutLastColumn(ReadText(dir_ / "two" / "evaluations.csv")));
  EXPECT_EQ(ReadText(dir_ / "one" / "runs.csv"), ReadText(dir_ / "two" / "runs.csv"));
  // Independent of the tuner's verdicts: a candidate keeps the bound when its (identical) run
  // passed within it, and the best is the lowest objective of those that ran the guards and kept
  // them. (ABrokenGuardIsNeverTheBest's bound, today, no candidate keeps.)
  int kept = 0, broken = 0;
  double expected = std::numeric_limits<double>::infinity();
  for (const Evaluation& e : a.evaluations) {
    if (!e.guards_run) continue;
    const RunScore& s = e.scores.at(0);
    const bool keeps = s.passed && s.value[kStepLengthSpread] <= kMidBound;
    EXPECT_EQ(e.guard_broken.empty(), keeps) << e.index << ": " << e.guard_broken;
    (keeps ? kept : broken) += 1;
    if (keeps) expected = std::min(expected, e.objective);
  }
  EXPECT_GE(kept, 1);
  EXPECT_GE(broken, 1);
  EXPECT_EQ(a.evaluations[a.best].objective, expected);
}

TEST_F(TuneGuardsTest, AKilledGuardedJobResumesToTheSameLog) {
  Guard(kMidGuard);
  const std::string job = Job("[\"guard.toml\"]");
  const std::string whole = (dir_ / "whole").string(), cut = (dir_ / "cut").string();
  ASSERT_EQ(RunCliCode("tune " + job + " -q --no-html --out " + whole), 0);
  const std::string command = "RABBIT_TUNE_KILL_AFTER=3 " + std::string(RABBIT_CLI_PATH) +
                              " tune " + job + " -q --no-html --out " + cut + " > /dev/null 2>&1";
  const int killed = std::system(command.c_str());
  EXPECT_TRUE(WIFSIGNALED(killed) || (WIFEXITED(killed) && WEXITSTATUS(killed) == 128 + SIGKILL))
      << killed;
  std::string output;
  ASSERT_EQ(RunCliCode("tune " + job + " --no-html --resume --out " + cut, &output), 0) << output;
  EXPECT_NE(output.find("replayed   3 evaluations"), std::string::npos) << output;
  EXPECT_EQ(WithoutLastColumn(ReadText(fs::path(cut) / "evaluations.csv")),
            WithoutLastColumn(ReadText(fs::path(whole) / "evaluations.csv")));
  ASSERT_TRUE(fs::exists(fs::path(whole) / "best.toml"));
  EXPECT_EQ(ReadText(fs::path(cut) / "best.toml"), ReadText(fs::path(whole) / "best.toml"));
  // A changed guard suite is another job: its fingerprint differs, the log is not resumed.
  Guard("max_l_step_spread_m = 0.03");
  EXPECT_EQ(RunCliCode("tune " + job + " --no-html --resume --out " + cut, &output), 2);
  EXPECT_NE(output.find("fingerprint"), std::string::npos) << output;
}

TEST_F(TuneGuardsTest, BadGuardsAreInputErrors) {
  auto expect_error = [&](const std::string& guards, const std::string& fragment) {
    try {
      LoadTuneJob(Job(guards));
      ADD_FAILURE() << "no error for " << guards;
    } catch (const InputError& e) {
      EXPECT_EQ(e.key().rfind("job.guards", 0), 0u) << e.what();
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  expect_error("[\"\"]", "an empty path");
  std::string optional = ReadText(Guard("min_steps = 1", "optional"));
  optional.replace(optional.find("name = \"ramp_up\""), 16, "name = \"ramp_up\"\nrequired = false");
  Write("optional.toml", optional);
  expect_error("[\"optional.toml\"]", "no required scenario");
  Guard("min_steps = 1", "twice");
  expect_error("[\"twice.toml\", \"twice.toml\"]", "two guard suites named");
  // A missing guard suite names its file.
  EXPECT_THROW(LoadTuneJob(Job("[\"missing.toml\"]")), InputError);
}

}  // namespace
}  // namespace rabbit
