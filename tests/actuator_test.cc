// Actuator limits (chapter section 2): the torque/speed curve at points in each region.
#include "rabbit/contact/actuator.h"

#include <gtest/gtest.h>

namespace rabbit {
namespace {

const double kTolerance = 1e-12;

TEST(ActuatorTest, TorqueLimitInEachRegion) {
  const ActuatorParams p;
  // Region 1: up to 2000 rpm at the motor (4.189 rad/s at the joint): 1.5 N m x 50 = 75 N m.
  EXPECT_NEAR(TorqueLimit(p, 0.0), 75.0, kTolerance);
  EXPECT_NEAR(TorqueLimit(p, -3.0), 75.0, kTolerance);
  EXPECT_NEAR(TorqueLimit(p, 4.189), 75.0, kTolerance);
  // Region 2: constant power 315 W.
  EXPECT_NEAR(TorqueLimit(p, 5.0), 315.0 / 5.0, kTolerance);
  EXPECT_NEAR(TorqueLimit(p, -8.0), 315.0 / 8.0, kTolerance);
  EXPECT_NEAR(TorqueLimit(p, 8.378), 315.0 / 8.378, kTolerance);
  // Region 3: beyond 4000 rpm, no torque.
  EXPECT_EQ(TorqueLimit(p, 8.4), 0.0);
  EXPECT_EQ(TorqueLimit(p, -20.0), 0.0);
  // The curve is continuous at the first corner: 315 W / 4.189 rad/s = 75.2 N m >= 75 N m.
  EXPECT_NEAR(p.max_power / p.full_torque_speed, p.max_torque, 0.3);
}

TEST(ActuatorTest, SaturationKeepsSignAndReportsRegion) {
  const ActuatorParams p;
  SaturationRegion region;
  EXPECT_EQ(SaturateTorque(p, 50.0, 1.0, &region), 50.0);
  EXPECT_EQ(region, SaturationRegion::kNone);
  EXPECT_EQ(SaturateTorque(p, -120.0, 1.0, &region), -75.0);
  EXPECT_EQ(region, SaturationRegion::kTorque);
  EXPECT_NEAR(SaturateTorque(p, 100.0, -6.0, &region), 315.0 / 6.0, kTolerance);
  EXPECT_EQ(region, SaturationRegion::kPower);
  EXPECT_EQ(SaturateTorque(p, 10.0, 9.0, &region), 0.0);
  EXPECT_EQ(region, SaturationRegion::kSpeed);
  ActuatorParams off = p;
  off.enabled = false;
  EXPECT_EQ(SaturateTorque(off, 500.0, 20.0, &region), 500.0);
  EXPECT_EQ(region, SaturationRegion::kNone);
}

TEST(ActuatorTest, InvalidParametersRejected) {
  ActuatorParams p;
  p.max_speed = 1.0;  // below full_torque_speed
  std::string error;
  EXPECT_FALSE(p.IsValid(&error));
  p = ActuatorParams{};
  p.max_torque = -1.0;
  EXPECT_FALSE(p.IsValid(&error));
}

}  // namespace
}  // namespace rabbit
