// The step planner's settings that follow the gait (FollowGait: the nominal step and the approach
// range from the walker's measured step) and the after-step-over settings, against hand-computed
// plans, and their keys in [controller.planner].
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "rabbit/control/step_planner.h"
#include "rabbit/io/error.h"
#include "rabbit/scenario/suite.h"

namespace rabbit {
namespace {

constexpr double kTolerance = 1e-12;

StepPlannerParams FollowParams() {
  StepPlannerParams p;
  p.enabled = true;
  p.horizon = 1.5;
  p.margin_before = 0.06;
  p.margin_after = 0.10;
  p.l_min = 0.28;
  p.l_max = 0.42;
  p.l_nominal = 0.36;
  p.l_over_max = 0.48;
  p.follow_gait = true;
  p.follow_shorten = 0.06;
  p.follow_lengthen = 0.04;
  return p;
}

TEST(FollowGaitTest, RangeAroundTheMeasuredStep) {
  // 0.45 m measured: [max(0.28, 0.39), min(0.48, 0.49)] = [0.39, 0.48], nominal 0.45.
  const StepPlannerParams f = FollowGait(FollowParams(), 0.45);
  EXPECT_NEAR(f.l_nominal, 0.45, kTolerance);
  EXPECT_NEAR(f.l_min, 0.39, kTolerance);
  EXPECT_NEAR(f.l_max, 0.48, kTolerance);
  // 0.30 m: [max(0.28, 0.24), min(0.48, 0.34)] = [0.28, 0.34].
  const StepPlannerParams s = FollowGait(FollowParams(), 0.30);
  EXPECT_NEAR(s.l_nominal, 0.30, kTolerance);
  EXPECT_NEAR(s.l_min, 0.28, kTolerance);
  EXPECT_NEAR(s.l_max, 0.34, kTolerance);
}

TEST(FollowGaitTest, MeasuredStepClampedIntoTheAbsoluteBounds) {
  // 0.60 m is above l_over_max: nominal 0.48, range [0.42, 0.48].
  const StepPlannerParams f = FollowGait(FollowParams(), 0.60);
  EXPECT_NEAR(f.l_nominal, 0.48, kTolerance);
  EXPECT_NEAR(f.l_min, 0.42, kTolerance);
  EXPECT_NEAR(f.l_max, 0.48, kTolerance);
  // 0.10 m is below l_min: nominal 0.28, range [0.28, 0.32].
  const StepPlannerParams s = FollowGait(FollowParams(), 0.10);
  EXPECT_NEAR(s.l_nominal, 0.28, kTolerance);
  EXPECT_NEAR(s.l_min, 0.28, kTolerance);
  EXPECT_NEAR(s.l_max, 0.32, kTolerance);
}

TEST(FollowGaitTest, OffOrUnmeasuredLeavesTheSettings) {
  StepPlannerParams p = FollowParams();
  const StepPlannerParams u = FollowGait(p, NAN);
  EXPECT_EQ(u.l_nominal, p.l_nominal);
  EXPECT_EQ(u.l_min, p.l_min);
  EXPECT_EQ(u.l_max, p.l_max);
  p.follow_gait = false;
  const StepPlannerParams o = FollowGait(p, 0.45);
  EXPECT_EQ(o.l_nominal, p.l_nominal);
  EXPECT_EQ(o.l_min, p.l_min);
  EXPECT_EQ(o.l_max, p.l_max);
}

TEST(FollowGaitTest, PlansAgainstHandComputedValues) {
  const StepPlannerParams p = FollowParams();
  // Fixed settings: 1.0 - 0.06 = 0.94 m is 3 x 0.3133 (2 x 0.47 exceeds l_max = 0.42).
  StepPlannerParams fixed = p;
  fixed.follow_gait = false;
  StepPlan plan = PlanStep(FollowGait(fixed, 0.45), 1.0, 0.2);
  EXPECT_EQ(plan.approach_steps, 3);
  EXPECT_NEAR(plan.step_length, 0.94 / 3, kTolerance);
  // A 0.45 m gait: 2 x 0.47 lies in [0.39, 0.48]; 3 x 0.3133 would be 0.077 short.
  plan = PlanStep(FollowGait(p, 0.45), 1.0, 0.2);
  EXPECT_EQ(plan.approach_steps, 2);
  EXPECT_NEAR(plan.step_length, 0.47, kTolerance);
  // A 0.30 m gait: 0.70 - 0.06 = 0.64 = 2 x 0.32, in [0.28, 0.34].
  plan = PlanStep(FollowGait(p, 0.30), 0.70, 0.2);
  EXPECT_EQ(plan.approach_steps, 2);
  EXPECT_NEAR(plan.step_length, 0.32, kTolerance);
  // The step over is the gait's business no more than before: d_obs + length + margin_after.
  plan = PlanStep(FollowGait(p, 0.45), 0.07, 0.2);
  EXPECT_EQ(plan.approach_steps, 0);
  EXPECT_NEAR(plan.step_length, 0.37, kTolerance);
}

TEST(FollowGaitTest, Validation) {
  std::string error;
  StepPlannerParams p = FollowParams();
  EXPECT_TRUE(p.IsValid(&error)) << error;
  p.follow_shorten = -0.01;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("planner.follow_shorten"), std::string::npos) << error;
  p = FollowParams();
  p.hold_pitch_steps = -1;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("hold_pitch_steps"), std::string::npos) << error;
}

class FollowKeysTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("rabbit_follow_keys_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string Write(const std::string& planner) {
    const std::string root = RABBIT_SOURCE_DIR;
    const std::string path = (dir_ / "suite.toml").string();
    std::ofstream(path) << "[suite]\nname = \"t\"\n[defaults.simulation]\nduration = 2.0\n"
                        << "[defaults.velocity]\nvalue = 0.6\n[defaults.controller]\n"
                        << "type = \"fuzzy_cmac\"\nfll = \"" << root
                        << "/gaits/gait_pattern.fll\"\nnetworks = \"" << root
                        << "/gaits/networks\"\ngaits = \"" << root << "/gaits/reference\"\n"
                        << "[defaults.controller.planner]\n"
                        << planner << "[[scenario]]\nname = \"a\"\n";
    return path;
  }
  std::filesystem::path dir_;
};

TEST_F(FollowKeysTest, ReadWithPresetDefaults) {
  const StepPlannerParams d = LoadSuite(Write("")).scenarios[0].walker.planner;
  EXPECT_FALSE(d.follow_gait);
  EXPECT_TRUE(d.over_feedback);
  EXPECT_EQ(d.hold_pitch_steps, 3);  // the adaptive preset's (walker_presets.cc)
  const StepPlannerParams r =
      LoadSuite(Write("follow_gait = true\nfollow_shorten = 0.08\nfollow_lengthen = 0.02\n"
                      "over_feedback = false\nhold_pitch_steps = 2\n"))
          .scenarios[0]
          .walker.planner;
  EXPECT_TRUE(r.follow_gait);
  EXPECT_DOUBLE_EQ(r.follow_shorten, 0.08);
  EXPECT_DOUBLE_EQ(r.follow_lengthen, 0.02);
  EXPECT_FALSE(r.over_feedback);
  EXPECT_EQ(r.hold_pitch_steps, 2);
  EXPECT_THROW(LoadSuite(Write("hold_pitch_steps = 101\n")), InputError);
  EXPECT_THROW(LoadSuite(Write("follow_shorten = -1.0\n")), InputError);
}

}  // namespace
}  // namespace rabbit
