// The step planner: its arithmetic against hand-computed plans, the step-length fuzzy
// system's interpolation between neighbouring gaits, and [controller.planner]'s key validation.
#include "rabbit/control/step_planner.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "rabbit/control/fuzzy_cmac_walker.h"
#include "rabbit/io/error.h"
#include "rabbit/learn/ts_fis.h"
#include "rabbit/scenario/run.h"
#include "rabbit/scenario/suite.h"
#include "suite_fixture.h"

namespace rabbit {
namespace {

constexpr double kTolerance = 1e-12;

StepPlannerParams HandParams() {
  StepPlannerParams p;
  p.enabled = true;
  p.horizon = 1.5;
  p.margin_before = 0.06;
  p.margin_after = 0.10;
  p.l_min = 0.28;
  p.l_max = 0.42;
  p.l_nominal = 0.36;
  p.l_over_max = 0.48;
  p.use_length = true;
  return p;
}

void ExpectPlan(const StepPlan& plan, int steps, double length) {
  EXPECT_TRUE(plan.active);
  EXPECT_EQ(plan.approach_steps, steps);
  EXPECT_NEAR(plan.step_length, length, kTolerance);
}

TEST(StepPlannerTest, OutsideTheHorizonNoPlan) {
  EXPECT_FALSE(PlanStep(HandParams(), 1.6, 0.2).active);
  EXPECT_FALSE(PlanStep(HandParams(), INFINITY, 0.2).active);
  EXPECT_TRUE(PlanStep(HandParams(), 1.5, 0.2).active);
}

TEST(StepPlannerTest, ApproachStepsAgainstHandComputedValues) {
  const StepPlannerParams p = HandParams();
  // 1.0 - 0.06 = 0.94 m to the last foot: 2 x 0.47 is too long, 4 x 0.235 too short; 3 x 0.3133.
  ExpectPlan(PlanStep(p, 1.0, 0.2), 3, 0.94 / 3);
  // 0.78 - 0.06 = 0.72 = 2 x 0.36 (the nominal step).
  ExpectPlan(PlanStep(p, 0.78, 0.2), 2, 0.36);
  // 0.40 - 0.06 = 0.34: one step.
  ExpectPlan(PlanStep(p, 0.40, 0.2), 1, 0.34);
  // 0.50 - 0.06 = 0.44 fits no count: one 0.44 m step (0.02 over l_max) beats 2 x 0.22 (0.06
  // under).
  ExpectPlan(PlanStep(p, 0.50, 0.2), 1, 0.44);
}

TEST(StepPlannerTest, StepOverAgainstHandComputedValues) {
  StepPlannerParams p = HandParams();
  // 0.10 m before a 0.2 m obstacle: over now, 0.10 + 0.20 + 0.10 = 0.40 m.
  ExpectPlan(PlanStep(p, 0.10, 0.2), 0, 0.40);
  // 0.20 m before a 0.30 m one: 0.60 m exceeds l_over_max, so creep 0.14 m closer first.
  ExpectPlan(PlanStep(p, 0.20, 0.3), 1, 0.14);
  // Within the margin already: over now, 0.03 + 0.30 + 0.10 = 0.43 m.
  ExpectPlan(PlanStep(p, 0.03, 0.3), 0, 0.43);
  // Not perceiving the length: the assumed 0.3 m.
  p.use_length = false;
  p.assumed_length = 0.3;
  ExpectPlan(PlanStep(p, 0.05, 0.05), 0, 0.45);
  // Clamped to l_over_max.
  p.margin_after = 0.2;
  ExpectPlan(PlanStep(p, 0.05, 0.05), 0, 0.48);
}

TEST(StepPlannerTest, StepOverAskedAtLeastLOverMin) {
  StepPlannerParams p = HandParams();
  p.l_over_min = 0.31;
  // 0.02 m before a 0.05 m obstacle: 0.02 + 0.05 + 0.10 = 0.17 m, raised to 0.31 m.
  ExpectPlan(PlanStep(p, 0.02, 0.05), 0, 0.31);
  // Longer than l_over_min already: unchanged (0.10 + 0.20 + 0.10 = 0.40 m).
  ExpectPlan(PlanStep(p, 0.10, 0.2), 0, 0.40);
  // Approach steps are not steps over: the 0.34 m approach step as without it.
  ExpectPlan(PlanStep(p, 0.40, 0.2), 1, 0.34);
  // Still clamped to l_over_max.
  ExpectPlan(PlanStep(p, 0.05, 0.40), 0, 0.48);
  p.l_over_min = 0.0;
  ExpectPlan(PlanStep(p, 0.02, 0.05), 0, 0.17);
}

TEST(StepPlannerTest, ParamsValidation) {
  std::string error;
  EXPECT_TRUE(HandParams().IsValid(&error)) << error;
  StepPlannerParams p = HandParams();
  p.l_min = 0.5;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("l_min < l_max"), std::string::npos) << error;
  p = HandParams();
  p.margin_before = -0.1;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("planner.margin_before"), std::string::npos) << error;
  p = HandParams();
  p.feedback_gain = 2.0;
  EXPECT_FALSE(p.IsValid(&error));
  p = HandParams();
  p.l_over_min = 0.5;  // above l_over_max (0.48)
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("planner.l_over_min must be <= l_over_max"), std::string::npos) << error;
}

TEST(StepLengthFisTest, InterpolatesLinearlyBetweenNeighbouringGaits) {
  // Gaits given out of order: gait 1 is the longest step.
  const TsFis fis = StepLengthFis({0.40, 0.25, 0.30});
  std::string error;
  ASSERT_TRUE(fis.IsValid(&error)) << error;
  auto expect = [&](double l, std::vector<double> want) {
    const std::vector<double> w = StepLengthWeights(fis, l);
    ASSERT_EQ(w.size(), want.size());
    for (size_t k = 0; k < w.size(); ++k) EXPECT_NEAR(w[k], want[k], 1e-9) << "l = " << l;
  };
  expect(0.35, {0.5, 0.0, 0.5});
  expect(0.27, {0.0, 0.6, 0.4});
  expect(0.30, {0.0, 0.0, 1.0});
  expect(0.10, {0.0, 1.0, 0.0});  // shoulders: the shortest gait below its step
  expect(0.55, {1.0, 0.0, 0.0});
  // Interpolating the gaits' own steps gives the target back (linear interpolation).
  for (double l = 0.25; l <= 0.40; l += 0.01) {
    const std::vector<double> w = StepLengthWeights(fis, l);
    EXPECT_NEAR(0.40 * w[0] + 0.25 * w[1] + 0.30 * w[2], l, 1e-9);
  }
}

TEST(StepLengthFisTest, AnyNumberOfGaits) {
  const std::vector<double> eight = {0.15, 0.20, 0.25, 0.30, 0.34, 0.38, 0.42, 0.46};
  const TsFis fis = StepLengthFis(eight);
  EXPECT_EQ(fis.rules.size(), 8u);
  const std::vector<double> w = StepLengthWeights(fis, 0.40);
  EXPECT_NEAR(w[5], 0.5, 1e-9);
  EXPECT_NEAR(w[6], 0.5, 1e-9);
  EXPECT_THROW(StepLengthFis({0.3}), std::invalid_argument);
  EXPECT_THROW(StepLengthFis({0.3, 0.3}), std::invalid_argument);
  EXPECT_THROW(StepLengthFis({0.3, -0.1}), std::invalid_argument);
}

// [controller.planner] keys: validated, errors naming the file, line and key.
// The walker suite with `planner` in [defaults.controller.planner] (line 12).
class PlannerKeysTest : public testing::WalkerKeysTest {
 protected:
  PlannerKeysTest() : WalkerKeysTest("rabbit_step_planner_test", "planner") {}
};

TEST_F(PlannerKeysTest, ReadAndValidated) {
  const Suite suite = LoadSuite(Write("enabled = true\nmargin_after = 0.12\n"));
  ASSERT_EQ(suite.scenarios.size(), 1u);
  EXPECT_TRUE(suite.scenarios[0].walker.planner.enabled);
  EXPECT_DOUBLE_EQ(suite.scenarios[0].walker.planner.margin_after, 0.12);
  ExpectError("enabled = true\nmargin_aftr = 0.1\n", 14,
              "scenario[1].controller.planner.margin_aftr", "unknown key");
  ExpectError("enabled = \"yes\"\n", 13, "scenario[1].controller.planner.enabled", "");
  ExpectError("l_min = 0.5\n", -1, "scenario[1].controller.planner.l_min", "l_min < l_max");
  ExpectError("horizon = -1.0\n", -1, "scenario[1].controller.planner.horizon", "[0, 10]");
  EXPECT_DOUBLE_EQ(LoadSuite(Write("l_over_min = 0.35\n")).scenarios[0].walker.planner.l_over_min,
                   0.35);
  ExpectError("l_over_min = 0.6\n", -1, "scenario[1].controller.planner.l_over_min",
              "must be <= l_over_max");
  EXPECT_FALSE(suite.scenarios[0].walker.planner.tracked_gaits_only);  // default
  EXPECT_TRUE(LoadSuite(Write("tracked_gaits_only = true\n"))
                  .scenarios[0]
                  .walker.planner.tracked_gaits_only);
  ExpectError("tracked_gaits_only = 1\n", 13, "scenario[1].controller.planner.tracked_gaits_only",
              "");
}

// tracked_gaits_only: the step-length system blends only the gaits whose rule share is below
// 1/2; a rule share that leaves fewer than two is refused when the walker is built.
TEST(StepPlannerTrackedGaitsTest, BlendsOnlyTheTrackedGaits) {
  WalkerParams p;
  p.warmup_steps = 0;
  p.thigh_frame = false;
  p.planner.enabled = true;
  p.planner.tracked_gaits_only = true;
  p.gait_l_steps = {0.15, 0.24, 0.28, 0.35, 0.36};
  p.rule_share = {1, 1, 1, 1, 0};
  p.gait_rules.assign(5, PragmaticParams());
  TsFis fis = DefaultGaitPattern({0.3, 0.4, 0.5, 0.6, 0.7});
  std::vector<GaitCmacs> networks(5);
  CmacOptions o;
  o.x_min = -1.0;
  o.x_max = 1.0;
  for (GaitCmacs& g : networks) g.assign(kGaitOutputs, Cmac(o));
  VelocityProfile v;
  EXPECT_THROW(FuzzyCmacWalker(p, FuzzyCmac(fis, networks), v, 0), std::invalid_argument);
  p.rule_share = {1, 0, 0, 0, 0};
  EXPECT_NO_THROW(FuzzyCmacWalker(p, FuzzyCmac(fis, networks), v, 0));
}

// Walking: obstacles of the training family that the walker without the planner trips on or
// falls after (Table 3 alone), stepped over with it (default settings).
class PlannerWalkTest : public PlannerKeysTest {};

TEST_F(PlannerWalkTest, StepsOverObstaclesThatFailedWithoutIt) {
  struct Case {
    double x_start, length, height;
  };
  // Training members obstacle-001, -002, -005 and -007 (robustness_train.toml), on the eight
  // shipped gaits with the walker of the robustness suites (fis_v_lead, rule_share).
  const Case cases[] = {{3.330445, 0.287657, 0.028837},
                        {3.964709, 0.230076, 0.025746},
                        {3.227988, 0.170842, 0.057472},
                        {3.752074, 0.235556, 0.023432}};
  const std::string root = RABBIT_SOURCE_DIR;
  std::string text =
      "[suite]\nname = \"walk\"\n[defaults]\nexpect_outcome = \"completed\"\n"
      "[defaults.simulation]\ndistance = 9.0\nduration = 40.0\nrecord_every = 50\n"
      "[defaults.velocity]\nvalue = 0.6\n[defaults.controller]\n"
      "type = \"fuzzy_cmac\"\ndatabase = \"" +
      root +
      "/gaits\"\nfis_v_lead = 1.0\n"
      "[defaults.criteria]\nmin_steps_after_obstacles = 10\n"
      "allow_obstacle_contact = false\n";
  int i = 0;
  for (const Case& c : cases) {
    text += "[[scenario]]\nname = \"o" + std::to_string(i++) +
            "\"\n[[scenario.terrain.obstacles]]\nx_start = " + std::to_string(c.x_start) +
            "\nlength = " + std::to_string(c.length) + "\nheight = " + std::to_string(c.height) +
            "\n";
  }
  const std::string path = (dir_ / "walk.toml").string();
  std::ofstream(path) << text;
  const Suite suite = LoadSuite(path);
  GaitLibraryCache cache;
  int failed_without = 0;
  for (const Scenario& s : suite.scenarios) {
    ASSERT_TRUE(s.walker.planner.enabled);
    const auto library = cache.Get(s.pattern);
    const RunOutput with = RunScenario(s, "fuzzy_cmac", library.get());
    EXPECT_TRUE(with.passed) << s.name << ": " << (with.failures.empty() ? "" : with.failures[0]);
    Scenario off = s;
    off.walker.planner.enabled = false;
    if (!RunScenario(off, "fuzzy_cmac", library.get()).passed) ++failed_without;
  }
  EXPECT_EQ(failed_without, static_cast<int>(suite.scenarios.size()));
}

}  // namespace
}  // namespace rabbit
