// The step planner's approach speed: the speed command near an obstacle against hand-worked
// cases (ApproachSpeed), its keys and the adaptive preset's value, and walks of training members
// that fall or trip when approached at their own low V_d and pass at the approach speed.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "rabbit/control/step_planner.h"
#include "rabbit/control/walker_presets.h"
#include "rabbit/io/error.h"
#include "rabbit/scenario/run.h"
#include "rabbit/scenario/suite.h"

namespace rabbit {
namespace {

StepPlannerParams Approach(double speed, double distance) {
  StepPlannerParams p;
  p.approach_speed = speed;
  p.approach_distance = distance;
  return p;
}

TEST(ApproachSpeedTest, RaisesTheCommandWhileAnObstacleIsNear) {
  const std::vector<Obstacle> one = {{4.0, 0.2, 0.05}};  // from x = 4.0 to 4.2 m
  const StepPlannerParams p = Approach(0.7, 2.5);
  // Near edge 2.5 m ahead of the front foot at most: raised; further: V_d.
  EXPECT_EQ(ApproachSpeed(p, one, 1.2, 1.5, 0.45), 0.7);
  EXPECT_EQ(ApproachSpeed(p, one, 1.1, 1.49, 0.45), 0.45);
  // Until the back foot is past the far edge.
  EXPECT_EQ(ApproachSpeed(p, one, 4.19, 4.5, 0.45), 0.7);
  EXPECT_EQ(ApproachSpeed(p, one, 4.2, 4.5, 0.45), 0.45);
  // A floor, not a set speed: a faster command is kept.
  EXPECT_EQ(ApproachSpeed(p, one, 3.0, 3.3, 0.8), 0.8);
  // Off, or no obstacle: V_d.
  EXPECT_EQ(ApproachSpeed(Approach(0.0, 2.5), one, 3.0, 3.3, 0.45), 0.45);
  EXPECT_EQ(ApproachSpeed(p, {}, 3.0, 3.3, 0.45), 0.45);
  // The second of two obstacles keeps it raised after the first is passed.
  const std::vector<Obstacle> two = {{4.0, 0.2, 0.05}, {6.0, 0.2, 0.05}};
  EXPECT_EQ(ApproachSpeed(p, two, 4.3, 4.6, 0.45), 0.7);
  EXPECT_EQ(ApproachSpeed(p, two, 6.3, 6.6, 0.45), 0.45);
}

TEST(ApproachSpeedTest, ValidationAndPresets) {
  std::string error;
  StepPlannerParams p;
  EXPECT_TRUE(p.IsValid(&error)) << error;
  EXPECT_EQ(p.approach_speed, 0.0);  // the planner as built in code: off
  p.approach_speed = -0.1;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("planner.approach_speed"), std::string::npos) << error;
  p = StepPlannerParams{};
  p.approach_distance = NAN;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("planner.approach_distance"), std::string::npos) << error;
  EXPECT_EQ(PresetWalkerParams(WalkerPreset::kAdaptive).planner.approach_speed, 0.7);
  EXPECT_EQ(PresetWalkerParams(WalkerPreset::kAdaptive).planner.approach_distance, 2.5);
  EXPECT_FALSE(PresetWalkerParams(WalkerPreset::kChapter).planner.enabled);
}

class ApproachWalkTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("rabbit_approach_speed_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

TEST_F(ApproachWalkTest, KeysAreRead) {
  const std::string root = RABBIT_SOURCE_DIR;
  auto load = [&](const std::string& planner) {
    const std::string path = (dir_ / "keys.toml").string();
    std::ofstream(path) << "[suite]\nname = \"t\"\n[defaults.simulation]\nduration = 2.0\n"
                        << "[defaults.velocity]\nvalue = 0.6\n"
                        << "[defaults.controller]\ntype = \"fuzzy_cmac\"\ndatabase = \"" << root
                        << "/gaits\"\n[defaults.controller.planner]\n"
                        << planner << "[[scenario]]\nname = \"a\"\n";
    return LoadSuite(path).scenarios[0].walker.planner;
  };
  EXPECT_EQ(load("").approach_speed, 0.7);  // the adaptive preset's
  const StepPlannerParams r = load("approach_speed = 0.55\napproach_distance = 3.0\n");
  EXPECT_DOUBLE_EQ(r.approach_speed, 0.55);
  EXPECT_DOUBLE_EQ(r.approach_distance, 3.0);
  EXPECT_THROW(load("approach_speed = 3.0\n"), InputError);
}

TEST_F(ApproachWalkTest, SlowApproachesThatFailedPassAtTheApproachSpeed) {
  struct Case {
    const char *x_start, *length, *height, *v_d;  // as drawn
  };
  // Training members obstacle-022 and obstacle-038 of scenarios/train/obstacles.toml: without
  // the approach speed the first falls after its step over, the second trips.
  const Case cases[] = {
      {"4.385737514395947", "0.0923324411467565", "0.017143000579822924", "0.4092708122414971"},
      {"3.770240250846941", "0.18038432047568925", "0.06701013485627487", "0.4964885483196304"}};
  const std::string root = RABBIT_SOURCE_DIR;
  std::string text =
      "[suite]\nname = \"walk\"\n[defaults]\nexpect_outcome = \"completed\"\n"
      "[defaults.simulation]\ndistance = 9.0\nduration = 40.0\nrecord_every = 50\n"
      "[defaults.controller]\ntype = \"fuzzy_cmac\"\ndatabase = \"" +
      root +
      "/gaits\"\n[defaults.criteria]\nmin_steps_after_obstacles = 10\n"
      "allow_obstacle_contact = false\n";
  int i = 0;
  for (const Case& c : cases) {
    text += "[[scenario]]\nname = \"o" + std::to_string(i++) +
            "\"\n[scenario.velocity]\nvalue = " + c.v_d +
            "\n[[scenario.terrain.obstacles]]\nx_start = " + c.x_start + "\nlength = " + c.length +
            "\nheight = " + c.height + "\n";
  }
  const std::string path = (dir_ / "walk.toml").string();
  std::ofstream(path) << text;
  const Suite suite = LoadSuite(path);
  GaitLibraryCache cache;
  for (const Scenario& s : suite.scenarios) {
    const auto library = cache.Get(s.pattern);
    const RunOutput with = RunScenario(s, "fuzzy_cmac", library.get());
    EXPECT_TRUE(with.passed) << s.name << ": " << (with.failures.empty() ? "" : with.failures[0]);
    Scenario off = s;
    off.walker.planner.approach_speed = 0.0;
    const RunOutput without = RunScenario(off, "fuzzy_cmac", library.get());
    EXPECT_FALSE(without.passed) << s.name;
  }
}

}  // namespace
}  // namespace rabbit
