// The slope adaptation's preview ([controller.slope] preview): the known change of grade ahead is
// added to the grade read from the feet. On flat ground the change is zero and the walk is the
// same bit for bit as without the preview; where a ramp begins, the walk departs from the
// walk without it at the touchdown before the ramp (the step that will cross onto it), not later.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>

#include "cli_fixture.h"
#include "rabbit/scenario/run.h"
#include "rabbit/scenario/scenario.h"

namespace rabbit {
namespace {

constexpr double kRampStart = 3.2;  // m: where the uphill begins

class SlopePreviewTest : public testing::ScratchDirTest {
 protected:
  SlopePreviewTest() : ScratchDirTest("rabbit_slope_preview_test") {}
  // 10 s at 0.6 m/s with the default (adaptive) walker; `terrain` is the [terrain] table's body.
  RunOutput Run(const std::string& terrain, double preview) {
    const std::string path = ScratchDirTest::Write(
        "walk.toml", "[simulation]\nduration = 10.0\n[velocity]\nvalue = 0.6\n[terrain]\n" +
                         terrain + "[controller]\ntype = \"fuzzy_cmac\"\ndatabase = \"" +
                         RABBIT_SOURCE_DIR + "/gaits\"\n[controller.slope]\npreview = " +
                         std::to_string(preview) + "\n");
    Scenario s = LoadScenario(path);
    s.walker.log_every = 0;
    const std::shared_ptr<const GaitLibrary> library = LoadGaitLibrary(s.pattern);
    return RunScenario(s, "fuzzy_cmac", library.get());
  }
  static bool SameStep(const StepRow& a, const StepRow& b) {
    return a.step.t_touchdown == b.step.t_touchdown && a.step.l_step == b.step.l_step &&
           a.step.x == b.step.x;
  }
};

TEST_F(SlopePreviewTest, DefaultIsOnInTheAdaptiveWalker) {
  const std::string path = ScratchDirTest::Write(
      "default.toml", std::string("[simulation]\nduration = 1.0\n[velocity]\nvalue = 0.6\n") +
                          "[controller]\ntype = \"fuzzy_cmac\"\ndatabase = \"" +
                          RABBIT_SOURCE_DIR + "/gaits\"\n");
  const Scenario s = LoadScenario(path);
  EXPECT_TRUE(s.walker.slope.enabled);
  EXPECT_EQ(s.walker.slope.preview, 1.0);
}

TEST_F(SlopePreviewTest, FlatGroundIsUnchangedBitForBit) {
  const RunOutput off = Run("", 0.0), on = Run("", 1.0);
  ASSERT_EQ(off.steps.size(), on.steps.size());
  ASSERT_GT(off.steps.size(), 10u);
  for (size_t i = 0; i < off.steps.size(); ++i) EXPECT_TRUE(SameStep(off.steps[i], on.steps[i]));
  EXPECT_EQ(off.sim.t_end, on.sim.t_end);
}

TEST_F(SlopePreviewTest, AnUphillIsAnticipatedOneStepEarly) {
  const std::string ramp = "slopes = [{ x_start = " + std::to_string(kRampStart) +
                           ", slope_deg = -3.0 }]\n";
  const RunOutput off = Run(ramp, 0.0), on = Run(ramp, 1.0);
  // The first touchdown whose coming step (about as long as the last) reaches the ramp.
  size_t first = 0;
  while (first < off.steps.size() &&
         off.steps[first].step.x + std::clamp(off.steps[first].step.l_step, 0.15, 0.6) <=
             kRampStart) {
    ++first;
  }
  ASSERT_LT(first + 2, off.steps.size());
  ASSERT_LT(off.steps[first].step.x, kRampStart) << "the step is still on the flat";
  // Up to that touchdown both walks are the same; the step after it is not.
  for (size_t i = 0; i <= first; ++i) EXPECT_TRUE(SameStep(off.steps[i], on.steps[i])) << i;
  EXPECT_FALSE(SameStep(off.steps[first + 1], on.steps[first + 1]));
}

}  // namespace
}  // namespace rabbit
