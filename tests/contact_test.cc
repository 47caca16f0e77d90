// Contact law (chapter eqs. 2-5 with the corrections of docs/design/model.md), its guards and
// transitions, and the terrain geometry.
#include "rabbit/contact/contact.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

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

// On a slope the contact law is the flat-ground law in the surface's frame. The reference: rotate
// the foot's position and velocity into the frame of the surface line (origin at a surface point
// P0, axes t = (cos a, -sin a), n = (sin a, cos a)), evaluate the flat law there (its anchor at the
// anchor point's tangential coordinate), and rotate the force back. Random states on two sloped
// segments of a profile (uphill and downhill), sticking and sliding.
TEST(ContactOnSlopeTest, ForceIsTheFlatLawInTheSurfaceFrame) {
  constexpr double kDeg = M_PI / 180.0;
  const ContactParams p;
  Terrain sloped;
  sloped.ground = GroundProfile({{-5.0, 0.0}, {0.5, -12.0 * kDeg}, {3.0, 7.0 * kDeg}});
  const Terrain flat;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double kForceTolerance = 1e-9;  // relative to the normal force's scale
  for (int trial = 0; trial < 400; ++trial) {
    const int segment = trial % 2 == 0 ? 2 : 3;
    const GroundSegment& g = sloped.ground.segment(segment);
    const double x_surface = segment == 2 ? 1.0 + 0.9 * (u(rng) + 1.0) : 3.2 + 2.0 * (u(rng) + 1.0);
    const Vec2 t(g.cos_slope, -g.sin_slope), n(g.sin_slope, g.cos_slope);
    const Vec2 p0(x_surface, g.HeightAt(x_surface));
    // A foot up to 3 mm inside, 1 mm along the surface from its anchor, moving.
    const double depth = 0.003 * (u(rng) + 1.0) / 2.0, along = 0.001 * u(rng);
    const Vec2 pos = p0 + along * t - depth * n;
    const Vec2 vel(0.2 * u(rng), 0.2 * u(rng));
    FootContactState on_slope;
    on_slope.segment = segment;
    on_slope.anchor_x = p0.x();  // anchored at P0
    on_slope.mode = trial % 4 < 2 ? ContactMode::kStick : ContactMode::kSlide;
    on_slope.slide_dir = u(rng) > 0.0 ? 1.0 : -1.0;
    FootContactState local = on_slope;
    local.segment = 0;
    local.anchor_x = 0.0;  // P0's tangential coordinate in the local frame
    const Vec2 pos_local((pos - p0).dot(t), (pos - p0).dot(n));
    const Vec2 vel_local(vel.dot(t), vel.dot(n));
    ASSERT_NEAR(pos_local.y(), -depth, 1e-15);
    const FootForce f = ComputeFootForce(p, sloped, on_slope, pos, vel);
    const FootForce ref = ComputeFootForce(p, flat, local, pos_local, vel_local);
    const double scale = std::max(1.0, ref.fn);
    EXPECT_NEAR(f.fn, ref.fn, kForceTolerance * scale) << trial;
    EXPECT_NEAR(f.ft, ref.ft, kForceTolerance * scale) << trial;
    const Vec2 world = ref.ft * t + ref.fn * n;
    EXPECT_NEAR(f.fx, world.x(), kForceTolerance * scale) << trial;
    EXPECT_NEAR(f.fy, world.y(), kForceTolerance * scale) << trial;
    EXPECT_NEAR(FootHeight(sloped, on_slope, pos), -depth, 1e-15);
    EXPECT_NEAR(SlipGuard(p, sloped, on_slope, pos, vel),
                SlipGuard(p, flat, local, pos_local, vel_local), kForceTolerance * scale);
    EXPECT_NEAR(ResumeGuard(p, sloped, on_slope, pos, vel),
                ResumeGuard(p, flat, local, pos_local, vel_local), kForceTolerance * scale);
    EXPECT_NEAR(ContactElasticEnergy(p, sloped, on_slope, pos),
                ContactElasticEnergy(p, flat, local, pos_local), 1e-12);
    // Slip stopping on the slope: the spring takes over the sliding force without a jump.
    if (on_slope.mode == ContactMode::kSlide) {
      FootContactState stuck = on_slope;
      OnFrictionEvent(p, sloped, pos, vel, &stuck);
      ASSERT_EQ(stuck.mode, ContactMode::kStick);
      // The anchor rule ignores lambda_t: compare the spring parts.
      const Vec2 still = Vec2::Zero();
      const double spring = ComputeFootForce(p, sloped, stuck, pos, still).ft;
      const double slide = -on_slope.slide_dir * p.lambda_g * f.fn - p.mu_g * vel.dot(t);
      EXPECT_NEAR(spring, slide, kForceTolerance * scale) << trial;
    }
  }
}

TEST(ContactOnSlopeTest, TouchdownSlipsAlongTheSurfaceAndSegmentsChangeAtBreakpoints) {
  constexpr double kDeg = M_PI / 180.0;
  Terrain t;
  // A ridge at x = 1: up 10 deg before it, down 10 deg after.
  t.ground = GroundProfile({{0.0, -10.0 * kDeg}, {1.0, 10.0 * kDeg}});
  const double ridge = std::tan(10.0 * kDeg);
  // Landing without speed along the surface: it sticks where it landed.
  const GroundSegment& up = t.ground.segment(1);
  FootContactState s;
  s.segment = 1;
  const Vec2 foot(0.5, up.HeightAt(0.5));
  OnTouchEvent(t, foot, Vec2::Zero(), &s);
  EXPECT_EQ(s.mode, ContactMode::kStick);
  EXPECT_EQ(s.anchor_x, 0.5);
  // Landing straight down on the uphill slope moves down it (toward -x): slide, direction -1.
  s = FootContactState{};
  s.segment = 1;
  OnTouchEvent(t, foot, Vec2(0.0, -0.3), &s);
  EXPECT_EQ(s.mode, ContactMode::kSlide);
  EXPECT_EQ(s.slide_dir, -1.0);
  // Segment guard: positive inside the segment, negative past the ridge.
  EXPECT_NEAR(SegmentGuard(t, s, Vec2(0.9, 0.0)), 0.1, 1e-12);
  EXPECT_LT(SegmentGuard(t, s, Vec2(1.001, 0.0)), 0.0);
  // A foot sliding over the ridge 1 mm deep is above the downhill side's line a little further
  // on: it leaves the ground there; 1 mm deep just past the ridge it stays in contact.
  s.mode = ContactMode::kSlide;
  EXPECT_TRUE(UpdateFootSurface(t, Vec2(1.0001, ridge - 0.001), &s));
  EXPECT_EQ(s.segment, 2);
  EXPECT_EQ(s.mode, ContactMode::kSlide);
  s.segment = 1;
  EXPECT_TRUE(UpdateFootSurface(t, Vec2(1.02, ridge - 0.001), &s));
  EXPECT_EQ(s.segment, 2);
  EXPECT_EQ(s.mode, ContactMode::kAir);
  // A sticking foot crossing the ridge keeps its spring's stretch (and so its friction force's
  // size): the anchor moves onto the downhill line.
  const ContactParams p;
  FootContactState stuck;
  stuck.mode = ContactMode::kStick;
  stuck.segment = 1;
  stuck.anchor_x = 0.9995;
  const Vec2 at(1.0002, ridge - 0.002), still = Vec2::Zero();
  const double before = ComputeFootForce(p, t, stuck, at, still).ft;
  EXPECT_TRUE(UpdateFootSurface(t, at, &stuck));
  EXPECT_EQ(stuck.segment, 2);
  EXPECT_EQ(stuck.mode, ContactMode::kStick);
  EXPECT_NEAR(ComputeFootForce(p, t, stuck, at, still).ft, before, 1e-9);
  // The initial state finds the segment and sticks a foot placed on the slope.
  const FootContactState start = InitialFootState(t, Vec2(1.5, t.GroundHeight(1.5)));
  EXPECT_EQ(start.segment, 2);
  EXPECT_EQ(start.mode, ContactMode::kStick);
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
