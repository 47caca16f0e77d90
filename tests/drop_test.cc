// The velocity control's drops (velocity_control.h): the rate of a drop and the speed from which
// it applies, the gap below the measured stride, the step down of the profile that starts a drop
// (a lower terrain command is none), no raise of q0_d after a decrease, the pitch floor at the
// new speed's pitch, the law unchanged bit for bit when off, and the keys of
// [controller.velocity_control].
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "rabbit/control/velocity_control.h"
#include "rabbit/scenario/suite.h"
#include "suite_fixture.h"

namespace rabbit {
namespace {

constexpr double kTolerance = 1e-12;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Enabled, rate 0.1 m/s per step, no feed-forward, no start at the map and no derivative.
VelocityControlParams Params() {
  VelocityControlParams p;
  p.enabled = true;
  p.v_d_rate = 0.1;
  p.feedforward_gain = 0.0;
  p.start_at_map = false;
  return p;
}

VelocityControl Control(const VelocityControlParams& p) {
  return VelocityControl(p, 0.2, 0.0, -0.1, 0.45, 0.0, PitchMap());
}

TEST(DropTest, RateAndWhereItApplies) {
  VelocityControlParams p = Params();
  p.v_d_rate_down = 0.3;
  p.v_d_rate_down_below = 0.75;
  VelocityControl c = Control(p);
  c.Command(0.9);
  EXPECT_NEAR(c.Command(0.3), 0.8, kTolerance);  // above 0.75 m/s: v_d_rate
  EXPECT_NEAR(c.Command(0.3), 0.7, kTolerance);
  EXPECT_NEAR(c.Command(0.3), 0.4, kTolerance);  // from 0.7 m/s: 0.3 per step
  EXPECT_NEAR(c.Command(0.3), 0.3, kTolerance);
  EXPECT_NEAR(c.Command(0.6), 0.4, kTolerance);  // a rise keeps v_d_rate
}

TEST(DropTest, GapBelowTheMeasuredStride) {
  VelocityControlParams p = Params();
  p.v_d_rate_down = 0.3;
  p.drop_gap = 0.2;
  VelocityControl c = Control(p);
  c.Command(0.7, 0.7);
  EXPECT_NEAR(c.Command(0.3, 0.68), 0.48, kTolerance);  // 0.4 by the rate, 0.48 by the stride
  EXPECT_NEAR(c.Command(0.3, 0.9), 0.48, kTolerance);   // never back up
  EXPECT_NEAR(c.Command(0.3, 0.5), 0.3, kTolerance);
}

TEST(DropTest, OnlyAStepDownOfTheProfileStartsADrop) {
  VelocityControlParams p = Params();
  p.v_d_rate_down = 0.3;
  p.drop_min = 0.15;
  VelocityControl c = Control(p);
  c.Command(0.7, kNaN, 0.7);
  // The terrain lowers the command, the profile stays: the rate is v_d_rate.
  EXPECT_NEAR(c.Command(0.3, kNaN, 0.7), 0.6, kTolerance);
  EXPECT_NEAR(c.Command(0.7, kNaN, 0.7), 0.7, kTolerance);
  // A step down of 0.1 m/s is no drop; one of 0.4 is.
  EXPECT_NEAR(c.Command(0.6, kNaN, 0.6), 0.6, kTolerance);
  EXPECT_NEAR(c.Command(0.2, kNaN, 0.2), 0.3, kTolerance);
  EXPECT_NEAR(c.Command(0.2, kNaN, 0.2), 0.2, kTolerance);
}

TEST(DropTest, NoRaiseAfterADecrease) {
  VelocityControlParams p = Params();
  p.v_d_rate = 0.0;  // no limit: V_c = V_d
  p.drop_no_raise = 2;
  VelocityControl c = Control(p);
  c.Command(0.6);
  EXPECT_NEAR(c.Update(0.6, 0.5), 0.0, kTolerance);
  c.Command(0.4);                                    // the decrease
  EXPECT_NEAR(c.Update(0.3, 0.5), 0.0, kTolerance);  // too slow by 0.1: no raise
  c.Command(0.4);
  EXPECT_NEAR(c.Update(0.5, 0.5), -0.02, kTolerance);  // too fast: lowered
  c.Command(0.4);
  EXPECT_NEAR(c.Update(0.3, 0.5), 0.0, kTolerance);  // two touchdowns on: raised again
}

// The pitch floor, against hand-computed updates of the law (K_P = 0.2, no derivative): in a
// drop to 0.5 m/s on a map whose pitch there is 0.05 rad less a margin of 0.01, the law's lean
// back stops at 0.04 rad for two touchdowns from the decrease of V_c, then goes on.
TEST(DropTest, PitchFloorAtTheNewSpeedsPitch) {
  VelocityControlParams p = Params();
  p.v_d_rate = 0.0;  // no limit: V_c = V_d
  p.drop_floor_steps = 2;
  p.drop_floor_margin = 0.01;
  VelocityControl c(p, 0.2, 0.0, -0.1, 0.45, 0.1, PitchMap({{0.4, 0.0}, {0.6, 0.1}}));
  c.Command(0.9);
  EXPECT_NEAR(c.Update(0.9, 0.5), 0.1, kTolerance);
  c.Command(0.5);                                     // the decrease: the floor is 0.04
  EXPECT_NEAR(c.Update(0.9, 0.5), 0.04, kTolerance);  // 0.1 - 0.2 * 0.4 = 0.02, held at 0.04
  c.Command(0.5);
  EXPECT_NEAR(c.Update(0.9, 0.5), 0.04, kTolerance);
  c.Command(0.5);  // two touchdowns on: the law alone, 0.04 - 0.08
  EXPECT_NEAR(c.Update(0.9, 0.5), -0.04, kTolerance);
  // A higher command since (a rise, an obstacle's approach speed) does not raise the floor: at
  // 0.7 m/s the map's 0.09 would lift the law's 0.04 + 0.2 (0.7 - 0.9) = 0; the drop's 0.04 holds.
  VelocityControl up(p, 0.2, 0.0, -0.1, 0.45, 0.1, PitchMap({{0.4, 0.0}, {0.6, 0.1}}));
  up.Command(0.9);
  up.Update(0.9, 0.5);
  up.Command(0.5);
  up.Update(0.9, 0.5);  // held at 0.04
  up.Command(0.7);
  EXPECT_NEAR(up.Update(0.9, 0.5), 0.04, kTolerance);
  // A floor above the range's ceiling stops at the ceiling.
  p.drop_floor_margin = -0.5;
  VelocityControl high(p, 0.2, 0.0, -0.1, 0.45, 0.1, PitchMap({{0.4, 0.0}, {0.6, 0.1}}));
  high.Command(0.9);
  high.Update(0.9, 0.5);
  high.Command(0.5);
  EXPECT_NEAR(high.Update(0.9, 0.5), 0.45, kTolerance);
  // Without a map there is no floor.
  p.drop_floor_margin = 0.0;
  VelocityControl none(p, 0.2, 0.0, -0.1, 0.45, 0.1, PitchMap());
  none.Command(0.9);
  none.Update(0.9, 0.5);
  none.Command(0.5);
  EXPECT_NEAR(none.Update(0.9, 0.5), 0.02, kTolerance);
}

TEST(DropTest, OffIsTheLawBitForBit) {
  VelocityControlParams on = Params();
  on.drop_min = 0.2;
  on.v_d_rate_down_below = 0.5;  // without v_d_rate_down, drop_gap and drop_no_raise: no effect
  on.drop_floor_margin = 0.02;   // nor with drop_floor_steps 0
  VelocityControl a = Control(Params()), b = Control(on);
  const double v_d[] = {0.9, 0.3, 0.3, 0.3, 0.8, 0.2, 0.2, 0.5};
  const double v_m[] = {0.9, 0.85, 0.6, 0.2, 0.3, 0.9, 0.4, 0.3};
  for (int i = 0; i < 8; ++i) {
    EXPECT_EQ(a.Command(v_d[i]), b.Command(v_d[i], v_m[i], v_d[i]));
    EXPECT_EQ(a.Update(v_m[i], 0.5), b.Update(v_m[i], 0.5));
  }
}

TEST(DropTest, Validated) {
  VelocityControlParams p;
  std::string error;
  p.v_d_rate_down = -0.1;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("v_d_rate_down"), std::string::npos);
  p = VelocityControlParams();
  p.drop_gap = kNaN;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("drop_gap"), std::string::npos);
  p = VelocityControlParams();
  p.drop_no_raise = -1;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("drop_no_raise"), std::string::npos);
  p = VelocityControlParams();
  p.drop_floor_steps = 101;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("drop_floor_steps"), std::string::npos);
  p = VelocityControlParams();
  p.drop_floor_margin = kNaN;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("drop_floor_margin_deg"), std::string::npos);
}

class DropKeysTest : public testing::WalkerKeysTest {
 protected:
  DropKeysTest() : WalkerKeysTest("rabbit_drop_test", "velocity_control") {}
};

TEST_F(DropKeysTest, ReadAndValidated) {
  const VelocityControlParams shipped = LoadSuite(Write("")).scenarios[0].walker.velocity_control;
  EXPECT_DOUBLE_EQ(shipped.v_d_rate_down, 0.18);  // the adaptive preset
  EXPECT_DOUBLE_EQ(shipped.v_d_rate_down_below, 0.75);
  EXPECT_DOUBLE_EQ(shipped.drop_gap, 0.55);
  EXPECT_EQ(shipped.drop_no_raise, 3);
  EXPECT_EQ(shipped.drop_floor_steps, 3);
  EXPECT_DOUBLE_EQ(shipped.drop_floor_margin, 0.0);
  const Suite suite = LoadSuite(
      Write("drop_min = 0.2\nv_d_rate_down = 0.25\nv_d_rate_down_below = 0.7\ndrop_gap = 0.3\n"
            "drop_no_raise = 4\ndrop_floor_steps = 5\ndrop_floor_margin_deg = 2.0\n"));
  const VelocityControlParams& v = suite.scenarios[0].walker.velocity_control;
  EXPECT_DOUBLE_EQ(v.drop_min, 0.2);
  EXPECT_DOUBLE_EQ(v.v_d_rate_down, 0.25);
  EXPECT_DOUBLE_EQ(v.v_d_rate_down_below, 0.7);
  EXPECT_DOUBLE_EQ(v.drop_gap, 0.3);
  EXPECT_EQ(v.drop_no_raise, 4);
  EXPECT_EQ(v.drop_floor_steps, 5);
  EXPECT_NEAR(v.drop_floor_margin, 2.0 * M_PI / 180.0, kTolerance);
  ExpectError("drop_gap = 4.0\n", "scenario[1].controller.velocity_control.drop_gap");
  ExpectError("drop_no_raise = 101\n", "scenario[1].controller.velocity_control.drop_no_raise");
  ExpectError("drop_floor_steps = -1\n",
              "scenario[1].controller.velocity_control.drop_floor_steps");
  ExpectError("drop_floor_margin_deg = 50.0\n",
              "scenario[1].controller.velocity_control.drop_floor_margin_deg");
}

}  // namespace
}  // namespace rabbit
