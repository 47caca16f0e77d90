// Contact law (chapter eqs. 2-5 with DESIGN.md's corrections), its guards and transitions, and the
// terrain geometry.
#include "rabbit/contact/contact.h"

#include <gtest/gtest.h>

#include <cmath>

namespace rabbit {
namespace {

using Vec2 = Eigen::Vector2d;

const double kTolerance = 1e-9;

FootContactState Stick(double anchor) {
  FootContactState s;
  s.mode = ContactMode::kStick;
  s.anchor_x = anchor;
  return s;
}

TEST(ContactTest, NormalForceIsHuntCrossleyAndNeverPulls) {
  const ContactParams p;
  const Terrain flat;
  const FootContactState s = Stick(0.0);
  // 2 mm deep, sinking at 0.1 m/s: k |y| - lambda |y| yd = 1e5*0.002 + 1e6*0.002*0.1 = 400 N.
  EXPECT_NEAR(ComputeFootForce(p, flat, s, Vec2(0, -0.002), Vec2(0, -0.1)).fn, 400.0, kTolerance);
  // Rising fast enough, the damping would pull: clamped to 0.
  EXPECT_EQ(ComputeFootForce(p, flat, s, Vec2(0, -0.002), Vec2(0, 1.0)).fn, 0.0);
  // Above the ground: nothing.
  EXPECT_EQ(ComputeFootForce(p, flat, s, Vec2(0, 0.001), Vec2(0, -1.0)).fn, 0.0);
  // In the air mode: nothing at all.
  EXPECT_EQ(ComputeFootForce(p, flat, FootContactState{}, Vec2(0, -0.01), Vec2::Zero()).fn, 0.0);
}

TEST(ContactTest, StickingSpringRestoresTowardAnchor) {
  const ContactParams p;
  const Terrain flat;
  // 1 mm ahead of the anchor, moving forward at 0.01 m/s: -k_t dx - lambda_t xd = -100 - 20.
  const FootForce f = ComputeFootForce(p, flat, Stick(0.0), Vec2(0.001, -0.002), Vec2(0.01, 0));
  EXPECT_NEAR(f.ft, -120.0, kTolerance);
}

TEST(ContactTest, SlidingForceOpposesSlip) {
  const ContactParams p;
  const Terrain flat;
  FootContactState s;
  s.mode = ContactMode::kSlide;
  s.slide_dir = 1.0;
  const FootForce f = ComputeFootForce(p, flat, s, Vec2(0, -0.002), Vec2(0.5, 0));
  EXPECT_NEAR(f.ft, -p.lambda_g * f.fn - p.mu_g * 0.5, kTolerance);
}

TEST(ContactTest, TransitionsAndGuards) {
  const ContactParams p;
  const Terrain flat;
  FootContactState s;
  // Touchdown while moving: anchored at the impact point, sliding in the direction of motion.
  OnTouchEvent(Vec2(0.3, 0.0), Vec2(0.2, -0.5), &s);
  EXPECT_EQ(s.mode, ContactMode::kSlide);
  EXPECT_EQ(s.slide_dir, 1.0);
  EXPECT_GT(SlipGuard(p, flat, s, Vec2(0.3, -0.001), Vec2(0.2, 0)), 0.0);
  EXPECT_LT(SlipGuard(p, flat, s, Vec2(0.3, -0.001), Vec2(-0.01, 0)), 0.0);
  // Slow slip on a loaded foot: the resume guard turns negative.
  EXPECT_GT(ResumeGuard(p, flat, s, Vec2(0.3, -0.002), Vec2(0.2, 0)), 0.0);
  EXPECT_LT(ResumeGuard(p, flat, s, Vec2(0.3, -0.002), Vec2(0.001, 0)), 0.0);
  EXPECT_EQ(ResumeGuard(p, flat, Stick(0.0), Vec2(0.3, -0.002), Vec2(0.001, 0)), 1.0);
  // Slip stops: re-anchored so that the spring carries the sliding force, no jump.
  const Vec2 pos(0.31, -0.002), vel(0.0, 0.0);
  const double ft_slide = ComputeFootForce(p, flat, s, pos, vel).ft;
  OnFrictionEvent(p, flat, pos, vel, &s);
  EXPECT_EQ(s.mode, ContactMode::kStick);
  EXPECT_NEAR(ComputeFootForce(p, flat, s, pos, vel).ft, ft_slide, kTolerance);
  // ... and then sticks: |Ft| = lambda_g Fn < mu_s Fn.
  EXPECT_GT(SlipGuard(p, flat, s, pos, vel), 0.0);
  // Lift-off.
  EXPECT_GT(TouchGuard(flat, s, pos), 0.0);
  EXPECT_LT(TouchGuard(flat, s, Vec2(0.31, 0.001)), 0.0);
  OnTouchEvent(Vec2(0.31, 0.0), Vec2(0, 0.3), &s);
  EXPECT_EQ(s.mode, ContactMode::kAir);
}

TEST(ContactTest, StickGuardTurnsNegativeOutsideFrictionCone) {
  const ContactParams p;
  const Terrain flat;
  const FootContactState s = Stick(0.0);
  // Fn = 1e5 * 0.002 = 200 N; cone 160 N. 1 mm stretch: 100 N inside; 2 mm: 200 N outside.
  EXPECT_GT(SlipGuard(p, flat, s, Vec2(0.001, -0.002), Vec2::Zero()), 0.0);
  EXPECT_LT(SlipGuard(p, flat, s, Vec2(0.002, -0.002), Vec2::Zero()), 0.0);
}

TEST(TerrainTest, SurfacesAndSegments) {
  Terrain t;
  t.obstacles.push_back({1.0, 0.2, 0.05});
  std::string error;
  ASSERT_TRUE(t.IsValid(&error));
  EXPECT_EQ(t.SurfaceAt(0.5), kGround);
  EXPECT_EQ(t.SurfaceAt(1.1), 0);
  EXPECT_EQ(t.HeightAt(1.1), 0.05);
  EXPECT_NEAR(t.DistanceToNextObstacle(0.7), 0.3, kTolerance);
  EXPECT_TRUE(std::isinf(t.DistanceToNextObstacle(1.5)));
  // A shin crossing the obstacle's side below its top hits it; one above it does not.
  EXPECT_EQ(t.SegmentHitsObstacle(Vec2(0.9, 0.3), Vec2(1.05, 0.02), 0.0), 0);
  EXPECT_EQ(t.SegmentHitsObstacle(Vec2(0.9, 0.3), Vec2(1.05, 0.08), 0.0), -1);
  // A foot resting on the top (slight penetration) is not a hit with the margin.
  EXPECT_EQ(t.SegmentHitsObstacle(Vec2(1.1, 0.5), Vec2(1.1, 0.048), 0.01), -1);
  // Foot entering through the side is a trip; from above it lands on the top.
  FootContactState s;
  EXPECT_FALSE(UpdateFootSurface(t, Vec2(1.0001, 0.01), &s));
  EXPECT_TRUE(UpdateFootSurface(t, Vec2(1.0001, 0.07), &s));
  EXPECT_EQ(s.surface, 0);
  EXPECT_NEAR(FootHeight(t, s, Vec2(1.1, 0.06)), 0.01, kTolerance);
  // Leaving the top while in contact: back in the air above the ground.
  s.mode = ContactMode::kStick;
  EXPECT_TRUE(UpdateFootSurface(t, Vec2(1.2001, 0.049), &s));
  EXPECT_EQ(s.surface, kGround);
  EXPECT_EQ(s.mode, ContactMode::kAir);
}

TEST(TerrainTest, InvalidObstaclesRejected) {
  Terrain t;
  std::string error;
  t.obstacles = {{1.0, 0.2, -0.05}};
  EXPECT_FALSE(t.IsValid(&error));
  EXPECT_NE(error.find("height"), std::string::npos);
  t.obstacles = {{1.0, 0.5, 0.05}, {1.2, 0.2, 0.05}};
  EXPECT_FALSE(t.IsValid(&error));
}

}  // namespace
}  // namespace rabbit
