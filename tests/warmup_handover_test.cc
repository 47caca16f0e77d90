// The warm-up's early hand-over: a warm-up step (from the warmup_handover_after-th on) shorter than
// warmup_handover_ratio times the start gait's L_step ends the warm-up at its touchdown. On a robot
// with 9 % heavier legs (a member of the training family link_masses) the start gait's rules alone
// shrink every step until it falls; handed over at the first short step, the Fuzzy-CMAC walks on.
// And the step planner's end_warmup_within: an obstacle close ahead of a warm-up step's landing
// foot ends the warm-up at that touchdown, so that the planner plans the approach.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "cli_fixture.h"
#include "rabbit/control/walker_presets.h"
#include "rabbit/io/error.h"
#include "rabbit/scenario/run.h"
#include "rabbit/scenario/scenario.h"

namespace rabbit {
namespace {

class WarmupHandoverTest : public testing::ScratchDirTest {
 protected:
  WarmupHandoverTest() : ScratchDirTest("rabbit_warmup_handover_test") {}
  // 20 s at 0.6 m/s with the legs 9 % heavier (masses and inertias) than the model the gaits were
  // found on, and the trunk 3 % heavier; `controller` lines are added to [controller].
  std::string Write(const std::string& controller) {
    return ScratchDirTest::Write("heavy_legs.toml",
                                 std::string("[simulation]\nduration = 20.0\n") +
                                     "[model]\ntrunk_mass = 12.32\ntrunk_inertia = 1.366\n" +
                                     "thigh_mass = 7.419\nthigh_inertia = 0.5128\n" +
                                     "shin_mass = 3.354\nshin_inertia = 0.2096\n" +
                                     "[velocity]\nvalue = 0.6\n[criteria]\nmin_steps = 20\n" +
                                     "[controller]\ntype = \"fuzzy_cmac\"\ndatabase = \"" +
                                     RABBIT_SOURCE_DIR + "/gaits\"\n" + controller);
  }
  RunOutput Run(const std::string& controller) {
    Scenario s = LoadScenario(Write(controller));
    s.walker.log_every = 0;
    const std::shared_ptr<const GaitLibrary> library = LoadGaitLibrary(s.pattern);
    return RunScenario(s, "fuzzy_cmac", library.get());
  }
};

TEST(WarmupHandover, TheAdaptivePresetHandsOverEarlyAndTheChaptersDoesNot) {
  const WalkerParams a = PresetWalkerParams(WalkerPreset::kAdaptive);
  const WalkerParams c = PresetWalkerParams(WalkerPreset::kChapter);
  EXPECT_GT(a.warmup_handover_ratio, 0.0);
  EXPECT_EQ(c.warmup_handover_ratio, 0.0);
  EXPECT_EQ(a.warmup_steps, c.warmup_steps);
}

TEST_F(WarmupHandoverTest, TheStartGaitsLengthComesFromTheDatabase) {
  const Scenario s = LoadScenario(Write(""));
  // vm_0.60's recorded L_step, the start gait at 0.6 m/s.
  EXPECT_GT(s.walker.warmup_l_step, 0.30);
  EXPECT_LT(s.walker.warmup_l_step, 0.40);
}

TEST_F(WarmupHandoverTest, HeavyLegsFallOnTheRulesAndWalkWhenHandedOver) {
  const RunOutput rules = Run("warmup_handover_ratio = 0\n");
  EXPECT_EQ(rules.sim.outcome, Outcome::kFell) << rules.sim.reason;
  ASSERT_FALSE(rules.steps.empty());
  for (const StepRow& row : rules.steps) EXPECT_TRUE(row.warmup);  // it never left the warm-up

  const Scenario s = LoadScenario(Write(""));
  const double ratio = s.walker.warmup_handover_ratio, l_start = s.walker.warmup_l_step;
  const size_t after = static_cast<size_t>(s.walker.warmup_handover_after);
  const RunOutput handed = Run("");
  EXPECT_EQ(handed.sim.outcome, Outcome::kCompleted) << handed.sim.reason;
  EXPECT_TRUE(handed.passed) << (handed.failures.empty() ? "" : handed.failures[0]);
  // The warm-up ends at the first step from the after-th on shorter than ratio * L_step, and not
  // before (a step's `warmup` flag says who is in charge from its touchdown on, as for the sixth
  // step of a full warm-up).
  size_t first_short = handed.steps.size();
  for (size_t i = after; i < handed.steps.size(); ++i) {
    if (handed.steps[i].step.l_step < ratio * l_start) {
      first_short = i;
      break;
    }
  }
  ASSERT_LT(first_short, 6u) << "no warm-up step was short: the test's robot walks as designed";
  for (size_t i = 0; i < first_short; ++i) EXPECT_TRUE(handed.steps[i].warmup) << i;
  for (size_t i = first_short; i < handed.steps.size(); ++i) {
    EXPECT_FALSE(handed.steps[i].warmup) << i;
  }
}

TEST_F(WarmupHandoverTest, ARatioOutsideZeroToOneIsRefusedNamingTheKey) {
  for (const char* bad : {"warmup_handover_ratio = 1.5\n", "warmup_handover_ratio = -0.1\n"}) {
    try {
      LoadScenario(Write(bad));
      ADD_FAILURE() << "no error for " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("warmup_handover_ratio"), std::string::npos) << e.what();
    }
  }
}

TEST(WarmupHandover, TheAdaptivePresetEndsTheWarmupNearAnObstacle) {
  const WalkerParams a = PresetWalkerParams(WalkerPreset::kAdaptive);
  EXPECT_TRUE(a.planner.enabled);
  EXPECT_GT(a.planner.end_warmup_within, a.planner.horizon);
  // The chapter's walker has no planner: its warm-up is the chapter's, whatever the key.
  EXPECT_FALSE(PresetWalkerParams(WalkerPreset::kChapter).planner.enabled);
}

class ObstacleHandoverTest : public testing::ScratchDirTest {
 protected:
  static constexpr double kObstacleX = 3.2;  // m: the near edge, reached during a full warm-up
  ObstacleHandoverTest() : ScratchDirTest("rabbit_obstacle_handover_test") {}
  // 12 s at 0.6 m/s toward an obstacle 0.2 m long and 0.05 m high; `planner` lines are added to
  // [controller.planner].
  RunOutput Run(const std::string& planner) {
    Scenario s = LoadScenario(Write(
        "obstacle_near.toml",
        std::string("[simulation]\nduration = 12.0\n[velocity]\nvalue = 0.6\n") +
            "[[terrain.obstacles]]\nx_start = " + std::to_string(kObstacleX) +
            "\nlength = 0.2\nheight = 0.05\n[controller]\ntype = \"fuzzy_cmac\"\n" +
            "database = \"" + RABBIT_SOURCE_DIR + "/gaits\"\n[controller.planner]\n" + planner));
    s.walker.log_every = 0;
    within_ = s.walker.planner.end_warmup_within;
    after_ = static_cast<size_t>(s.walker.warmup_handover_after);
    warmup_steps_ = static_cast<size_t>(s.walker.warmup_steps);
    const std::shared_ptr<const GaitLibrary> library = LoadGaitLibrary(s.pattern);
    return RunScenario(s, "fuzzy_cmac", library.get());
  }
  static size_t WarmupSteps(const RunOutput& run) {
    size_t n = 0;
    while (n < run.steps.size() && run.steps[n].warmup) ++n;
    return n;
  }
  double within_ = 0.0;
  size_t after_ = 0, warmup_steps_ = 0;
};

TEST_F(ObstacleHandoverTest, TheWarmupEndsAtTheFirstLandingWithinReachOfTheObstacle) {
  const RunOutput early = Run("");  // the preset's distance
  const double within = within_;
  ASSERT_GT(within, 0.0);
  const RunOutput full = Run("end_warmup_within = 0.0\n");
  // Off: the whole warm-up (the touchdown of its last step hands over, as in the test above).
  ASSERT_GT(full.steps.size(), warmup_steps_);
  EXPECT_EQ(WarmupSteps(full), warmup_steps_ - 1);
  // The two walks are the same up to the hand-over. The first landing, from the after-th step
  // on, whose foot has the obstacle's near edge within reach ends the warm-up; none of the
  // warm-up's landings lies within 1 cm of the limit, so that where the gait meter and the walker
  // put the foot cannot decide it.
  size_t first = full.steps.size();
  for (size_t i = 0; i + 1 < warmup_steps_; ++i) {
    const double ahead = kObstacleX - full.steps[i].step.x;
    EXPECT_GT(std::abs(ahead - within), 0.01) << i;
    if (i >= after_ && ahead < within && first == full.steps.size()) first = i;
  }
  ASSERT_LT(first, warmup_steps_ - 1) << "the obstacle came into reach only after a full warm-up";
  EXPECT_EQ(WarmupSteps(early), first);
  for (size_t i = 0; i <= first && i < early.steps.size(); ++i) {
    EXPECT_EQ(early.steps[i].step.x, full.steps[i].step.x) << i;
  }
  for (size_t i = first; i < early.steps.size(); ++i) EXPECT_FALSE(early.steps[i].warmup) << i;
}

// After a backward push the push response hands the walk to the rules for a few steps (as a
// warm-up, but not flagged in steps.csv: they are steps of the walk); an obstacle within reach
// ends those too. A training member of obstacle_after_push (seeds 4xxx): 6.76 N s backward at
// 4.66 m, an obstacle at 6.68 m, out of reach of every landing of the start's warm-up.
class PushRulesHandoverTest : public testing::ScratchDirTest {
 protected:
  static constexpr double kObstacleX = 6.677982602460192;
  PushRulesHandoverTest() : ScratchDirTest("rabbit_push_rules_handover_test") {}
  RunOutput Run(bool push, const std::string& planner) {
    Scenario s = LoadScenario(
        Write("push_then_obstacle.toml",
              std::string("[simulation]\ndistance = 11.7\nduration = 60.0\n") +
                  "[velocity]\nvalue = 0.7145972181767831\n" +
                  (push ? "[[push]]\nat_hip_x = 4.663427368711831\nduration = 0.05730411639844639\n"
                          "impulse_n_s = -6.7618117940531945\nheight = 0.2\n"
                        : "") +
                  "[[terrain.obstacles]]\nx_start = 6.677982602460192\n" +
                  "length = 0.13763755230398578\nheight = 0.03274831440932812\n" +
                  "[controller]\ntype = \"fuzzy_cmac\"\ndatabase = \"" + RABBIT_SOURCE_DIR +
                  "/gaits\"\n[controller.planner]\n" + planner));
    s.walker.log_every = 0;
    within_ = s.walker.planner.end_warmup_within;
    const std::shared_ptr<const GaitLibrary> library = LoadGaitLibrary(s.pattern);
    return RunScenario(s, "fuzzy_cmac", library.get());
  }
  // The first step whose landing differs between the two walks (a.steps.size() if none).
  static size_t FirstDifference(const RunOutput& a, const RunOutput& b) {
    size_t i = 0;
    while (i < a.steps.size() && i < b.steps.size() && a.steps[i].step.x == b.steps[i].step.x &&
           a.steps[i].step.t_touchdown == b.steps[i].step.t_touchdown) {
      ++i;
    }
    return i;
  }
  double within_ = 0.0;
};

TEST_F(PushRulesHandoverTest, TheResponsesRuleStepsEndWithinReachOfTheObstacle) {
  const RunOutput on = Run(true, "");
  const double within = within_;
  ASSERT_GT(within, 0.0);
  const RunOutput off = Run(true, "end_warmup_within = 0.0\n");
  // The start's warm-up never has the obstacle within reach: the key cannot act there.
  int warmup_steps = 0;
  for (const StepRow& row : off.steps) {
    if (row.warmup) {
      ++warmup_steps;
      EXPECT_GT(kObstacleX - row.step.x, within + 0.01);
    }
  }
  EXPECT_GT(warmup_steps, 0);
  // With the push, the walks part: the touchdown before the first step that differs landed
  // within reach of the obstacle (where the response's rules handed back to the Fuzzy-CMAC).
  const size_t i = FirstDifference(on, off);
  ASSERT_GT(i, 0u);
  ASSERT_LT(i, off.steps.size()) << "the key changed nothing after the push";
  EXPECT_LT(kObstacleX - on.steps[i - 1].step.x, within);
  EXPECT_GT(kObstacleX - on.steps[i - 1].step.x, 0.0);
  // Without the push no rule steps come after the warm-up, and the key changes nothing.
  const RunOutput calm_on = Run(false, ""), calm_off = Run(false, "end_warmup_within = 0.0\n");
  ASSERT_FALSE(calm_on.steps.empty());
  EXPECT_EQ(FirstDifference(calm_on, calm_off), calm_on.steps.size());
  EXPECT_EQ(calm_on.steps.size(), calm_off.steps.size());
}

TEST_F(ObstacleHandoverTest, ADistanceOutsideTheRangeIsRefusedNamingTheKey) {
  for (const char* bad : {"end_warmup_within = -0.5\n", "end_warmup_within = 1000.0\n"}) {
    try {
      Run(bad);
      ADD_FAILURE() << "no error for " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("end_warmup_within"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace rabbit
