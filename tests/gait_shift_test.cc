// The velocity control's gait shift (velocity_control.h): the split range against hand-computed
// steps (the effort below the q0_d floor shifts the FIS's velocity input, within its largest
// shift, and unwinds before the pitch leaves the floor), the command gate, the law unchanged bit
// for bit when off or gated, and the keys of [controller.velocity_control].
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "rabbit/control/velocity_control.h"
#include "rabbit/scenario/suite.h"
#include "suite_fixture.h"

namespace rabbit {
namespace {

constexpr double kTolerance = 1e-12;
constexpr double kFloor = -0.1, kCeiling = 0.45;

// Enabled, no feed-forward, no start at the map and no derivative: the law is K_P e alone.
VelocityControl Control(double gain, double max, double below, bool idle_windup = true) {
  VelocityControlParams p;
  p.idle_shift_windup = idle_windup;
  p.enabled = true;
  p.feedforward_gain = 0.0;
  p.start_at_map = false;
  p.gait_shift_gain = gain;
  p.gait_shift_max = max;
  p.gait_shift_below = below;
  return VelocityControl(p, 0.2, 0.0, kFloor, kCeiling, -0.09, PitchMap());
}

TEST(GaitShiftTest, SplitRangeByHand) {
  VelocityControl c = Control(4.0, 0.1, 0.4);
  c.Command(0.32);
  // Too fast by 0.1: u = -0.09 - 0.02 = -0.11; q0_d at the floor, 0.01 rad below it -> -0.04 m/s.
  EXPECT_NEAR(c.Update(0.42, 0.5), kFloor, kTolerance);
  EXPECT_NEAR(c.FisOffset(), -0.04, kTolerance);
  // Again: u = -0.13, held at the floor less 0.1 / 4 = 0.025 rad: the largest shift, -0.1 m/s.
  c.Command(0.32);
  EXPECT_NEAR(c.Update(0.42, 0.5), kFloor, kTolerance);
  EXPECT_NEAR(c.FisOffset(), -0.1, kTolerance);
  // Too slow by 0.1: u = -0.125 + 0.02 = -0.105: the shift unwinds first, the pitch stays.
  c.Command(0.32);
  EXPECT_NEAR(c.Update(0.22, 0.5), kFloor, kTolerance);
  EXPECT_NEAR(c.FisOffset(), -0.02, kTolerance);
  // Again: u = -0.085: no shift left, the pitch leaves the floor.
  c.Command(0.32);
  EXPECT_NEAR(c.Update(0.22, 0.5), -0.085, kTolerance);
  EXPECT_DOUBLE_EQ(c.FisOffset(), 0.0);
  // Nothing above the ceiling: the law clamps there as before.
  for (int i = 0; i < 40; ++i) {
    c.Command(0.32);
    c.Update(0.0, 0.5);
  }
  EXPECT_DOUBLE_EQ(c.q0_d(), kCeiling);
  EXPECT_DOUBLE_EQ(c.FisOffset(), 0.0);
}

// Idle (the walker's rule gait choice in its place) and without windup: the effort stops at the
// floor and the stored shift is dropped, so the pitch rises at the first update that asks for it;
// with windup (the default) the same updates unwind the effort first, as in SplitRangeByHand.
TEST(GaitShiftTest, AnIdleShiftWithoutWindupStopsAtTheFloor) {
  for (const bool windup : {true, false}) {
    VelocityControl c = Control(4.0, 0.1, 0.4, windup);
    c.Command(0.32);
    // Not idle: u = -0.11, the floor, a shift of 4 * -0.01 = -0.04 m/s either way.
    EXPECT_NEAR(c.Update(0.42, 0.5), kFloor, kTolerance);
    EXPECT_NEAR(c.FisOffset(), -0.04, kTolerance);
    c.SetShiftIdle(true);
    c.Command(0.32);
    EXPECT_NEAR(c.Update(0.42, 0.5), kFloor, kTolerance);
    // With windup u = -0.13 holds the largest shift; without, nothing is stored.
    EXPECT_NEAR(c.FisOffset(), windup ? -0.1 : 0.0, kTolerance) << windup;
    // Too slow by 0.1 (+0.02 rad): from u = -0.125 the pitch stays at the floor; from the floor
    // it rises to -0.08 at once.
    c.Command(0.32);
    EXPECT_NEAR(c.Update(0.22, 0.5), windup ? kFloor : kFloor + 0.02, kTolerance) << windup;
    // No longer idle, the shift works as before: too fast by 0.1 twice from -0.08 (windup off),
    // u = -0.1 then -0.12: a shift of -0.08 m/s.
    if (!windup) {
      c.SetShiftIdle(false);
      c.Command(0.32);
      EXPECT_NEAR(c.Update(0.42, 0.5), kFloor, kTolerance);
      c.Command(0.32);
      EXPECT_NEAR(c.Update(0.42, 0.5), kFloor, kTolerance);
      EXPECT_NEAR(c.FisOffset(), -0.08, kTolerance);
    }
  }
}

TEST(GaitShiftTest, NoShiftFromTheGateOn) {
  VelocityControl c = Control(4.0, 0.1, 0.4);
  c.Command(0.32);
  c.Update(0.42, 0.5);
  c.Command(0.32);
  c.Update(0.42, 0.5);
  ASSERT_NEAR(c.FisOffset(), -0.1, kTolerance);
  // The command reaches the gate (0.32 -> 0.42 -> 0.4, within the rate): the shift is cleared at
  // the next update and q0_d follows the law from the floor.
  EXPECT_NEAR(c.Command(0.4), 0.4, kTolerance);
  EXPECT_NEAR(c.Update(0.42, 0.5), kFloor, kTolerance);
  EXPECT_DOUBLE_EQ(c.FisOffset(), 0.0);
  EXPECT_NEAR(c.Update(0.3, 0.5), kFloor + 0.2 * 0.1, kTolerance);
}

// Off (gain 0), or gated (every command at or above gait_shift_below), the law is the one without
// the shift, bit for bit, and the FIS's input is not moved.
TEST(GaitShiftTest, OffOrGatedIsTheLawBitForBit) {
  const std::vector<double> v_d = {0.3, 0.3, 0.35, 0.5, 0.9, 0.9, 0.3, 0.3, 0.3, 0.45};
  const std::vector<double> v_m = {0.45, 0.5, 0.44, 0.3, 0.2, 0.35, 0.7, 0.5, 0.45, 0.4};
  auto run = [&](VelocityControl c, std::vector<double>* offsets) {
    std::vector<double> q;
    for (size_t i = 0; i < v_d.size(); ++i) {
      c.Command(v_d[i]);
      q.push_back(c.Update(v_m[i], 0.5));
      offsets->push_back(c.FisOffset());
    }
    return q;
  };
  std::vector<double> o_plain, o_off, o_gated, o_on;
  const std::vector<double> plain = run(Control(0.0, 0.1, 0.4), &o_plain);
  const std::vector<double> off = run(Control(0.0, 0.3, 3.0), &o_off);
  const std::vector<double> gated = run(Control(4.0, 0.1, 0.0), &o_gated);
  const std::vector<double> on = run(Control(4.0, 0.1, 0.4), &o_on);
  for (size_t i = 0; i < plain.size(); ++i) {
    EXPECT_EQ(off[i], plain[i]) << i;  // exactly
    EXPECT_EQ(gated[i], plain[i]) << i;
    EXPECT_EQ(o_off[i], 0.0) << i;
    EXPECT_EQ(o_gated[i], 0.0) << i;
  }
  // On, the same walk shifts the FIS's input (and so differs from the plain law).
  double lowest = 0.0;
  for (double o : o_on) lowest = std::min(lowest, o);
  EXPECT_LT(lowest, -0.05);
  EXPECT_NE(on, plain);
}

TEST(GaitShiftTest, ParamsValidation) {
  VelocityControlParams p;
  std::string error;
  EXPECT_DOUBLE_EQ(p.gait_shift_gain, 0.0);  // off by default
  p.gait_shift_gain = -1.0;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("gait_shift_gain"), std::string::npos);
  p = VelocityControlParams();
  p.gait_shift_max = std::nan("");
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("gait_shift_max"), std::string::npos);
  p = VelocityControlParams();
  p.gait_shift_below = 5.0;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("gait_shift_below"), std::string::npos);
}

class GaitShiftKeysTest : public testing::WalkerKeysTest {
 protected:
  GaitShiftKeysTest() : WalkerKeysTest("rabbit_gait_shift_test", "velocity_control") {}
};

TEST_F(GaitShiftKeysTest, ReadAndValidated) {
  const VelocityControlParams shipped = LoadSuite(Write("")).scenarios[0].walker.velocity_control;
  EXPECT_DOUBLE_EQ(shipped.gait_shift_gain, 2.0);  // the adaptive preset turns it on
  EXPECT_FALSE(shipped.idle_shift_windup);         // ... and off where the shift is idle
  EXPECT_TRUE(VelocityControlParams().idle_shift_windup);
  EXPECT_TRUE(LoadSuite(Write("idle_shift_windup = true\n"))
                  .scenarios[0]
                  .walker.velocity_control.idle_shift_windup);
  ExpectError("idle_shift_windup = 1\n",
              "scenario[1].controller.velocity_control.idle_shift_windup");
  const Suite suite =
      LoadSuite(Write("gait_shift_gain = 2.0\ngait_shift_max = 0.15\ngait_shift_below = 0.45\n"));
  const VelocityControlParams& v = suite.scenarios[0].walker.velocity_control;
  EXPECT_DOUBLE_EQ(v.gait_shift_gain, 2.0);
  EXPECT_DOUBLE_EQ(v.gait_shift_max, 0.15);
  EXPECT_DOUBLE_EQ(v.gait_shift_below, 0.45);
  ExpectError("gait_shift_gain = 11.0\n",
              "scenario[1].controller.velocity_control.gait_shift_gain");
  ExpectError("gait_shift_max = -0.1\n", "scenario[1].controller.velocity_control.gait_shift_max");
  ExpectError("gait_shift_below = 4.0\n",
              "scenario[1].controller.velocity_control.gait_shift_below");
}

}  // namespace
}  // namespace rabbit
