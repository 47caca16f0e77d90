// Vertical steps of the ground profile ([[terrain.steps]]): the levels and the face
// (GroundProfile, Terrain), the contact transitions at a step (UpdateFootSurface), and the physics
// of the whole robot: standing on a platform's upper level, a foot sliding into a step's face (a
// trip), and feet running off a step down and landing on the lower level.
#include <gtest/gtest.h>

#include <cmath>

#include "rabbit/contact/contact.h"
#include "rabbit/contact/terrain.h"
#include "rabbit/control/basic_controllers.h"
#include "rabbit/model/model.h"
#include "rabbit/sim/simulator.h"
#include "sim_fixture.h"

namespace rabbit {
namespace {

using Vec2 = Eigen::Vector2d;

using testing::HoldAt;
using testing::Stance;

TEST(GroundStepsTest, LevelsFaceAndOutline) {
  // A 4 cm platform from 1 to 2 m on flat ground.
  const GroundProfile g({{1.0, 0.0, 0.04}, {2.0, 0.0, -0.04}});
  std::string error;
  ASSERT_TRUE(g.IsValid(&error)) << error;
  EXPECT_DOUBLE_EQ(g.HeightAt(0.0), 0.0);
  EXPECT_DOUBLE_EQ(g.HeightAt(0.999), 0.0);
  EXPECT_DOUBLE_EQ(g.HeightAt(1.0), 0.04);  // the breakpoint belongs to the new level
  EXPECT_DOUBLE_EQ(g.HeightAt(1.5), 0.04);
  EXPECT_DOUBLE_EQ(g.HeightAt(2.5), 0.0);
  EXPECT_TRUE(g.StepBetween(0, 1));
  EXPECT_TRUE(g.StepBetween(2, 1));
  const std::vector<Vec2> outline = g.Outline(0.0, 3.0);
  ASSERT_EQ(outline.size(), 6u);  // both ends and two points at each face
  EXPECT_EQ(outline[1], Vec2(1.0, 0.0));
  EXPECT_EQ(outline[2], Vec2(1.0, 0.04));
  EXPECT_EQ(outline[4], Vec2(2.0, 0.0));
  // A step at or behind 0: H(0) = 0 is the level before a step at 0, after one behind.
  EXPECT_DOUBLE_EQ(GroundProfile({{0.0, 0.0, 0.05}}).HeightAt(-0.1), 0.0);
  EXPECT_DOUBLE_EQ(GroundProfile({{0.0, 0.0, 0.05}}).HeightAt(0.1), 0.05);
  EXPECT_DOUBLE_EQ(GroundProfile({{-1.0, 0.0, 0.05}}).HeightAt(-2.0), -0.05);
  // On a slope, the step keeps the slope and shifts the level.
  const GroundProfile sloped({{0.0, -10.0 * M_PI / 180.0, 0.0}, {1.0, -10.0 * M_PI / 180.0, 0.03}});
  EXPECT_NEAR(sloped.HeightAt(1.0), std::tan(10.0 * M_PI / 180.0) + 0.03, 1e-12);
  EXPECT_FALSE(GroundProfile({{1.0, 0.0, 1.5}}).IsValid(&error));
  EXPECT_NE(error.find("rise"), std::string::npos) << error;
  // Obstacles stand on either level, not across a step.
  Terrain t;
  t.ground = g;
  t.obstacles = {{1.2, 0.2, 0.05}};
  EXPECT_TRUE(t.IsValid(&error)) << error;
  EXPECT_DOUBLE_EQ(t.ObstacleTop(0), 0.09);
  t.obstacles = {{0.9, 0.2, 0.05}};
  EXPECT_FALSE(t.IsValid(&error));
  // A link crossing the face below the upper level hits it; above it (or within the top margin
  // a foot standing at the edge may sink in) it does not.
  t.obstacles.clear();
  EXPECT_EQ(t.SegmentHitsStepFace(Vec2(0.95, 0.03), Vec2(1.05, 0.01), 0.0),
            0);  // y = 0.02 at x = 1
  EXPECT_EQ(t.SegmentHitsStepFace(Vec2(0.95, 0.05), Vec2(1.05, 0.04), 0.0), -1);  // 0.045
  EXPECT_EQ(t.SegmentHitsStepFace(Vec2(0.95, 0.04), Vec2(1.05, 0.03), 0.0), 0);   // 0.035
  EXPECT_EQ(t.SegmentHitsStepFace(Vec2(0.95, 0.04), Vec2(1.05, 0.03), 0.01), -1);
  EXPECT_EQ(t.SegmentHitsStepFace(Vec2(0.95, 0.03), Vec2(0.99, 0.01), 0.0), -1);  // short of it
  EXPECT_EQ(t.SegmentHitsStepFace(Vec2(2.05, 0.01), Vec2(1.95, 0.03), 0.0), 1);
}

TEST(GroundStepsTest, AFootCrossingAStepBelowTheLevelBeyondTrips) {
  Terrain t;
  t.ground = GroundProfile({{1.0, 0.0, 0.04}, {2.0, 0.0, -0.04}});
  // On the lower level, sliding into the face: a trip.
  FootContactState s = InitialFootState(t, Vec2(0.99, 0.0));
  ASSERT_EQ(s.mode, ContactMode::kStick);
  EXPECT_FALSE(UpdateFootSurface(t, Vec2(1.0001, -0.001), &s));
  // In the air above the upper level: onto it.
  FootContactState air = InitialFootState(t, Vec2(0.99, 0.06));
  EXPECT_TRUE(UpdateFootSurface(t, Vec2(1.0001, 0.05), &air));
  EXPECT_EQ(air.segment, 1);
  EXPECT_NEAR(FootHeight(t, air, Vec2(1.0001, 0.05)), 0.01, 1e-12);
  // Standing on the upper level, off its far edge: into the air over the lower level.
  FootContactState top = InitialFootState(t, Vec2(1.99, 0.04));
  ASSERT_EQ(top.mode, ContactMode::kStick);
  EXPECT_TRUE(UpdateFootSurface(t, Vec2(2.0001, 0.039), &top));
  EXPECT_EQ(top.mode, ContactMode::kAir);
  EXPECT_NEAR(FootHeight(t, top, Vec2(2.0001, 0.039)), 0.039, 1e-12);
  // Back onto the platform from beyond it, below its level: the face again.
  FootContactState behind = InitialFootState(t, Vec2(2.01, 0.0));
  EXPECT_FALSE(UpdateFootSurface(t, Vec2(1.999, 0.0), &behind));
}

class GroundStepsSimTest : public ::testing::Test {
 protected:
  SimSetup Setup(const Model& model, double duration) const {
    SimSetup setup;
    setup.model = &model;
    setup.options.duration = duration;
    return setup;
  }
};

// Dropped onto a 5 cm platform, both feet land on its top (not on the ground beside it) and the
// top carries the robot's weight.
TEST_F(GroundStepsSimTest, FeetRestOnTheUpperLevel) {
  const Model model{ModelParams{}};
  SimSetup setup = Setup(model, 1.5);
  const double kRise = 0.05;
  setup.terrain.ground = GroundProfile({{-0.6, 0.0, kRise}, {0.6, 0.0, -kRise}});
  // H(0) = 0 on the platform: the ground beside it is 5 cm lower.
  ASSERT_DOUBLE_EQ(setup.terrain.GroundHeight(-1.0), -kRise);
  const Vec7 q = Stance(model, 0.02);
  PdHoldController hold(HoldAt(q));
  const SimResult r = Simulate(setup, q, Vec7::Zero(), &hold);
  ASSERT_EQ(r.outcome, Outcome::kCompleted) << r.reason;
  ASSERT_FALSE(r.events.empty());
  EXPECT_NEAR(r.events.front().y, 0.0, 1e-9);  // touchdown located on the platform's top
  const SimSample& last = r.samples.back();
  double fy = 0.0;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    EXPECT_NEAR(last.foot_pos[leg].y(), 0.0, 0.005);
    EXPECT_NE(last.foot_mode[leg], ContactMode::kAir);
    fy += last.foot_force[leg].fy;
  }
  const double kWeightTolerance = 0.02;  // of the weight, what is left of the landing's bounce
  EXPECT_NEAR(fy, model.total_mass() * 9.81, kWeightTolerance * model.total_mass() * 9.81);
}

// A robot sliding forward on the lower level into a 5 cm step up: the front foot hits the face.
TEST_F(GroundStepsSimTest, AFootSlidingIntoTheFaceTrips) {
  const Model model{ModelParams{}};
  SimSetup setup = Setup(model, 1.0);
  const Vec7 q = Stance(model, 0.005);
  const double front_x = FootPosition(model, q, 0).x();
  setup.terrain.ground = GroundProfile({{front_x + 0.03, 0.0, 0.05}});
  Vec7 qd = Vec7::Zero();
  qd[kX] = 1.5;
  PdHoldController hold(HoldAt(q));
  const SimResult r = Simulate(setup, q, qd, &hold);
  EXPECT_EQ(r.outcome, Outcome::kTripped);
  EXPECT_NE(r.reason.find("step's face"), std::string::npos) << r.reason;
  // The same slide over a step down is no trip.
  setup.terrain.ground = GroundProfile({{front_x + 0.03, 0.0, -0.05}});
  setup.options.fall.enabled = false;
  PdHoldController hold_down(HoldAt(q));
  const SimResult down = Simulate(setup, q, qd, &hold_down);
  EXPECT_NE(down.outcome, Outcome::kTripped) << down.reason;
}

// Sliding forward over the edge of a 3 cm step down: each foot leaves the upper level at the edge
// (located by root finding) and lands on the lower level, which then carries the robot.
TEST_F(GroundStepsSimTest, FeetRunOffAStepDownAndLandBelow) {
  const Model model{ModelParams{}};
  SimSetup setup = Setup(model, 2.0);
  setup.options.fall.enabled = false;
  setup.contact.mu_s = 0.1;  // a slippery upper level: the robot slides off it
  setup.contact.lambda_g = 0.05;
  const double kRise = -0.03;
  const Vec7 q = Stance(model, 0.0);
  const double front_x = FootPosition(model, q, 0).x();
  const double edge = front_x + 0.02;
  setup.terrain.ground = GroundProfile({{edge, 0.0, kRise}});
  Vec7 qd = Vec7::Zero();
  qd[kX] = 0.8;
  PdHoldController hold(HoldAt(q));
  const SimResult r = Simulate(setup, q, qd, &hold);
  ASSERT_NE(r.outcome, Outcome::kTripped) << r.reason;
  int lift_offs = 0, landings = 0;
  for (const ContactEvent& e : r.events) {
    if (e.to == ContactMode::kAir && e.from != ContactMode::kAir && std::abs(e.x - edge) < 1e-6) {
      ++lift_offs;
      EXPECT_NEAR(e.y, 0.0, 0.005);  // on the upper level, sunk in a little
    }
    if (e.from == ContactMode::kAir && e.x > edge) {
      ++landings;
      EXPECT_NEAR(e.y, kRise, 1e-9) << "t = " << e.t;  // on the lower level
    }
  }
  EXPECT_GE(lift_offs, 1);
  EXPECT_GE(landings, 1);
  const SimSample& last = r.samples.back();
  for (int leg = 0; leg < kNumLegs; ++leg) {
    if (last.foot_pos[leg].x() > edge && last.foot_mode[leg] != ContactMode::kAir) {
      EXPECT_NEAR(last.foot_pos[leg].y(), kRise, 0.005) << "leg " << leg;
    }
  }
}

}  // namespace
}  // namespace rabbit
