// What the walker reads from the known terrain at a touchdown: the change of grade over the coming
// step against its closed form on a ramp, level ground, and the order in which the slope
// adaptation's and the step planner's speed commands stack.
#include <gtest/gtest.h>

#include <cmath>

#include "rabbit/control/terrain_command.h"

namespace rabbit {
namespace {

constexpr double kDeg = M_PI / 180.0;

TEST(TerrainCommandTest, GradeOverTheComingStep) {
  Terrain t;
  t.ground = GroundProfile({{2.0, 3.0 * kDeg, 0.0}});  // flat to 2 m, then 3 deg down
  // Feet on the flat, the coming step (0.4 m) reaches 0.3 m onto the ramp: the grade of the chord
  // from (1.9, 0) to (2.3, -0.3 tan 3 deg).
  const GradeView g = GradeAround(&t, Vec2(1.9, 0.0), Vec2(1.5, 0.0), 0.4);
  EXPECT_NEAR(g.change, std::atan(0.3 * std::tan(3.0 * kDeg) / 0.4), 1e-12);
  EXPECT_FALSE(g.level);
  // On the ramp, both feet: no change, not level.
  const double y = -std::tan(3.0 * kDeg);
  const GradeView r = GradeAround(&t, Vec2(3.5, 1.5 * y), Vec2(3.1, 1.1 * y), 0.4);
  EXPECT_NEAR(r.change, 0.0, 1e-12);
  EXPECT_FALSE(r.level);
  // Flat ahead and between: level. The step's length is clamped to [0.15, 0.6] m.
  EXPECT_TRUE(GradeAround(&t, Vec2(1.0, 0.0), Vec2(0.6, 0.0), 0.4).level);
  EXPECT_TRUE(GradeAround(&t, Vec2(1.0, 0.0), Vec2(0.6, 0.0), 5.0).level);  // 0.6 m: to 1.6
  EXPECT_TRUE(GradeAround(&t, Vec2(1.8, 0.0), Vec2(1.4, 0.0), 0.01).level);   // 0.15 m: to 1.95
  EXPECT_FALSE(GradeAround(&t, Vec2(1.9, 0.0), Vec2(1.5, 0.0), 0.01).level);  // 0.15 m: to 2.05
  // Without a terrain, or feet within 1 cm of each other: nothing known.
  const GradeView none = GradeAround(nullptr, Vec2(1.9, 0.0), Vec2(1.5, 0.0), 0.4);
  EXPECT_EQ(none.change, 0.0);
  EXPECT_TRUE(none.level);
  EXPECT_EQ(GradeAround(&t, Vec2(1.9, 0.0), Vec2(1.895, 0.0), 0.4).change, 0.0);
}

TEST(TerrainCommandTest, SpeedCommandsStackSlopeThenObstacle) {
  Terrain t;
  t.ground = GroundProfile({{4.0, 4.0 * kDeg, 0.0}});  // 4 deg down from 4 m
  t.obstacles.push_back({2.0, 0.2, 0.05});
  SlopeParams sp;
  sp.enabled = true;
  sp.downhill_brake = 3.0;
  sp.speed_lookahead = 1.0;
  const SlopeAdaptation slope(sp);
  StepPlannerParams pp;
  pp.enabled = true;
  pp.approach_speed = 0.7;
  pp.approach_distance = 2.5;
  const TerrainSteps steps{TerrainStepParams{}};
  // Near the obstacle on flat ground: raised to the approach speed, or V_d when faster.
  EXPECT_EQ(TerrainSpeedCommand(&t, slope, pp, steps, 0.5, Vec2(1.0, 0.0), Vec2(0.7, 0.0)), 0.7);
  EXPECT_EQ(TerrainSpeedCommand(&t, slope, pp, steps, 0.8, Vec2(1.0, 0.0), Vec2(0.7, 0.0)), 0.8);
  // Past the obstacle, the downhill within 1 m: the brake alone.
  EXPECT_DOUBLE_EQ(TerrainSpeedCommand(&t, slope, pp, steps, 0.8, Vec2(3.5, 0.0), Vec2(3.1, 0.0)),
                   0.8 - 3.0 * 4.0 * kDeg);
  // The planner off: the slope's command alone; no terrain: V_d.
  pp.enabled = false;
  EXPECT_EQ(TerrainSpeedCommand(&t, slope, pp, steps, 0.5, Vec2(1.0, 0.0), Vec2(0.7, 0.0)), 0.5);
  EXPECT_EQ(TerrainSpeedCommand(nullptr, slope, pp, steps, 0.5, Vec2(1.0, 0.0), Vec2(0.7, 0.0)),
            0.5);
}

}  // namespace
}  // namespace rabbit
