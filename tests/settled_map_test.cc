// The walker's settled pitch map (velocity_control.settled_pitch_map_deg, settled_start_clear,
// settled_feedforward_gain, settled_rise_extra): the first update and the feed-forward of the
// profile's rises and drops against hand-interpolated maps, the terrain's commands left on the
// pitch map, open level ground against hand-drawn terrains, the keys and the adaptive preset's
// values, and walks of the default walker whose first pitch after the warm-up is the settled
// map's on open ground and the gaits' near an obstacle.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "rabbit/control/terrain_command.h"
#include "rabbit/control/velocity_control.h"
#include "rabbit/control/walker_presets.h"
#include "rabbit/io/error.h"
#include "rabbit/scenario/run.h"
#include "rabbit/scenario/suite.h"
#include "suite_fixture.h"

namespace rabbit {
namespace {

constexpr double kTolerance = 1e-12;
constexpr double kDeg = M_PI / 180.0;

VelocityControlParams WithStartMap() {
  VelocityControlParams p;
  p.enabled = true;
  // Not monotone: made non-decreasing, 0.6 and 0.8 pool at 0.25.
  p.settled_pitch_map = {{0.4, 0.05}, {0.6, 0.3}, {0.8, 0.2}};
  return p;
}

TEST(SettledMapTest, TheFirstUpdateTakesTheStartMapWhereAsked) {
  const PitchMap map({{0.4, 0.0}, {0.8, 0.2}});
  VelocityControl c(WithStartMap(), 0.2, 0.1, -0.1, 0.45, 0.05, map);
  c.Command(0.5);
  c.UseStartMap(true);
  // S(0.5) = 0.05 + (0.25 - 0.05) / 2, not P(0.5) = 0.05.
  EXPECT_NEAR(c.Update(0.6, 0.5), 0.15, kTolerance);
  EXPECT_TRUE(c.started());
  // The feed-forward of a later change of V_c keeps P: 0.5 -> 0.6 adds 0.5 (P(0.6) - P(0.5)).
  c.Command(0.6);
  EXPECT_NEAR(c.Update(0.6, 0.5), 0.15 + 0.5 * 0.05, kTolerance);
}

TEST(SettledMapTest, NotAskedOrEmptyTheStartIsThePitchMap) {
  const PitchMap map({{0.4, 0.0}, {0.8, 0.2}});
  VelocityControl not_asked(WithStartMap(), 0.2, 0.1, -0.1, 0.45, 0.05, map);
  not_asked.Command(0.7);
  EXPECT_NEAR(not_asked.Update(0.6, 0.5), 0.15, kTolerance);  // P(0.7)
  VelocityControlParams none = WithStartMap();
  none.settled_pitch_map.clear();
  VelocityControl empty(none, 0.2, 0.1, -0.1, 0.45, 0.05, map);
  empty.Command(0.7);
  empty.UseStartMap(true);
  EXPECT_NEAR(empty.Update(0.6, 0.5), 0.15, kTolerance);
  // Clamped to the q0_d range like the pitch map's start: S(0.9) = 0.25, ceiling 0.2.
  VelocityControl clamped(WithStartMap(), 0.2, 0.1, -0.1, 0.2, 0.05, map);
  clamped.Command(0.9);
  clamped.UseStartMap(true);
  EXPECT_NEAR(clamped.Update(0.6, 0.5), 0.2, kTolerance);
}

TEST(SettledMapTest, TheProfilesRisesAndDropsLeanByTheSettledMap) {
  VelocityControlParams p = WithStartMap();  // S: 0.05, 0.25, 0.25 at 0.4, 0.6, 0.8
  p.v_d_rate = 0.1;
  p.feedforward_gain = 0.5;
  p.feedforward_rise_extra = 0.4;
  p.drop_min = 0.15;
  p.settled_feedforward_gain = 0.5;
  p.settled_rise_extra = 0.15;
  const PitchMap map({{0.4, 0.0}, {0.8, 0.2}});  // P
  // K_P = K_V = 0: q0_d moves by the feed-forward alone.
  VelocityControl c(p, 0.0, 0.0, -0.1, 0.45, 0.05, map);
  c.Command(0.4, 0.4, 0.4);
  EXPECT_NEAR(c.Update(0.4, 0.5), 0.0, kTolerance);  // P(0.4): the start not asked for S
  // The profile steps up to 0.6: V_c 0.4 -> 0.5, (0.5 + 0.15) (S(0.5) - S(0.4)) = 0.65 * 0.1.
  c.Command(0.6, 0.4, 0.6);
  EXPECT_NEAR(c.Update(0.4, 0.5), 0.065, kTolerance);
  // A terrain command above the profile (0.7 over 0.6): no rise, 0.5 (P(0.6) - P(0.5)).
  c.Command(0.7, 0.5, 0.6);
  EXPECT_NEAR(c.Update(0.5, 0.5), 0.065 + 0.025, kTolerance);
  // The profile drops to 0.3: V_c 0.6 -> 0.5, 0.5 (S(0.5) - S(0.6)) = -0.05.
  c.Command(0.3, 0.6, 0.3);
  EXPECT_NEAR(c.Update(0.6, 0.5), 0.09 - 0.05, kTolerance);
  // Off (gain 0): the same rise leans by (0.5 + 0.4) (P(0.5) - P(0.4)).
  p.settled_feedforward_gain = 0.0;
  VelocityControl off(p, 0.0, 0.0, -0.1, 0.45, 0.05, map);
  off.Command(0.4, 0.4, 0.4);
  off.Update(0.4, 0.5);
  off.Command(0.6, 0.4, 0.6);
  EXPECT_NEAR(off.Update(0.4, 0.5), 0.9 * 0.05, kTolerance);
}

TEST(SettledMapTest, ParamsValidation) {
  VelocityControlParams p = WithStartMap();
  std::string error;
  EXPECT_TRUE(p.IsValid(&error)) << error;
  p.settled_pitch_map.push_back({0.9, 50.0 * kDeg});
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("settled_pitch_map_deg"), std::string::npos) << error;
  p = VelocityControlParams();
  p.settled_start_clear = -0.5;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_EQ(error, "velocity_control.settled_start_clear must be in [0, 100] m");
  p.settled_start_clear = 100.0;
  EXPECT_TRUE(p.IsValid(&error));
}

TEST(SettledMapTest, OpenLevelGround) {
  EXPECT_TRUE(OpenLevelGround(nullptr, 1.0, 9.0));
  Terrain flat;
  EXPECT_TRUE(OpenLevelGround(&flat, 1.0, 9.0));
  Terrain obstacle;
  obstacle.obstacles = {{5.0, 0.2, 0.05}};
  EXPECT_TRUE(OpenLevelGround(&obstacle, 1.0, 4.99));
  EXPECT_FALSE(OpenLevelGround(&obstacle, 1.0, 5.0));
  EXPECT_FALSE(OpenLevelGround(&obstacle, 5.1, 6.0));  // standing on its top
  EXPECT_TRUE(OpenLevelGround(&obstacle, 5.3, 9.0));   // past it
  Terrain step;
  step.ground = GroundProfile({{4.0, 0.0, 0.03}});  // a 3 cm step up at 4 m
  EXPECT_TRUE(OpenLevelGround(&step, 1.0, 3.9));
  EXPECT_FALSE(OpenLevelGround(&step, 1.0, 4.1));
  EXPECT_TRUE(OpenLevelGround(&step, 4.1, 9.0));  // on the upper level
  Terrain ramp;
  ramp.ground = GroundProfile({{4.0, 3.0 * kDeg, 0.0}});
  EXPECT_FALSE(OpenLevelGround(&ramp, 1.0, 4.1));
  EXPECT_FALSE(OpenLevelGround(&ramp, 4.5, 5.0));  // on the ramp
}

TEST(SettledMapTest, TheAdaptivePresetStartsAtTheSettledMap) {
  const WalkerParams a = PresetWalkerParams(WalkerPreset::kAdaptive);
  ASSERT_EQ(a.velocity_control.settled_pitch_map.size(), 16u);
  EXPECT_DOUBLE_EQ(a.velocity_control.settled_pitch_map[10].first, 0.75);
  EXPECT_NEAR(a.velocity_control.settled_pitch_map[10].second / kDeg, 16.8, 1e-12);
  EXPECT_EQ(a.velocity_control.settled_start_clear, 8.0);
  EXPECT_EQ(a.velocity_control.settled_feedforward_gain, 0.5);
  EXPECT_EQ(a.velocity_control.settled_rise_extra, 0.15);
  std::string error;
  EXPECT_TRUE(a.velocity_control.IsValid(&error)) << error;
  // The chapter's walker: no velocity control, no start map.
  const WalkerParams c = PresetWalkerParams(WalkerPreset::kChapter);
  EXPECT_FALSE(c.velocity_control.enabled);
  EXPECT_TRUE(c.velocity_control.settled_pitch_map.empty());
  EXPECT_EQ(c.velocity_control.settled_feedforward_gain, 0.0);
}

class SettledMapKeysTest : public testing::WalkerKeysTest {
 protected:
  SettledMapKeysTest() : WalkerKeysTest("rabbit_settled_map_test", "velocity_control") {}
};

TEST_F(SettledMapKeysTest, ReadOverThePreset) {
  EXPECT_EQ(LoadSuite(Write("")).scenarios[0].walker.velocity_control.settled_pitch_map.size(),
            16u);
  const Suite suite = LoadSuite(
      Write("settled_pitch_map_deg = [[0.4, -2.0], [0.8, 18.0]]\nsettled_start_clear = 3.5\n"
            "settled_feedforward_gain = 0.3\nsettled_rise_extra = 0.2\n"));
  const VelocityControlParams& v = suite.scenarios[0].walker.velocity_control;
  ASSERT_EQ(v.settled_pitch_map.size(), 2u);
  EXPECT_NEAR(v.settled_pitch_map[0].second, -2.0 * kDeg, kTolerance);
  EXPECT_NEAR(v.settled_pitch_map[1].second, 18.0 * kDeg, kTolerance);
  EXPECT_DOUBLE_EQ(v.settled_start_clear, 3.5);
  EXPECT_DOUBLE_EQ(v.settled_feedforward_gain, 0.3);
  EXPECT_DOUBLE_EQ(v.settled_rise_extra, 0.2);
  // Written empty: no start map of its own.
  EXPECT_TRUE(LoadSuite(Write("settled_pitch_map_deg = []\n"))
                  .scenarios[0]
                  .walker.velocity_control.settled_pitch_map.empty());
  ExpectError("settled_pitch_map_deg = [[0.4, 60.0]]\n",
              "scenario[1].controller.velocity_control.settled_pitch_map_deg");
  ExpectError("settled_start_clear = -1.0\n",
              "scenario[1].controller.velocity_control.settled_start_clear");
}

// The default walker at 0.74 m/s: its q0_d after the warm-up is the start map's on flat ground and
// with an obstacle beyond 8 m, and the gaits' (the start map written empty) with one within 8 m.
class SettledMapWalkTest : public testing::SuiteFileTest {
 protected:
  SettledMapWalkTest() : SuiteFileTest("rabbit_settled_map_walk") {}
  // The first q0_d (rad) after the warm-up of each scenario.
  std::vector<double> FirstPitches(const std::string& scenarios) {
    const Suite suite = LoadSuite(
        Write(std::string("[suite]\nname = \"walk\"\n[defaults]\nexpect_outcome = \"completed\"\n"
                          "[defaults.simulation]\nduration = 5.0\nrecord_every = 50\n"
                          "[defaults.velocity]\nvalue = 0.74\n"
                          "[defaults.controller]\ntype = \"fuzzy_cmac\"\ndatabase = \"") +
              RABBIT_SOURCE_DIR + "/gaits\"\n" + scenarios));
    GaitLibraryCache cache;
    std::vector<double> first;
    for (const Scenario& s : suite.scenarios) {
      const RunOutput run = RunScenario(s, "fuzzy_cmac", cache.Get(s.pattern).get());
      double q = NAN;
      for (const StepRow& row : run.steps) {
        if (!row.warmup) {
          q = row.q0_d;
          break;
        }
      }
      first.push_back(q);
    }
    return first;
  }
};

TEST_F(SettledMapWalkTest, TheStartMapOnOpenGroundOnly) {
  const std::string obstacle_at_5 =
      "[[scenario.terrain.obstacles]]\nx_start = 5.0\nlength = 0.1\nheight = 0.03\n";
  const std::string obstacle_at_12 =
      "[[scenario.terrain.obstacles]]\nx_start = 12.0\nlength = 0.1\nheight = 0.03\n";
  const std::vector<double> q = FirstPitches(
      "[[scenario]]\nname = \"flat\"\n"
      "[[scenario]]\nname = \"far\"\n" +
      obstacle_at_12 + "[[scenario]]\nname = \"near\"\n" + obstacle_at_5 +
      "[[scenario]]\nname = \"flat_gaits\"\n"
      "[scenario.controller.velocity_control]\nsettled_pitch_map_deg = []\n");
  ASSERT_EQ(q.size(), 4u);
  // S(0.74) of the preset's map: 0.75 and 0.80 pool at 15.35 deg, 11.9 at 0.70.
  const double s = (11.9 + 0.8 * (15.35 - 11.9)) * kDeg;
  EXPECT_NEAR(q[0], s, 1e-9);
  EXPECT_NEAR(q[1], s, 1e-9);
  // Near the obstacle the gaits' map, as on flat ground without a start map; several degrees less.
  EXPECT_NEAR(q[2], q[3], kTolerance);
  EXPECT_LT(q[3], s - 3.0 * kDeg);
}

}  // namespace
}  // namespace rabbit
