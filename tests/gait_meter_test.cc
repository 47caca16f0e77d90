// Gait measurement from contact sensors: steps, L_step, t_step and V_M (chapter eq. 1) on a
// scripted sequence of observations with known answers.
#include "rabbit/control/gait_meter.h"

#include <gtest/gtest.h>

namespace rabbit {
namespace {

Observation At(double t, bool c1, bool c2, double x1, double x2) {
  Observation o;
  o.t = t;
  o.foot_contact = {c1, c2};
  o.foot_pos = {Vec2(x1, 0.0), Vec2(x2, 0.0)};
  return o;
}

TEST(GaitMeterTest, MeasuresStepsFromContactSensors) {
  GaitMeter meter;
  const double kTolerance = 1e-12;
  EXPECT_FALSE(meter.Update(At(0.00, true, true, 0.0, -0.3)));
  EXPECT_FALSE(meter.Update(At(0.10, true, false, 0.0, -0.3)));  // leg 2 takes off at 0.10
  EXPECT_FALSE(meter.Update(At(0.30, true, false, 0.0, 0.10)));
  ASSERT_TRUE(meter.Update(At(0.50, true, true, 0.0, 0.32)));  // lands 0.32 ahead at 0.50
  EXPECT_EQ(meter.last_step().leg, 1);
  EXPECT_NEAR(meter.last_step().l_step, 0.32, kTolerance);
  EXPECT_NEAR(meter.last_step().t_step, 0.40, kTolerance);
  EXPECT_NEAR(meter.last_step().v_m, 0.8, kTolerance);
  EXPECT_FALSE(meter.Update(At(0.55, false, true, 0.0, 0.32)));  // leg 1 takes off at 0.55
  ASSERT_TRUE(meter.Update(At(0.90, true, true, 0.62, 0.32)));
  EXPECT_EQ(meter.last_step().index, 1);
  EXPECT_EQ(meter.last_step().leg, 0);
  EXPECT_NEAR(meter.last_step().l_step, 0.30, kTolerance);
  EXPECT_NEAR(meter.last_step().t_step, 0.35, kTolerance);
  EXPECT_EQ(meter.steps().size(), 2u);
}

TEST(GaitMeterTest, AStepBackwardHasANegativeLengthAndVelocity) {
  // Leg 2 starts 0.3 m ahead, lifts and lands 0.41 m behind leg 1: L_step = x_landing - x_other.
  GaitMeter meter;
  const double kTolerance = 1e-12;
  meter.Update(At(0.0, true, true, 0.0, 0.3));
  meter.Update(At(0.1, true, false, 0.0, 0.3));
  ASSERT_TRUE(meter.Update(At(0.6, true, true, 0.0, -0.41)));
  EXPECT_NEAR(meter.last_step().l_step, -0.41, kTolerance);
  EXPECT_NEAR(meter.last_step().t_step, 0.5, kTolerance);
  EXPECT_NEAR(meter.last_step().v_m, -0.82, kTolerance);
}

TEST(GaitMeterTest, RemembersEachFootsHeightAtItsOwnTouchdown) {
  // The slope perception's touchdown heights: a loaded foot sinks after it lands, and the record
  // keeps the height it landed at, not the one it has at the other foot's touchdown.
  GaitMeter meter;
  Observation o = At(0.0, true, true, 0.0, -0.3);
  meter.Update(o);
  EXPECT_EQ(meter.LastLanding(0), nullptr);
  EXPECT_EQ(meter.LastLanding(1), nullptr);
  o = At(0.1, true, false, 0.0, -0.3);
  meter.Update(o);
  o = At(0.5, true, true, 0.0, 0.3);
  o.foot_pos[1].y() = 0.010;  // lands 1 cm up
  ASSERT_TRUE(meter.Update(o));
  EXPECT_EQ(meter.last_step().y, 0.010);
  o = At(0.6, false, true, 0.0, 0.3);
  o.foot_pos[1].y() = 0.007;  // loaded, sunk 3 mm
  meter.Update(o);
  o = At(1.0, true, true, 0.6, 0.3);
  o.foot_pos[0].y() = 0.020;
  o.foot_pos[1].y() = 0.007;
  ASSERT_TRUE(meter.Update(o));
  ASSERT_NE(meter.LastLanding(1), nullptr);
  EXPECT_EQ(meter.LastLanding(1)->y, 0.010);
  EXPECT_EQ(meter.LastLanding(1)->index, 0);
  EXPECT_EQ(meter.LastLanding(0)->y, 0.020);
  EXPECT_EQ(meter.LastLanding(0), &meter.last_step());
  // Leg 2 lands again: its latest landing, not its first, is the one kept.
  o = At(1.1, true, false, 0.6, 0.3);
  meter.Update(o);
  o = At(1.5, true, true, 0.6, 0.9);
  o.foot_pos[1].y() = 0.030;
  ASSERT_TRUE(meter.Update(o));
  EXPECT_EQ(meter.LastLanding(1)->index, 2);
  EXPECT_EQ(meter.LastLanding(1)->y, 0.030);
  EXPECT_EQ(meter.LastLanding(0)->index, 1);
}

TEST(GaitMeterTest, FootInTheAirAtTheStartLandsWithoutAStepTime) {
  GaitMeter meter;
  meter.Update(At(0.0, true, false, 0.0, -0.3));  // leg 2 already in the air: take-off unseen
  ASSERT_TRUE(meter.Update(At(0.4, true, true, 0.0, 0.25)));
  EXPECT_EQ(meter.last_step().t_step, 0.0);
  EXPECT_EQ(meter.last_step().v_m, 0.0);
  EXPECT_NEAR(meter.last_step().l_step, 0.25, 1e-12);
}

TEST(GaitMeterTest, ContactFlickerIsNotAStep) {
  GaitMeter meter;
  meter.Update(At(0.0, true, true, 0.0, -0.3));
  meter.Update(At(0.01, true, false, 0.0, -0.3));
  // Back on the ground 20 ms later: shorter than min_air_time, a flicker.
  EXPECT_FALSE(meter.Update(At(0.03, true, true, 0.0, -0.3)));
  EXPECT_TRUE(meter.steps().empty());
}

}  // namespace
}  // namespace rabbit
