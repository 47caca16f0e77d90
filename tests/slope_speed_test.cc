// The slope adaptation's speed command ([controller.slope] uphill_boost, downhill_brake,
// speed_lookahead): the steepest grades of the ground profile ahead against their closed form,
// the command's law, nothing on flat pieces, the adaptive preset's values; on flat ground and
// between the levels of vertical steps the walk is the same bit for bit as without it; and a
// valley (a downhill into an uphill) that the walker without it stalls in is walked with it.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "cli_fixture.h"
#include "rabbit/control/slope_adaptation.h"
#include "rabbit/scenario/run.h"
#include "rabbit/scenario/scenario.h"

namespace rabbit {
namespace {

constexpr double kDeg = M_PI / 180.0;

TEST(SlopeSpeedTest, SteepestGradesOfThePiecesAhead) {
  // Flat to 2 m, 3 deg down to 4 m, 2 deg up to 5 m, then a vertical step onto a flat level.
  const GroundProfile ground({{2.0, 3.0 * kDeg, 0.0}, {4.0, -2.0 * kDeg, 0.0}, {5.0, 0.0, 0.04}});
  EXPECT_EQ(SteepestAhead(ground, 0.0, 1.5), std::make_pair(0.0, 0.0));
  EXPECT_EQ(SteepestAhead(ground, 1.5, 2.5), std::make_pair(0.0, 3.0 * kDeg));
  EXPECT_EQ(SteepestAhead(ground, 3.5, 4.5), std::make_pair(2.0 * kDeg, 3.0 * kDeg));
  EXPECT_EQ(SteepestAhead(ground, 4.2, 4.8), std::make_pair(2.0 * kDeg, 0.0));
  EXPECT_EQ(SteepestAhead(ground, 5.0, 9.0), std::make_pair(0.0, 0.0));  // the step's level
}

TEST(SlopeSpeedTest, CommandFollowsItsLaw) {
  const GroundProfile ground({{2.0, -4.0 * kDeg}, {6.0, 3.0 * kDeg}});
  SlopeParams p;
  p.enabled = true;
  p.uphill_boost = 1.5;
  p.downhill_brake = 2.0;
  p.speed_lookahead = 1.0;
  const SlopeAdaptation a(p);
  EXPECT_EQ(a.SpeedCommand(0.6, ground, 0.5), 0.6);                            // flat ahead
  EXPECT_DOUBLE_EQ(a.SpeedCommand(0.6, ground, 1.2), 0.6 + 1.5 * 4.0 * kDeg);  // uphill in reach
  EXPECT_DOUBLE_EQ(a.SpeedCommand(0.6, ground, 5.5),
                   0.6 + 1.5 * 4.0 * kDeg - 2.0 * 3.0 * kDeg);  // the valley: both
  EXPECT_DOUBLE_EQ(a.SpeedCommand(0.6, ground, 7.0), 0.6 - 2.0 * 3.0 * kDeg);
  // The brake stops at speed_floor, or at V_d when V_d is below it; the boost is not limited.
  p.downhill_brake = 6.0;  // 0.6 - 6 * 3 deg = 0.286 m/s
  p.speed_floor = 0.4;
  EXPECT_EQ(SlopeAdaptation(p).SpeedCommand(0.6, ground, 7.0), 0.4);
  EXPECT_EQ(SlopeAdaptation(p).SpeedCommand(0.35, ground, 7.0), 0.35);
  EXPECT_DOUBLE_EQ(SlopeAdaptation(p).SpeedCommand(0.6, ground, 1.2), 0.6 + 1.5 * 4.0 * kDeg);
  p.speed_floor = 0.0;
  p.downhill_brake = 2.0;
  p.speed_lookahead = 0.5;
  EXPECT_EQ(SlopeAdaptation(p).SpeedCommand(0.6, ground, 1.2), 0.6);  // out of reach
  // Zero gains, or the adaptation off: V_d itself.
  p.uphill_boost = p.downhill_brake = 0.0;
  EXPECT_EQ(SlopeAdaptation(p).SpeedCommand(0.6, ground, 5.5), 0.6);
  p.enabled = false;
  p.uphill_boost = p.downhill_brake = 1.0;
  EXPECT_EQ(SlopeAdaptation(p).SpeedCommand(0.6, ground, 5.5), 0.6);
  // Bounds.
  std::string error;
  p = SlopeParams();
  p.downhill_brake = -1.0;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("downhill_brake"), std::string::npos) << error;
}

class SlopeSpeedWalkTest : public testing::ScratchDirTest {
 protected:
  SlopeSpeedWalkTest() : ScratchDirTest("rabbit_slope_speed_test") {}
  Scenario Load(const std::string& terrain, const std::string& slope_keys, double duration) {
    const std::string path = ScratchDirTest::Write(
        "walk.toml", "[simulation]\nduration = " + std::to_string(duration) +
                         "\n[velocity]\nvalue = 0.6\n[terrain]\n" + terrain +
                         "[controller]\ntype = \"fuzzy_cmac\"\ndatabase = \"" + RABBIT_SOURCE_DIR +
                         "/gaits\"\n[controller.slope]\n" + slope_keys);
    Scenario s = LoadScenario(path);
    s.walker.log_every = 0;
    return s;
  }
  RunOutput Run(const std::string& terrain, const std::string& slope_keys, double duration) {
    const Scenario s = Load(terrain, slope_keys, duration);
    const std::shared_ptr<const GaitLibrary> library = LoadGaitLibrary(s.pattern);
    return RunScenario(s, "fuzzy_cmac", library.get());
  }
  static void ExpectSameWalk(const RunOutput& a, const RunOutput& b) {
    ASSERT_EQ(a.steps.size(), b.steps.size());
    ASSERT_GT(a.steps.size(), 10u);
    for (size_t i = 0; i < a.steps.size(); ++i) {
      EXPECT_EQ(a.steps[i].step.t_touchdown, b.steps[i].step.t_touchdown) << i;
      EXPECT_EQ(a.steps[i].step.x, b.steps[i].step.x) << i;
      EXPECT_EQ(a.steps[i].q0_d, b.steps[i].q0_d) << i;
    }
    EXPECT_EQ(a.sim.t_end, b.sim.t_end);
    EXPECT_TRUE(a.sim.last.q == b.sim.last.q);
  }
  static constexpr const char* kOff = "uphill_boost = 0\ndownhill_brake = 0\n";
};

TEST_F(SlopeSpeedWalkTest, TheAdaptivePresetSetsTheGains) {
  const Scenario s = Load("", "", 1.0);
  EXPECT_EQ(s.walker.slope.uphill_boost, 1.0);
  EXPECT_EQ(s.walker.slope.downhill_brake, 3.0);
  EXPECT_EQ(s.walker.slope.speed_floor, 0.4);
  EXPECT_EQ(s.walker.slope.speed_lookahead, 1.0);
  const Scenario read =
      Load("", "uphill_boost = 0.5\ndownhill_brake = 2\nspeed_lookahead = 0.7\n", 1.0);
  EXPECT_EQ(read.walker.slope.uphill_boost, 0.5);
  EXPECT_EQ(read.walker.slope.downhill_brake, 2.0);
  EXPECT_EQ(read.walker.slope.speed_lookahead, 0.7);
}

TEST_F(SlopeSpeedWalkTest, FlatGroundAndStepsAreUnchangedBitForBit) {
  ExpectSameWalk(Run("", kOff, 10.0), Run("", "", 10.0));
  const std::string steps =
      "steps = [{ x_start = 2.5, rise = 0.03 }, { x_start = 4.0, rise = -0.02 }]\n";
  ExpectSameWalk(Run(steps, kOff, 10.0), Run(steps, "", 10.0));
}

TEST_F(SlopeSpeedWalkTest, AValleyThatStalledIsWalked) {
  // Down 2.2 deg from 3.3 m, up 1.5 deg from 7.4 m, flat from 10.7 m (a training member of the
  // `slope` family): without the speed command the robot rolls back after its first step onto the
  // uphill; with it, it climbs the uphill to the flat.
  const std::string valley =
      "slopes = [{ x_start = 3.3, slope_deg = 2.2 }, { x_start = 7.4, slope_deg = -1.5 },"
      " { x_start = 10.7, slope_deg = 0.0 }]\n";
  const RunOutput off = Run(valley, kOff, 25.0), on = Run(valley, "", 25.0);
  EXPECT_EQ(off.sim.outcome, Outcome::kStalled) << off.sim.reason;
  EXPECT_LT(off.sim.last.q[kX], 8.5);
  EXPECT_EQ(on.sim.outcome, Outcome::kCompleted) << on.sim.reason;
  EXPECT_GT(on.sim.last.q[kX], 11.0);
}

}  // namespace
}  // namespace rabbit
