// The approach to a step ([controller.steps] up_speed, down_speed, speed_before, hold_steps): on
// terrain without steps the adaptive walker is the same bit for bit with them as without them;
// at a low V_d a 4 cm step up that the walker without them falls at is walked onto and past.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "cli_fixture.h"
#include "rabbit/scenario/run.h"
#include "rabbit/scenario/scenario.h"

namespace rabbit {
namespace {

constexpr double kFace = 3.5;  // m: where the step up is

class StepApproachTest : public testing::ScratchDirTest {
 protected:
  StepApproachTest() : ScratchDirTest("rabbit_step_approach_test") {}
  // The default (adaptive) walker at `v_d` for `duration`; `terrain` is the [terrain] table's
  // body; `approach` false sets the approach's keys to their off values.
  // The knee's gated extension and the one-step lean of the adaptive preset are set back to the
  // library's (timed extension, two steps of lean), the walker the approach was chosen with: this
  // tests the approach alone (one member at 0.42 m/s stalls on the step with both, as others
  // pass instead; the figures over the training members are in docs/design/steps.md).
  RunOutput Run(const std::string& terrain, double v_d, double duration, bool approach) {
    std::string text = "[simulation]\nduration = " + std::to_string(duration) +
                       "\n[velocity]\nvalue = " + std::to_string(v_d) + "\n[terrain]\n" + terrain +
                       "[controller]\ntype = \"fuzzy_cmac\"\ndatabase = \"" + RABBIT_SOURCE_DIR +
                       "/gaits\"\n[controller.steps]\nup_knee_by_hip = false\nlean_steps = 2\n";
    if (!approach) text += "up_speed = 0.0\ndown_speed = 0.0\nhold_steps = 0\n";
    Scenario s = LoadScenario(ScratchDirTest::Write("walk.toml", text));
    s.walker.log_every = 0;
    const std::shared_ptr<const GaitLibrary> library = LoadGaitLibrary(s.pattern);
    return RunScenario(s, "fuzzy_cmac", library.get());
  }
  static bool SameStep(const StepRow& a, const StepRow& b) {
    return a.step.t_touchdown == b.step.t_touchdown && a.step.l_step == b.step.l_step &&
           a.step.x == b.step.x && a.q0_d == b.q0_d;
  }
};

TEST_F(StepApproachTest, AdaptivePresetSetsTheApproach) {
  const Scenario s = LoadScenario(ScratchDirTest::Write(
      "default.toml", std::string("[simulation]\nduration = 1.0\n[velocity]\nvalue = 0.6\n") +
                          "[controller]\ntype = \"fuzzy_cmac\"\ndatabase = \"" + RABBIT_SOURCE_DIR +
                          "/gaits\"\n"));
  EXPECT_EQ(s.walker.steps.up_speed, 0.7);
  EXPECT_EQ(s.walker.steps.down_speed, 0.65);
  EXPECT_EQ(s.walker.steps.speed_before, 2.5);
  EXPECT_EQ(s.walker.steps.hold_steps, 2);
  EXPECT_TRUE(s.walker.steps.up_knee_by_hip);
  EXPECT_EQ(s.walker.steps.up_knee_at, -0.12);
  EXPECT_EQ(s.walker.steps.lean_steps, 1);
  EXPECT_EQ(s.walker.steps.lead, 0.18);
}

TEST_F(StepApproachTest, TerrainWithoutStepsIsUnchangedBitForBit) {
  // Flat ground at a low V_d (the approach speed would change it most), and a ramp.
  for (const std::string& terrain :
       {std::string(), std::string("slopes = [{ x_start = 2.5, slope_deg = -3.0 }]\n")}) {
    const RunOutput off = Run(terrain, 0.42, 10.0, false), on = Run(terrain, 0.42, 10.0, true);
    ASSERT_EQ(off.steps.size(), on.steps.size()) << terrain;
    ASSERT_GT(off.steps.size(), 10u);
    for (size_t i = 0; i < off.steps.size(); ++i) {
      EXPECT_TRUE(SameStep(off.steps[i], on.steps[i])) << terrain << " step " << i;
    }
    EXPECT_EQ(off.sim.t_end, on.sim.t_end);
    EXPECT_EQ(off.sim.outcome, on.sim.outcome);
  }
}

TEST_F(StepApproachTest, LowSpeedStepUpIsWalkedOnto) {
  // 4 cm up at 3.5 m, V_d 0.42 m/s: without the approach the planner's 0.36 m steps at that
  // speed topple the robot before the face; at the approach speed it walks onto the step and on.
  const std::string step = "steps = [{ x_start = " + std::to_string(kFace) + ", rise = 0.04 }]\n";
  const RunOutput off = Run(step, 0.42, 15.0, false), on = Run(step, 0.42, 15.0, true);
  EXPECT_NE(off.sim.outcome, Outcome::kCompleted);
  EXPECT_EQ(on.sim.outcome, Outcome::kCompleted);
  ASSERT_FALSE(on.steps.empty());
  EXPECT_GT(on.steps.back().step.x, kFace + 2.0);
}

}  // namespace
}  // namespace rabbit
