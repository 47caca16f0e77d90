// The walker's terrain-step handling (terrain_steps.h): the rise between two points and the next
// face against the ground profile's own heights, the knee angle that shortens a leg against the
// law of cosines, the slope reading levelled by a step, the lift's height over a step up, the
// planner's view of a face, the lean and the stance knee's ramps, the approach speed and the pitch
// hold after a crossing, nothing when disabled, invalid parameters refused, and the
// [controller.steps] keys read from a suite.
#include "rabbit/control/terrain_steps.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "rabbit/control/slope_adaptation.h"
#include "rabbit/scenario/scenario.h"
#include "rabbit/scenario/suite.h"
#include "suite_fixture.h"

namespace rabbit {
namespace {

constexpr double kTolerance = 1e-12;
constexpr double kL1 = 0.40, kL2 = 0.47;

Terrain Platform(double x_up, double x_down, double rise) {
  Terrain t;
  t.ground = GroundProfile({{x_up, 0.0, rise}, {x_down, 0.0, -rise}});
  return t;
}

TEST(TerrainStepsTest, RiseBetweenIsTheProfilesHeightDifference) {
  // A step up of 4 cm at 2 m, a step down of 1 cm at 3 m and a 2 deg ramp from 4 m: between two
  // points on flat pieces the rise is the difference of the profile's heights there.
  const GroundProfile g({{2.0, 0.0, 0.04}, {3.0, 0.0, -0.01}, {4.0, 2.0 * M_PI / 180.0, 0.0}});
  for (const auto& [a, b] : {std::pair{1.0, 2.5}, {2.5, 3.5}, {1.0, 3.9}, {3.5, 1.0}, {1.5, 1.9}}) {
    EXPECT_NEAR(RiseBetween(g, a, b), g.HeightAt(b) - g.HeightAt(a), kTolerance) << a << " " << b;
  }
  // On the ramp only the steps count.
  EXPECT_NEAR(RiseBetween(g, 1.0, 5.0), 0.03, kTolerance);
  // A point on the face belongs to the ground beyond it.
  EXPECT_NEAR(RiseBetween(g, 1.0, 2.0), 0.04, kTolerance);
}

TEST(TerrainStepsTest, StepInFindsTheFirstFaceInTheInterval) {
  const GroundProfile g({{2.0, 0.0, 0.04}, {2.5, 0.05, 0.0}, {3.0, 0.0, -0.01}});
  StepFace f = StepIn(g, 1.0, 4.0);
  EXPECT_TRUE(f.found);
  EXPECT_EQ(f.x, 2.0);
  EXPECT_EQ(f.rise, 0.04);
  f = StepIn(g, 2.0, 4.0);  // (x_lo, x_hi]: the face at 2 m is behind; the ramp is no step
  EXPECT_TRUE(f.found);
  EXPECT_EQ(f.x, 3.0);
  EXPECT_EQ(f.rise, -0.01);
  EXPECT_FALSE(StepIn(g, 3.0, 9.0).found);
}

TEST(TerrainStepsTest, KneeForShorteningMatchesTheLawOfCosines) {
  for (const double shorten : {0.0, 0.01, 0.025, 0.05}) {
    const double k = KneeForShortening(kL1, kL2, shorten);
    EXPECT_LE(k, 0.0);
    // The hip-foot distance of a leg with that knee angle.
    const double length = std::hypot(kL1 + kL2 * std::cos(k), kL2 * std::sin(k));
    EXPECT_NEAR(length, kL1 + kL2 - shorten, 1e-9) << shorten;
  }
}

TEST(TerrainStepsTest, SlopeReadingIgnoresAStep) {
  // A step down of 5 cm between the feet: without the levelling the slope adaptation reads a
  // downhill of atan(0.05 / 0.35); levelled, flat ground.
  Terrain t;
  t.ground = GroundProfile({{1.0, 0.0, -0.05}});
  TerrainStepParams p;
  p.enabled = true;
  const TerrainSteps steps(p);
  const Vec2 back(0.8, 0.0), landing(1.15, -0.05);
  EXPECT_NEAR(MeasuredGrade(landing, back, 0.1), std::atan(0.05 / 0.35), kTolerance);
  EXPECT_NEAR(MeasuredGrade(steps.LevelledLanding(t, landing, back), back, 0.1), 0.0, kTolerance);
  // Disabled: the landing as it is.
  const TerrainSteps off{TerrainStepParams()};
  EXPECT_EQ(off.LevelledLanding(t, landing, back), landing);
}

TEST(TerrainStepsTest, LiftOverAStepUp) {
  const Terrain t = Platform(2.0, 4.0, 0.03);
  TerrainStepParams p;
  p.enabled = true;
  TerrainSteps steps(p);
  // Feet at 1.4 and 1.75 m: the predicted landing 2.1 m is past the face, the lift is armed.
  steps.OnTouchdown(t, 1.0, Vec2(1.75, 0.0), Vec2(1.4, 0.0));
  ASSERT_TRUE(steps.LiftArmed());
  const double top = 0.03 + p.clearance;
  EXPECT_NEAR(steps.LiftHeight(t, 2.0 - p.lead), top, kTolerance);
  EXPECT_NEAR(steps.LiftHeight(t, 2.0 + p.trail), top, kTolerance);
  // Half way down the ramp in front of `lead`: half the height above the lower level.
  EXPECT_NEAR(steps.LiftHeight(t, 2.0 - p.lead - p.ramp / 2), top / 2, kTolerance);
  EXPECT_EQ(steps.LiftHeight(t, 2.0 - p.lead - p.ramp - 0.01),
            -std::numeric_limits<double>::infinity());
  // Feet far behind the face: nothing to lift over.
  steps.OnTouchdown(t, 2.0, Vec2(0.75, 0.0), Vec2(0.4, 0.0));
  EXPECT_FALSE(steps.LiftArmed());
  // The trailing leg: the face between the feet.
  steps.OnTouchdown(t, 3.0, Vec2(2.2, 0.03), Vec2(1.85, 0.0));
  EXPECT_TRUE(steps.LiftArmed());
}

TEST(TerrainStepsTest, PlannerSeesAFaceAsAnObstacle) {
  const Terrain t = Platform(2.0, 4.0, 0.03);
  TerrainStepParams p;
  p.enabled = true;
  const TerrainSteps steps(p);
  const double margin_before = 0.06, margin_after = 0.05;
  double length = -1.0;
  const double d = steps.FaceAhead(t, 1.0, 1.5, margin_before, margin_after, &length);
  // The planner's last foot (margin_before short of the near edge) lands face_before short of
  // the face; its step over (near edge + length + margin_after) face_after past it.
  EXPECT_NEAR(1.0 + d - margin_before, 2.0 - p.face_before, kTolerance);
  EXPECT_NEAR(1.0 + d + length + margin_after, 2.0 + p.face_after, kTolerance);
  // Beyond the horizon, or disabled: none.
  EXPECT_TRUE(std::isinf(steps.FaceAhead(t, 0.0, 1.5, margin_before, margin_after, &length)));
  const TerrainSteps off{TerrainStepParams()};
  EXPECT_TRUE(std::isinf(off.FaceAhead(t, 1.0, 1.5, margin_before, margin_after, &length)));
}

TEST(TerrainStepsTest, LeanAndStanceKneeRamps) {
  const Terrain t = Platform(2.0, 4.0, 0.04);
  TerrainStepParams p;
  p.enabled = true;
  p.up_lean = 5.0;
  p.down_lean = -3.0;
  p.lean_steps = 2;
  p.knee_share = 0.5;
  p.knee_ramp_s = 0.2;
  p.up_knee_share = 1.0;
  p.up_knee_ramp_s = 0.1;
  TerrainSteps steps(p);
  // The coming swing crosses the step up: the lean is up_lean times the rise, for two steps.
  steps.OnTouchdown(t, 1.0, Vec2(1.8, 0.0), Vec2(1.45, 0.0));
  EXPECT_NEAR(steps.TrunkOffset(), 5.0 * 0.04, kTolerance);
  EXPECT_EQ(steps.StanceKnee(1.05), 0.0);
  // Landed on the upper level: the stance knee starts flexed by the rise and extends linearly.
  steps.OnTouchdown(t, 1.6, Vec2(2.15, 0.04), Vec2(1.8, 0.0));
  const double k_up = KneeForShortening(kL1, kL2, 0.04);
  EXPECT_NEAR(steps.StanceKnee(1.6), k_up, kTolerance);
  EXPECT_NEAR(steps.StanceKnee(1.65), k_up / 2, kTolerance);
  EXPECT_EQ(steps.StanceKnee(1.8), 0.0);
  EXPECT_NEAR(steps.TrunkOffset(), 5.0 * 0.04, kTolerance);  // the second step of the lean
  steps.OnTouchdown(t, 2.2, Vec2(2.5, 0.04), Vec2(2.15, 0.04));
  EXPECT_EQ(steps.TrunkOffset(), 0.0);
  // Before the step down: the stance knee flexes to shorten the leg by half the drop.
  steps.OnTouchdown(t, 2.8, Vec2(3.8, 0.04), Vec2(3.45, 0.04));
  const double k_down = KneeForShortening(kL1, kL2, 0.02);
  EXPECT_EQ(steps.StanceKnee(2.8), 0.0);
  EXPECT_NEAR(steps.StanceKnee(2.9), k_down / 2, kTolerance);
  EXPECT_NEAR(steps.StanceKnee(3.5), k_down, kTolerance);
  EXPECT_NEAR(steps.TrunkOffset(), -3.0 * 0.04, kTolerance);
  // Disabled: nothing.
  TerrainSteps off{TerrainStepParams()};
  off.OnTouchdown(t, 1.0, Vec2(1.8, 0.0), Vec2(1.45, 0.0));
  EXPECT_FALSE(off.LiftArmed());
  EXPECT_EQ(off.TrunkOffset(), 0.0);
  EXPECT_EQ(off.StanceKnee(1.0), 0.0);
}

TEST(TerrainStepsTest, StanceKneeExtensionWaitsForTheHip) {
  const Terrain t = Platform(2.0, 4.0, 0.04);
  TerrainStepParams p;
  p.enabled = true;
  p.up_knee_share = 1.0;
  p.up_knee_ramp_s = 0.1;
  p.up_knee_by_hip = true;
  p.up_knee_at = -0.1;
  TerrainSteps steps(p);
  steps.OnTouchdown(t, 1.0, Vec2(1.8, 0.0), Vec2(1.45, 0.0));
  // Landed on the upper level at 2.15: the knee stays flexed while the hip is more than 0.1 m
  // behind the foot, however long that takes.
  steps.OnTouchdown(t, 1.6, Vec2(2.15, 0.04), Vec2(1.8, 0.0));
  const double k_up = KneeForShortening(kL1, kL2, 0.04);
  steps.Observe(1.6, 1.95);
  EXPECT_NEAR(steps.StanceKnee(1.6), k_up, kTolerance);
  steps.Observe(1.9, 2.04);
  EXPECT_NEAR(steps.StanceKnee(1.9), k_up, kTolerance);
  // The hip reaches 2.05 at 2.0 s: the extension runs over up_knee_ramp_s from there.
  steps.Observe(2.0, 2.05);
  EXPECT_NEAR(steps.StanceKnee(2.0), k_up, kTolerance);
  steps.Observe(2.05, 2.07);
  EXPECT_NEAR(steps.StanceKnee(2.05), k_up / 2, kTolerance);
  steps.Observe(2.1, 2.04);  // a hip back behind the gate does not restart it
  EXPECT_EQ(steps.StanceKnee(2.1), 0.0);
  // The next touchdown on the same level: no flexion.
  steps.OnTouchdown(t, 2.2, Vec2(2.5, 0.04), Vec2(2.15, 0.04));
  steps.Observe(2.2, 2.3);
  EXPECT_EQ(steps.StanceKnee(2.2), 0.0);
  // Without up_knee_by_hip the extension starts at the touchdown, wherever the hip is.
  p.up_knee_by_hip = false;
  TerrainSteps timed(p);
  timed.OnTouchdown(t, 1.6, Vec2(2.15, 0.04), Vec2(1.8, 0.0));
  timed.Observe(1.65, 1.9);
  EXPECT_NEAR(timed.StanceKnee(1.65), k_up / 2, kTolerance);
}

TEST(TerrainStepsTest, ApproachSpeedNearAFace) {
  const Terrain t = Platform(2.0, 4.0, 0.04);
  TerrainStepParams p;
  p.enabled = true;
  p.up_speed = 0.7;
  p.down_speed = 0.65;
  p.speed_before = 1.0;
  TerrainSteps steps(p);
  // Before the window: V_d itself, bit for bit.
  steps.OnTouchdown(t, 1.0, Vec2(0.5, 0.0), Vec2(0.15, 0.0));
  EXPECT_EQ(steps.SpeedCommand(0.42), 0.42);
  // The step up within speed_before of the front foot: up_speed in place of V_d, below or above.
  steps.OnTouchdown(t, 1.5, Vec2(1.2, 0.0), Vec2(0.85, 0.0));
  EXPECT_EQ(steps.SpeedCommand(0.42), 0.7);
  EXPECT_EQ(steps.SpeedCommand(0.8), 0.7);
  // Until the back foot has crossed it.
  steps.OnTouchdown(t, 2.0, Vec2(2.15, 0.04), Vec2(1.8, 0.0));
  EXPECT_EQ(steps.SpeedCommand(0.42), 0.7);
  steps.OnTouchdown(t, 2.5, Vec2(2.5, 0.04), Vec2(2.15, 0.04));
  EXPECT_EQ(steps.SpeedCommand(0.42), 0.42);
  // The step down within speed_before: down_speed.
  steps.OnTouchdown(t, 3.0, Vec2(3.2, 0.04), Vec2(2.85, 0.04));
  EXPECT_EQ(steps.SpeedCommand(0.42), 0.65);
  // Both faces in the window: the larger speed.
  const Terrain short_platform = Platform(2.0, 2.6, 0.04);
  steps.OnTouchdown(short_platform, 3.5, Vec2(1.5, 0.0), Vec2(1.15, 0.0));
  EXPECT_EQ(steps.SpeedCommand(0.42), 0.7);
  // No speed given for a step up (0), or disabled: V_d.
  p.up_speed = 0.0;
  TerrainSteps no_up(p);
  no_up.OnTouchdown(t, 1.5, Vec2(1.2, 0.0), Vec2(0.85, 0.0));
  EXPECT_EQ(no_up.SpeedCommand(0.42), 0.42);
  TerrainSteps off{TerrainStepParams()};
  off.OnTouchdown(t, 1.5, Vec2(1.2, 0.0), Vec2(0.85, 0.0));
  EXPECT_EQ(off.SpeedCommand(0.42), 0.42);
}

TEST(TerrainStepsTest, PitchHoldAfterACrossing) {
  const Terrain t = Platform(2.0, 9.0, 0.04);
  TerrainStepParams p;
  p.enabled = true;
  p.hold_steps = 2;
  TerrainSteps steps(p);
  steps.OnTouchdown(t, 1.0, Vec2(1.45, 0.0), Vec2(1.1, 0.0));
  steps.OnTouchdown(t, 1.5, Vec2(1.8, 0.0), Vec2(1.45, 0.0));
  EXPECT_FALSE(steps.HoldsPitch());
  // The step across (from 1.45 m) and the trailing leg's (from 1.8 m) cross the face; the hold
  // lasts hold_steps touchdowns from the last of them.
  steps.OnTouchdown(t, 2.0, Vec2(2.15, 0.04), Vec2(1.8, 0.0));
  EXPECT_TRUE(steps.HoldsPitch());
  steps.OnTouchdown(t, 2.5, Vec2(2.5, 0.04), Vec2(2.15, 0.04));
  EXPECT_TRUE(steps.HoldsPitch());
  steps.OnTouchdown(t, 3.0, Vec2(2.85, 0.04), Vec2(2.5, 0.04));
  EXPECT_TRUE(steps.HoldsPitch());
  steps.OnTouchdown(t, 3.5, Vec2(3.2, 0.04), Vec2(2.85, 0.04));
  EXPECT_FALSE(steps.HoldsPitch());
  // hold_steps = 0: never.
  p.hold_steps = 0;
  TerrainSteps none(p);
  none.OnTouchdown(t, 1.5, Vec2(1.8, 0.0), Vec2(1.45, 0.0));
  none.OnTouchdown(t, 2.0, Vec2(2.15, 0.04), Vec2(1.8, 0.0));
  EXPECT_FALSE(none.HoldsPitch());
}

TEST(TerrainStepsTest, InvalidParametersAreRefused) {
  std::string error;
  TerrainStepParams p;
  EXPECT_TRUE(p.IsValid(&error));
  p.clearance = -0.01;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("clearance"), std::string::npos);
  p = TerrainStepParams();
  p.knee_share = 1.5;
  EXPECT_FALSE(p.IsValid(&error));
  p = TerrainStepParams();
  p.up_lean = std::nan("");
  EXPECT_FALSE(p.IsValid(&error));
  p = TerrainStepParams();
  p.up_speed = -0.1;
  EXPECT_FALSE(p.IsValid(&error));
  p = TerrainStepParams();
  p.speed_before = 6.0;
  EXPECT_FALSE(p.IsValid(&error));
  p = TerrainStepParams();
  p.hold_steps = -1;
  EXPECT_FALSE(p.IsValid(&error));
  p = TerrainStepParams();
  p.up_knee_at = 1.5;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("up_knee_at"), std::string::npos);
}

class TerrainStepKeysTest : public testing::WalkerKeysTest {
 protected:
  TerrainStepKeysTest() : WalkerKeysTest("rabbit_terrain_steps_test", "steps") {}
};

TEST_F(TerrainStepKeysTest, KeysAreRead) {
  const Scenario s =
      LoadSuite(
          Write(
              "enabled = true\nclearance = 0.05\nup_lean = 6.0\nknee_share = 0.3\nlean_steps = 3\n"
              "placement = false\nup_speed = 0.75\ndown_speed = 0.6\nspeed_before = 3.0\n"
              "hold_steps = 3\nup_knee_by_hip = true\nup_knee_at = -0.1\n"))
          .scenarios[0];
  EXPECT_TRUE(s.walker.steps.enabled);
  EXPECT_EQ(s.walker.steps.clearance, 0.05);
  EXPECT_EQ(s.walker.steps.up_lean, 6.0);
  EXPECT_EQ(s.walker.steps.knee_share, 0.3);
  EXPECT_EQ(s.walker.steps.lean_steps, 3);
  EXPECT_FALSE(s.walker.steps.placement);
  EXPECT_EQ(s.walker.steps.up_speed, 0.75);
  EXPECT_EQ(s.walker.steps.down_speed, 0.6);
  EXPECT_EQ(s.walker.steps.speed_before, 3.0);
  EXPECT_EQ(s.walker.steps.hold_steps, 3);
  EXPECT_TRUE(s.walker.steps.up_knee_by_hip);
  EXPECT_EQ(s.walker.steps.up_knee_at, -0.1);
}

TEST_F(TerrainStepKeysTest, BadValueNamesItsKey) {
  ExpectError("knee_share = 2\n", "scenario[1].controller.steps.knee_share");
  ExpectError("no_such_key = 1\n", "scenario[1].controller.steps.no_such_key");
}

}  // namespace
}  // namespace rabbit
