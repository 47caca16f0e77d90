// Batch runs: the same summary whatever the number of threads; pass criteria on hand-built runs;
// metrics against independent figures; and the paper suite's claims:
// (a) V_M follows V_d up to 1.0 m/s and L_step rises from about 0.25 to above 0.45 m, (b) flat
// walking with a nearly constant L_step, (c) the step before the obstacle shortens, the next
// lengthens and clears it, and walking goes on.
#include "rabbit/scenario/run.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "rabbit/scenario/batch.h"
#include "rabbit/scenario/run_files.h"
#include "rabbit/scenario/suite.h"

namespace rabbit {
namespace {

const std::string kRoot = RABBIT_SOURCE_DIR;

// The summary rows of a batch without the wall-time columns.
std::vector<std::string> DeterministicRows(const Suite& suite, const std::string& filter,
                                           int threads, std::vector<RunOutput>* runs = nullptr) {
  const std::vector<BatchJob> jobs = PlanBatch(suite, filter);
  std::vector<std::string> rows(jobs.size());
  if (runs != nullptr) runs->resize(jobs.size());
  RunBatch(jobs, threads, nullptr, [&](size_t i, RunOutput&& run) {
    run.wall = 0.0;  // the only non-deterministic figure
    rows[i] = SummaryRow(suite.name, run);
    if (runs != nullptr) (*runs)[i] = std::move(run);
  });
  return rows;
}

class PaperSuiteTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    suite_ = new Suite(LoadSuite(kRoot + "/scenarios/paper.toml"));
    runs_ = new std::vector<RunOutput>();
    rows_ = new std::vector<std::string>(
        DeterministicRows(*suite_, "^(ramp|flat|obstacle)$", 2, runs_));
  }
  static void TearDownTestSuite() {
    delete suite_;
    delete runs_;
    delete rows_;
  }
  static const RunOutput& Run(const std::string& name) {
    for (const RunOutput& r : *runs_) {
      if (r.run == name) return r;
    }
    throw std::runtime_error("no run " + name);
  }
  static Suite* suite_;
  static std::vector<RunOutput>* runs_;
  static std::vector<std::string>* rows_;
};
Suite* PaperSuiteTest::suite_ = nullptr;
std::vector<RunOutput>* PaperSuiteTest::runs_ = nullptr;
std::vector<std::string>* PaperSuiteTest::rows_ = nullptr;

TEST_F(PaperSuiteTest, SameSummaryOnOneThread) {
  EXPECT_EQ(DeterministicRows(*suite_, "^(ramp|flat|obstacle)$", 1), *rows_);
}

TEST_F(PaperSuiteTest, RampFollowsTheDesiredVelocity) {
  const RunOutput& r = Run("ramp");
  EXPECT_TRUE(r.passed) << (r.failures.empty() ? "" : r.failures[0]);
  EXPECT_EQ(r.sim.outcome, Outcome::kCompleted);
  // L_step: about 0.25 m at 0.4 m/s (the first steps of the walker), about 0.43 m at 0.8 m/s and
  // above 0.45 m at 1.0 m/s; at the end of the 1.0 m/s level the stride V_M is within 0.05 m/s.
  double early = 0.0, at_08 = 0.0;
  int n_early = 0, n_08 = 0;
  std::vector<const StepRow*> top;
  for (const StepRow& s : r.steps) {
    if (s.step.t_step <= 0.0) continue;
    if (s.v_d < 0.45 && s.step.t_touchdown > 4.0) {
      early += s.step.l_step;
      ++n_early;
    }
    if (std::abs(s.v_d - 0.8) < 1e-9 && s.step.t_touchdown > 36.0) {
      at_08 += s.step.l_step;
      ++n_08;
    }
    if (s.v_d >= 1.0) top.push_back(&s);
  }
  ASSERT_GT(n_early, 3);
  ASSERT_GT(n_08, 3);
  ASSERT_GT(top.size(), 12u);
  const double kStepTolerance = 0.03;  // m: "about"
  EXPECT_NEAR(early / n_early, 0.25, kStepTolerance);
  EXPECT_NEAR(at_08 / n_08, 0.43, kStepTolerance);
  const double kSpeedTolerance = 0.05;  // m/s, the ramp's criterion
  for (size_t i = top.size() - 10; i < top.size(); ++i) {
    EXPECT_GT(top[i]->step.l_step, 0.45) << "step at t = " << top[i]->step.t_touchdown;
    const double stride = 0.5 * (top[i]->step.v_m + top[i - 1]->step.v_m);
    EXPECT_NEAR(stride, 1.0, kSpeedTolerance) << "step at t = " << top[i]->step.t_touchdown;
  }
}

TEST_F(PaperSuiteTest, FlatWalkingHasANearlyConstantStep) {
  const RunOutput& r = Run("flat");
  EXPECT_TRUE(r.passed) << (r.failures.empty() ? "" : r.failures[0]);
  EXPECT_GE(r.metrics.steps, 20);
  EXPECT_LT(r.metrics.l_step_spread, 0.01);
}

TEST_F(PaperSuiteTest, ObstacleIsSteppedOverAsInFigure16) {
  const RunOutput& r = Run("obstacle");
  EXPECT_TRUE(r.passed) << (r.failures.empty() ? "" : r.failures[0]);
  const Obstacle& o = suite_->scenarios[2].terrain.obstacles.at(0);
  // The last landing before the obstacle and the first beyond it.
  size_t before = 0;
  while (before + 1 < r.steps.size() && r.steps[before + 1].step.x < o.x_start) ++before;
  ASSERT_LT(before + 1, r.steps.size());
  const StepRow& short_step = r.steps[before];
  const StepRow& long_step = r.steps[before + 1];
  const double flat = Run("flat").metrics.l_step_mean;
  // The step planner (on by default) plans the approach from 1.5 m out, so the last step before
  // the obstacle need not be shorter than the flat walk's (Table 3 alone shortens it to 0.318 m);
  // it lands just before the obstacle.
  EXPECT_LT(short_step.step.l_step, flat + 0.02);
  EXPECT_LT(o.x_start - short_step.step.x, 0.10);
  EXPECT_GT(long_step.step.l_step, flat + 0.03);  // lengthened...
  EXPECT_GT(long_step.step.x, o.x_end());         // ...to land beyond it
  int after = 0;
  for (const StepRow& s : r.steps) after += s.step.x > o.x_end() ? 1 : 0;
  EXPECT_GE(after, 10);
  // No foot ever stood on the obstacle.
  for (const ContactEvent& e : r.sim.events) {
    if (e.from == ContactMode::kAir && e.to != ContactMode::kAir) {
      EXPECT_FALSE(e.x >= o.x_start && e.x <= o.x_end() && e.y > 0.02) << "landing at " << e.t;
    }
  }
}

TEST_F(PaperSuiteTest, TheChaptersControlBeatsItsBaselines) {
  // The pragmatic rules at the start gait do not follow V_d and trip on the obstacle.
  EXPECT_FALSE(Run("ramp+pragmatic").passed);
  EXPECT_GT(Run("ramp+pragmatic").metrics.mean_abs_speed_error,
            2.0 * Run("ramp").metrics.mean_abs_speed_error);
  EXPECT_EQ(Run("obstacle+pragmatic").sim.outcome, Outcome::kTripped);
}

TEST_F(PaperSuiteTest, PatternMemoryIsTheWalkersGaitPatternAndNoneForThePragmaticRules) {
  const std::size_t bytes = LoadGaitLibrary(suite_->scenarios[1].pattern)->pattern.MemoryBytes();
  EXPECT_GT(bytes, 0u);
  EXPECT_EQ(Run("flat").metrics.pattern_memory_bytes, bytes);
  EXPECT_EQ(Run("flat+nearest_gait").metrics.pattern_memory_bytes, bytes);
  EXPECT_EQ(Run("flat+pragmatic").metrics.pattern_memory_bytes, 0u);
  // In summary.csv before the family (none: a plain scenario) and the wall-time columns.
  const std::string row = SummaryRow(suite_->name, Run("flat"));
  EXPECT_NE(row.find("," + std::to_string(bytes) + ",,0,"), std::string::npos) << row;
  EXPECT_NE(SummaryHeader().find(",pattern_memory_bytes,family,wall_s,real_time_factor"),
            std::string::npos);
}

TEST(MultiCmacBaselineTest, RunsTheWalkerOnTheTrainedPattern) {
  const Suite suite = LoadSuite(kRoot + "/scenarios/paper.toml");
  Scenario s = suite.scenarios[1];  // flat
  ASSERT_EQ(s.name, "flat");
  s.options.duration = 8.0;
  const std::shared_ptr<const GaitLibrary> library = LoadGaitLibrary(s.pattern);
  const RunOutput r = RunScenario(s, "multi_cmac", library.get());
  EXPECT_EQ(r.run, "flat+multi_cmac");
  EXPECT_EQ(r.controller, "multi_cmac");
  EXPECT_EQ(r.sim.outcome, Outcome::kCompleted);
  EXPECT_EQ(r.metrics.pattern_memory_bytes, 4u * (1u << 16) * sizeof(double));
  ASSERT_GT(r.steps.size(), 7u);  // past the six warm-up steps
  for (const StepRow& step : r.steps) {
    ASSERT_EQ(step.weights.size(), library->gait_names.size());
    for (double w : step.weights) EXPECT_TRUE(std::isnan(w));
    EXPECT_EQ(step.rules, "");
  }
  // Trained once for the library: a second run reuses the pattern.
  EXPECT_EQ(library->multi_cmac->trainings(), 1);
  EXPECT_EQ(MultiCmacBaseline(s, *library), MultiCmacBaseline(s, *library));
  EXPECT_EQ(library->multi_cmac->trainings(), 1);
  // The walker's own swing references came from it (tracked after the warm-up).
  int tracked = 0;
  for (const WalkerTrack& t : r.tracking) tracked += std::isfinite(t.hip_ref) ? 1 : 0;
  EXPECT_GT(tracked, 0);
}

// The batch starts the first multi_cmac run first (its training begins at once), then every run
// that needs no trained pattern, then the other multi_cmac runs; every job exactly once.
TEST(ExecutionOrderTest, TheFirstTrainingStartsAtOnceAndTheOthersWaitForTheEnd) {
  Scenario s;
  const std::vector<std::string> variants = {"fuzzy_cmac",  "nearest_gait", "multi_cmac",
                                             "pragmatic",   "fuzzy_cmac",   "multi_cmac",
                                             "nearest_gait"};
  std::vector<BatchJob> jobs;
  for (const std::string& v : variants) jobs.push_back({&s, v});
  EXPECT_EQ(ExecutionOrder(jobs), (std::vector<size_t>{2, 0, 1, 3, 4, 6, 5}));
  // Without multi_cmac runs the order is the jobs' own.
  jobs = {{&s, "fuzzy_cmac"}, {&s, "pragmatic"}, {&s, "nearest_gait"}};
  EXPECT_EQ(ExecutionOrder(jobs), (std::vector<size_t>{0, 1, 2}));
  EXPECT_TRUE(ExecutionOrder({}).empty());
}

// The walker holds each reference gait's velocity, 0.3 to 1.0 m/s, from that gait's start
// (scenarios/reference_walks.toml: 20 s, stride V_M within 0.05 m/s from 10 steps on).
TEST(ReferenceWalksTest, TheWalkerWalksEveryReferenceGaitAtItsVelocity) {
  const Suite suite = LoadSuite(kRoot + "/scenarios/reference_walks.toml");
  ASSERT_EQ(suite.scenarios.size(), 8u);
  std::vector<RunOutput> runs;
  DeterministicRows(suite, "", 2, &runs);
  int walker_runs = 0;
  for (const RunOutput& r : runs) {
    if (r.variant != "fuzzy_cmac") continue;
    ++walker_runs;
    EXPECT_TRUE(r.passed) << r.run << ": " << (r.failures.empty() ? "" : r.failures[0]);
    EXPECT_EQ(r.sim.outcome, Outcome::kCompleted) << r.run;
    EXPECT_GE(r.metrics.steps, 20) << r.run;
  }
  EXPECT_EQ(walker_runs, 8);
}

TEST(RunMetricsTest, EnergyAndCostOfTransport) {
  // 10 s of a pragmatic walk: CoT = positive actuator work / (m g distance), and the work equals
  // the sum over the recorded samples (every period) of max(0, tau qd) dt.
  Scenario s = LoadScenario(kRoot + "/scenarios/walk_pragmatic_0.60.toml");
  s.options.duration = 10.0;
  const RunOutput r = RunScenario(s, "pragmatic", nullptr);
  double work = 0.0;
  for (size_t k = 0; k + 1 < r.sim.samples.size(); ++k) {
    const SimSample& x = r.sim.samples[k];
    for (int j = 0; j < kNumJoints; ++j) {
      work += std::max(0.0, x.tau[j] * x.qd[3 + j]) * s.options.control_period;
    }
  }
  const double kTolerance = 1e-9;
  EXPECT_NEAR(r.metrics.energy, work, kTolerance * work);
  const Model model(s.model);
  EXPECT_NEAR(r.metrics.cost_of_transport, work / (model.total_mass() * 9.81 * r.metrics.distance),
              1e-12);
  EXPECT_GT(r.metrics.distance, 4.0);
  EXPECT_GT(r.metrics.steps, 10);
}

TEST(RunMetricsTest, DistanceIsTravelAndRunningOutOfTimeFails) {
  // Standing (pd_hold) from x = 3 m with distance = 1 m: the robot never travels 1 m, so the run
  // lasts its whole time limit and fails; it must not stop at once because x >= 1.
  Scenario s = LoadScenario(kRoot + "/scenarios/standing_pd_hold.toml");
  s.q0[kX] += 3.0;
  s.options.duration = 1.0;
  s.options.stop_distance = 1.0;
  RunOutput r = RunScenario(s, ScenarioVariants(s).front(), nullptr);
  EXPECT_EQ(r.sim.outcome, Outcome::kCompleted);
  EXPECT_NEAR(r.sim.t_end, 1.0, 1e-9);
  EXPECT_FALSE(r.passed);
  ASSERT_FALSE(r.failures.empty());
  EXPECT_NE(r.failures.back().find("before the time limit"), std::string::npos) << r.failures[0];
}

TEST(RunMetricsTest, NoVelocityProfileNoSpeedError) {
  // A pragmatic walk names no V_d: the steps carry none and no speed error is invented.
  Scenario s = LoadScenario(kRoot + "/scenarios/walk_pragmatic_0.60.toml");
  s.options.duration = 4.0;
  ASSERT_FALSE(s.has_velocity);
  const RunOutput r = RunScenario(s, "pragmatic", nullptr);
  ASSERT_GT(r.steps.size(), 3u);
  EXPECT_TRUE(std::isnan(r.steps[2].v_d));
  EXPECT_TRUE(std::isnan(r.metrics.mean_abs_speed_error));
}

// A run with hand-made steps for the criteria.
RunOutput HandRun(const std::vector<std::pair<double, double>>& vd_vm) {
  RunOutput r;
  r.metrics.steps = static_cast<int>(vd_vm.size());
  for (size_t i = 0; i < vd_vm.size(); ++i) {
    StepRow s;
    s.step.index = static_cast<int>(i);
    s.step.t_touchdown = 0.5 * static_cast<double>(i);
    s.step.t_step = 0.5;
    s.step.v_m = vd_vm[i].second;
    s.step.l_step = 0.3;
    s.step.x = 0.3 * static_cast<double>(i);
    s.v_d = vd_vm[i].first;
    r.steps.push_back(s);
  }
  return r;
}

TEST(CriteriaTest, TrackingIsCheckedOnSettledStridesUpToTheLimit) {
  Scenario s;
  s.criteria.speed_tolerance = 0.05;
  s.criteria.settle_steps = 3;
  s.criteria.track_up_to = 0.8;
  // V_d 0.5 for 6 steps then 0.9. Step i is settled when steps i-3..i-1 saw its V_d: steps 3-5
  // (V_d 0.5) and 9 (V_d 0.9 > 0.8: not checked). Strides: (0.50 + 0.52) / 2, (0.52 + 0.48) / 2,
  // (0.48 + 0.51) / 2, all within 0.05 of 0.5.
  std::vector<std::pair<double, double>> steps = {{0.5, 0.1},  {0.5, 0.2},  {0.5, 0.5}, {0.5, 0.52},
                                                  {0.5, 0.48}, {0.5, 0.51}, {0.9, 0.5}, {0.9, 0.5},
                                                  {0.9, 0.5},  {0.9, 0.5}};
  RunOutput good = HandRun(steps);
  EvaluateCriteria(s, &good);
  EXPECT_TRUE(good.passed) << (good.failures.empty() ? "" : good.failures[0]);
  steps[4].second = 0.35;  // strides of steps 4 and 5 now 0.435 and 0.43: off by > 0.05
  RunOutput bad = HandRun(steps);
  EvaluateCriteria(s, &bad);
  EXPECT_FALSE(bad.passed);
  ASSERT_EQ(bad.failures.size(), 1u);
  EXPECT_NE(bad.failures[0].find("at 2 of 3 settled steps"), std::string::npos) << bad.failures[0];
  s.criteria.settle_steps = 20;  // nothing is ever settled: that is a failure, not a pass
  RunOutput none = HandRun(steps);
  EvaluateCriteria(s, &none);
  EXPECT_FALSE(none.passed);
}

TEST(CriteriaTest, FinalStepLengthIsTheMeanOfTheLastSteps) {
  Scenario s;
  s.criteria.min_l_step = 0.45;
  s.criteria.spread_steps = 3;
  RunOutput r = HandRun({{1.0, 1.0}, {1.0, 1.0}, {1.0, 1.0}, {1.0, 1.0}, {1.0, 1.0}});
  for (StepRow& row : r.steps) row.step.l_step = 0.46;
  r.steps[0].step.l_step = 0.30;  // before the last three: not counted
  EvaluateCriteria(s, &r);
  EXPECT_TRUE(r.passed) << (r.failures.empty() ? "" : r.failures[0]);
  r.steps[3].step.l_step = 0.40;  // last three: mean 0.44 < 0.45
  r.failures.clear();
  EvaluateCriteria(s, &r);
  EXPECT_FALSE(r.passed);
  ASSERT_EQ(r.failures.size(), 1u);
  EXPECT_NE(r.failures[0].find("mean L_step 0.440 m"), std::string::npos) << r.failures[0];
}

TEST(CriteriaTest, StepsSpreadOutcomeAndObstacles) {
  Scenario s;
  s.expected_outcome = "completed";
  s.criteria.min_steps = 5;
  s.criteria.max_l_step_spread = 0.01;
  s.criteria.spread_steps = 3;
  s.criteria.min_steps_after_obstacles = 2;
  s.terrain.obstacles = {{1.0, 0.2, 0.05}};
  RunOutput r = HandRun({{0.6, 0.6}, {0.6, 0.6}, {0.6, 0.6}, {0.6, 0.6}, {0.6, 0.6}, {0.6, 0.6}});
  r.steps[4].step.l_step = 0.32;  // inside the last three: spread 0.02
  r.sim.outcome = Outcome::kFell;
  r.metrics = ComputeMetrics(s, Model(s.model), r.sim, r.steps);
  EvaluateCriteria(s, &r);
  // Fell, spread 0.02 > 0.01, and only step 5 (x = 1.5) lands beyond the obstacle's 1.2 m end.
  ASSERT_EQ(r.failures.size(), 3u);
  EXPECT_NE(r.failures[0].find("outcome fell"), std::string::npos);
  EXPECT_NE(r.failures[1].find("spread"), std::string::npos);
  EXPECT_NE(r.failures[2].find("1 steps beyond"), std::string::npos);
}

TEST(CriteriaTest, VelocityIntegralIsExactForEveryProfileKind) {
  const double kTolerance = 1e-12;
  VelocityProfile constant;
  constant.points = {{0.0, 0.6}};
  EXPECT_NEAR(VelocityIntegral(constant, 30.0), 18.0, kTolerance);
  VelocityProfile steps;
  steps.kind = VelocityProfile::Kind::kSteps;
  steps.points = {{0.0, 0.4}, {8.0, 0.5}, {16.0, 0.6}};
  // 8 s at 0.4, 8 s at 0.5, 4 s at 0.6.
  EXPECT_NEAR(VelocityIntegral(steps, 20.0), 3.2 + 4.0 + 2.4, kTolerance);
  VelocityProfile ramp;
  ramp.kind = VelocityProfile::Kind::kRamp;
  ramp.points = {{2.0, 0.4}, {6.0, 0.8}};
  // 2 s at 0.4, the trapezoid 4 s x 0.6 m/s mean, then 4 s at 0.8; cut at 8 s: 2 s of the last.
  EXPECT_NEAR(VelocityIntegral(ramp, 8.0), 0.8 + 2.4 + 1.6, kTolerance);
  EXPECT_NEAR(VelocityIntegral(ramp, 4.0), 0.8 + 0.5 * (0.4 + 0.6) * 2.0, kTolerance);
  EXPECT_EQ(VelocityIntegral(ramp, 0.0), 0.0);
}

TEST(CriteriaTest, AWalkerMustTravelForwardMostOfWhatVdAsks) {
  Scenario s;
  s.controller = ControllerKind::kFuzzyCmac;
  s.has_velocity = true;
  s.velocity.points = {{0.0, 0.6}};  // 6 m in 10 s; the default asks for 70 %: 4.2 m
  ASSERT_DOUBLE_EQ(s.criteria.min_travel_ratio, 0.7);
  RunOutput forward;
  forward.sim.t_end = 10.0;
  forward.metrics.distance = 4.3;
  EvaluateCriteria(s, &forward);
  EXPECT_TRUE(forward.passed) << (forward.failures.empty() ? "" : forward.failures[0]);
  RunOutput slow = forward;
  slow.metrics.distance = 4.1;
  EvaluateCriteria(s, &slow);
  EXPECT_FALSE(slow.passed);
  // Walking backward: long steps recorded as negative, the hip 1.5 m behind its start.
  RunOutput backward = HandRun({{0.6, -0.8}, {0.6, -0.8}, {0.6, -0.8}});
  for (StepRow& row : backward.steps) row.step.l_step = -0.4;
  backward.sim.t_end = 10.0;
  backward.metrics.distance = -1.5;
  EvaluateCriteria(s, &backward);
  EXPECT_FALSE(backward.passed);
  ASSERT_EQ(backward.failures.size(), 1u);
  EXPECT_NE(backward.failures[0].find("hip travelled -1.50 m forward"), std::string::npos)
      << backward.failures[0];
  EXPECT_NE(backward.failures[0].find("min_travel_ratio"), std::string::npos);
  // A scenario may ask for another share, or none; a standing controller is not checked.
  s.criteria.min_travel_ratio = 0.0;
  RunOutput unchecked = backward;
  unchecked.failures.clear();
  EvaluateCriteria(s, &unchecked);
  EXPECT_TRUE(unchecked.passed);
  s.criteria.min_travel_ratio = 0.7;
  s.controller = ControllerKind::kPdHold;
  RunOutput standing = backward;
  standing.failures.clear();
  EvaluateCriteria(s, &standing);
  EXPECT_TRUE(standing.passed);
}

TEST(CriteriaTest, AWalkSlowerThanVdFailsTheTravelCriterion) {
  // The pragmatic rules of the 0.6 m/s gait: asked for V_d = 0.6 m/s they travel more than 70 % of
  // it; asked for 2.5 m/s (25 m in 10 s), the same walk fails the travel criterion.
  Scenario s = LoadScenario(kRoot + "/scenarios/walk_pragmatic_0.60.toml");
  s.options.duration = 10.0;
  s.has_velocity = true;
  s.velocity.points = {{0.0, 0.6}};
  RunOutput walks = RunScenario(s, "pragmatic", nullptr);
  EXPECT_EQ(walks.sim.outcome, Outcome::kCompleted);
  EXPECT_GT(walks.metrics.distance, 0.7 * 6.0);
  EXPECT_TRUE(walks.passed) << (walks.failures.empty() ? "" : walks.failures[0]);
  s.velocity.points = {{0.0, 2.5}};
  RunOutput slow = RunScenario(s, "pragmatic", nullptr);
  EXPECT_FALSE(slow.passed);
  ASSERT_FALSE(slow.failures.empty());
  EXPECT_NE(slow.failures.back().find("min_travel_ratio"), std::string::npos);
}

TEST(CriteriaTest, AWalkerFrozenAfterAStepBackwardIsStalled) {
  // The paper suite's obstacle_anywhere-000: after a long step past the obstacle the walker's next
  // step lands behind the stance foot (a negative L_step and V_M), and then the robot stands in a
  // split stance. The stall watch ends the run there, 2 s after its last touchdown.
  const Suite suite = LoadSuite(kRoot + "/scenarios/paper.toml");
  const std::vector<BatchJob> jobs = PlanBatch(suite, "^obstacle_anywhere-000$");
  ASSERT_EQ(jobs.size(), 1u);
  GaitLibraryCache libraries;
  const Scenario& s = *jobs[0].scenario;
  const RunOutput r = RunScenario(s, jobs[0].variant, libraries.Get(s.pattern).get());
  EXPECT_EQ(r.sim.outcome, Outcome::kStalled) << r.sim.reason;
  EXPECT_NE(r.sim.reason.find("no touchdown"), std::string::npos) << r.sim.reason;
  EXPECT_LT(r.sim.t_end, s.options.duration);
  ASSERT_FALSE(r.steps.empty());
  const StepRow& last = r.steps.back();
  EXPECT_LT(last.step.l_step, 0.0);
  EXPECT_LT(last.step.v_m, 0.0);
  EXPECT_NEAR(last.step.v_m, last.step.l_step / last.step.t_step, 1e-12);
  EXPECT_NEAR(r.sim.t_end - last.step.t_touchdown, 2.0, 0.01);
  EXPECT_FALSE(r.passed);
}

}  // namespace
}  // namespace rabbit
