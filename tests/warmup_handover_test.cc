// The warm-up's early hand-over: a warm-up step (from the warmup_handover_after-th on) shorter than
// warmup_handover_ratio times the start gait's L_step ends the warm-up at its touchdown. On a robot
// with 9 % heavier legs (a member of the training family link_masses) the start gait's rules alone
// shrink every step until it falls; handed over at the first short step, the Fuzzy-CMAC walks on.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace rabbit
