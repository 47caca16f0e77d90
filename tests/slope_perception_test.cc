// The slope adaptation's perception on flat ground ([controller.slope] touchdown_heights). The
// compliant contact lets a loaded foot sink a few millimetres; read from the feet as they are at a
// touchdown, the just-landed foot stands higher than the loaded one, which on a short step reads
// as an uphill of about 1 deg, and the walker leans its trunk forward by trunk_gain times that.
// The reference is the gait's own pragmatic rules walked at the same trunk pitch: the walker on
// the slowest gait (walked by those rules, rule share 1) with its pitch held (k_p = k_v = 0)
// walks their speed when the other foot's height is taken at its own touchdown, and much faster
// when it is taken under load.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "cli_fixture.h"
#include "rabbit/scenario/run.h"
#include "rabbit/scenario/scenario.h"

namespace rabbit {
namespace {

constexpr double kDeg = M_PI / 180.0;

class SlopePerceptionTest : public testing::ScratchDirTest {
 protected:
  SlopePerceptionTest() : ScratchDirTest("rabbit_slope_perception_test") {}
  // The walker at V_d = 0.32 m/s (it starts on the slowest gait, vm_0.30) with its pitch held.
  RunOutput Walker(bool touchdown_heights) {
    const std::string path = Write(
        "walker.toml",
        std::string("[simulation]\nduration = 14.0\n[velocity]\nvalue = 0.32\n") +
            "[controller]\ntype = \"fuzzy_cmac\"\ndatabase = \"" + RABBIT_SOURCE_DIR +
            "/gaits\"\nk_p = 0\nk_v = 0\n" +
            "[controller.slope]\ntouchdown_heights = " + (touchdown_heights ? "true" : "false") +
            // The pitch held is the gaits' map's at the command (no start map of its own).
            "\n[controller.velocity_control]\nsettled_pitch_map_deg = []\n");
    Scenario s = LoadScenario(path);
    s.walker.log_every = 0;
    const std::shared_ptr<const GaitLibrary> library = LoadGaitLibrary(s.pattern);
    return RunScenario(s, "fuzzy_cmac", library.get());
  }
  // The slowest gait's pragmatic rules at the trunk pitch q0_d (rad).
  RunOutput Rules(double q0_d) {
    const std::string path = Write(
        "rules.toml",
        "[simulation]\nduration = 14.0\n[controller]\ntype = \"pragmatic\"\n"
        "gait = \"" +
            std::string(RABBIT_SOURCE_DIR) +
            "/gaits/reference/vm_0.30.csv\"\nq0_d_deg = " + std::to_string(q0_d / kDeg) + "\n");
    return RunScenario(LoadScenario(path), "pragmatic", nullptr);
  }
  // The mean V_M of the steps from the 14th on.
  static double SettledSpeed(const RunOutput& run) {
    double sum = 0.0;
    int n = 0;
    for (size_t i = 14; i < run.steps.size(); ++i, ++n) sum += run.steps[i].step.v_m;
    EXPECT_GT(n, 8);
    return n > 0 ? sum / n : 0.0;
  }
};

TEST_F(SlopePerceptionTest, TouchdownHeightsWalkTheRulesSpeedOnFlatGround) {
  const RunOutput at_touchdown = Walker(true), loaded = Walker(false);
  ASSERT_EQ(at_touchdown.sim.outcome, Outcome::kCompleted) << at_touchdown.sim.reason;
  ASSERT_EQ(loaded.sim.outcome, Outcome::kCompleted) << loaded.sim.reason;
  ASSERT_GT(at_touchdown.steps.size(), 14u);
  const double q0_d = at_touchdown.steps.back().q0_d;  // held since the first update
  EXPECT_EQ(q0_d, loaded.steps.back().q0_d);
  const RunOutput rules = Rules(q0_d);
  ASSERT_EQ(rules.sim.outcome, Outcome::kCompleted) << rules.sim.reason;
  const double v_rules = SettledSpeed(rules);
  // Measured: 0.282 m/s for the rules, 0.283 with touchdown heights, 0.380 under load.
  EXPECT_NEAR(SettledSpeed(at_touchdown), v_rules, 0.015);
  EXPECT_GT(SettledSpeed(loaded), v_rules + 0.06);
}

TEST_F(SlopePerceptionTest, TheShippedWalkerReadsTheFeetUnderLoad) {
  // The shipped settings were tuned with the loaded reading (docs/design/slope.md, "Slope
  // adaptation").
  const Scenario s = LoadScenario(
      Write("w.toml", std::string("[simulation]\nduration = 1.0\n[velocity]\nvalue = "
                                  "0.6\n[controller]\ntype = \"fuzzy_cmac\"\ndatabase = \"") +
                          RABBIT_SOURCE_DIR + "/gaits\"\n"));
  EXPECT_FALSE(s.walker.slope.touchdown_heights);
}

}  // namespace
}  // namespace rabbit
