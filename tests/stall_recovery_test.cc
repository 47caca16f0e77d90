// The walker's stall recovery (stall_recovery.h): the catch step's thigh angle against the
// capture point computed by hand; a push-off pulse starts only after hold_s below the speed in a
// split stance, has the documented strength profile and moves the references by the documented
// amounts; disabled, nothing happens; invalid parameters are refused.
#include "rabbit/control/stall_recovery.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "rabbit/model/model.h"

namespace rabbit {
namespace {

constexpr double kTolerance = 1e-12;
constexpr double kDt = 0.001;  // s, the control period

Observation At(double t, double xd, bool both_down) {
  Observation obs;
  obs.t = t;
  obs.q[kY] = 0.85;
  obs.q[kQ0] = 0.1;
  obs.qd[kX] = xd;
  obs.foot_contact = {true, both_down};
  return obs;
}

TEST(StallRecoveryTest, CatchAngleIsTheCapturePoint) {
  StallRecoveryParams p;
  p.catch_margin = 0.05;
  StallRecovery r(p);
  // x_cp - x_hip = xd sqrt(y / g) = -0.5 sqrt(0.85 / 9.81); 5 cm further back; leg 0.87 m.
  const double dx = -0.5 * std::sqrt(0.85 / 9.81) - 0.05;
  EXPECT_NEAR(r.CatchAngle(-0.5, 0.85), std::asin(dx / 0.87), kTolerance);
  // Clamped to catch_max.
  EXPECT_NEAR(r.CatchAngle(-5.0, 0.85), -p.catch_max, kTolerance);
}

TEST(StallRecoveryTest, PulseAfterHoldInASplitStance) {
  StallRecoveryParams p;
  p.enabled = true;
  p.hold_s = 0.25;
  p.pulse_s = 0.4;
  p.ramp_s = 0.05;
  p.push_off = 0.3;
  p.trunk_lean = 0.1;
  p.knee_dip = 0.25;
  StallRecovery r(p);
  // Slow, but one foot in the air: no pulse, however long.
  double t = 0.0;
  for (; t < 1.0; t += kDt) r.Observe(At(t, 0.0, false), true);
  EXPECT_EQ(r.pulses(), 0);
  // Both feet down and slow: the pulse starts hold_s later (within a period).
  const double slow_from = t;
  double started = -1.0;
  for (; t < 2.0 && started < 0.0; t += kDt) {
    r.Observe(At(t, 0.02, true), true);
    if (r.Active(t)) started = t;
  }
  ASSERT_EQ(r.pulses(), 1);
  EXPECT_NEAR(started - slow_from, p.hold_s, 1.5 * kDt);
  // Strength: ramps in over ramp_s, full in the middle, out over ramp_s, 0 after pulse_s.
  EXPECT_NEAR(r.Strength(started + 0.025), 0.5, 1e-9);
  EXPECT_NEAR(r.Strength(started + 0.2), 1.0, kTolerance);
  EXPECT_NEAR(r.Strength(started + 0.4 - 0.01), 0.2, 1e-9);
  EXPECT_EQ(r.Strength(started + 0.4 + kDt), 0.0);
  // At full strength: thigh reference back by push_off, knee straight, trunk forward.
  Eigen::Vector4d ref(0.2, -0.5, 1.0, -2.0);
  r.Apply(At(started + 0.2, 0.02, true), 0, &ref);
  EXPECT_NEAR(ref[0], 0.2 - 0.3, kTolerance);
  EXPECT_NEAR(ref[1], 0.0, kTolerance);
  EXPECT_NEAR(ref[2], 1.0, kTolerance);
  EXPECT_NEAR(ref[3], 0.0, kTolerance);
  EXPECT_NEAR(r.TrunkOffset(started + 0.2), 0.1, kTolerance);
  EXPECT_NEAR(r.StanceKnee(started + 0.2), -0.25, kTolerance);
  EXPECT_NEAR(r.StanceKnee(started + 0.025), -0.125, 1e-9);
  EXPECT_EQ(r.StanceKnee(started + 0.4 + kDt), 0.0);
  // Not armed (warm-up): no further pulse.
  for (t = started + 0.5; t < 3.0; t += kDt) r.Observe(At(t, 0.0, true), false);
  EXPECT_EQ(r.pulses(), 1);
}

TEST(StallRecoveryTest, CatchStepDrivesTheSwingWhileMovingBack) {
  StallRecoveryParams p;
  p.enabled = true;
  StallRecovery r(p);
  Observation obs = At(1.0, -0.4, false);  // swing leg 1 in the air, hip moving back
  r.Observe(obs, true);
  ASSERT_TRUE(r.Catching(obs, 0));
  Eigen::Vector4d ref(0.5, -0.8, 0.0, 0.0);
  r.Apply(obs, 0, &ref);
  // Hip joint = absolute thigh angle + trunk pitch; the knee flexed by catch_knee.
  EXPECT_NEAR(ref[0], r.CatchAngle(-0.4, 0.85) + 0.1, kTolerance);
  EXPECT_NEAR(ref[1], -p.catch_knee, kTolerance);
  // Slower than catch_speed: the pattern's references stay.
  obs.qd[kX] = -0.05;
  EXPECT_FALSE(r.Catching(obs, 0));
}

TEST(StallRecoveryTest, CatchStepUsesTheHipsHeightAboveTheLocalGround) {
  // The hip at y = 0.89 over a 4 cm step up: the pendulum's height is 0.85 m, as on flat ground
  // with the hip at 0.85 m.
  StallRecoveryParams p;
  p.enabled = true;
  StallRecovery r(p);
  Terrain terrain;
  terrain.ground = GroundProfile({{1.0, 0.0, 0.04}});
  Observation obs = At(1.0, -0.4, false);
  obs.q[kX] = 2.0;  // on the upper level, H = 0.04 m
  obs.q[kY] = 0.85 + 0.04;
  obs.terrain = &terrain;
  r.Observe(obs, true);
  ASSERT_TRUE(r.Catching(obs, 0));
  Eigen::Vector4d ref(0.5, -0.8, 0.0, 0.0);
  r.Apply(obs, 0, &ref);
  EXPECT_NEAR(ref[0], r.CatchAngle(-0.4, 0.85) + 0.1, kTolerance);
}

TEST(StallRecoveryTest, DisabledChangesNothing) {
  StallRecoveryParams p;  // enabled = false by default
  StallRecovery r(p);
  for (double t = 0.0; t < 2.0; t += kDt) r.Observe(At(t, -0.5, true), true);
  EXPECT_EQ(r.pulses(), 0);
  Observation obs = At(2.0, -0.5, false);
  EXPECT_FALSE(r.Catching(obs, 0));
  Eigen::Vector4d ref(0.2, -0.5, 1.0, -2.0);
  const Eigen::Vector4d before = ref;
  r.Apply(obs, 0, &ref);
  EXPECT_EQ(ref, before);
  EXPECT_EQ(r.TrunkOffset(2.0), 0.0);
  EXPECT_EQ(r.StanceKnee(2.0), 0.0);
}

TEST(StallRecoveryTest, InvalidParametersAreRefused) {
  std::string error;
  StallRecoveryParams p;
  EXPECT_TRUE(p.IsValid(&error));
  p.ramp_s = 0.3;  // more than half of pulse_s
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("ramp_s"), std::string::npos);
  p = StallRecoveryParams();
  p.catch_max = 2.0;
  EXPECT_FALSE(p.IsValid(&error));
  p = StallRecoveryParams();
  p.hold_s = std::nan("");
  EXPECT_FALSE(p.IsValid(&error));
}

}  // namespace
}  // namespace rabbit
