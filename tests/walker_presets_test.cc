// Walker presets: a scenario naming only the walker gets the adaptive preset; `preset = "chapter"`
// and the baseline "chapter" read the scenario's keys over the chapter's settings; bad names are
// refused naming the file and key; the adaptive walker leans back further for a step down.
#include "rabbit/control/walker_presets.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "rabbit/control/terrain_steps.h"
#include "rabbit/io/error.h"
#include "rabbit/scenario/run.h"
#include "rabbit/scenario/scenario.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

class WalkerPresetsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rabbit_walker_presets_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // A walker scenario on the shipped database with `controller` lines added to [controller].
  std::string Write(const std::string& controller) {
    const std::string path = (dir_ / "walk.toml").string();
    std::ofstream(path) << "[simulation]\nduration = 1.0\n[velocity]\nvalue = 0.6\n"
                        << "[controller]\ntype = \"fuzzy_cmac\"\ndatabase = \"" << RABBIT_SOURCE_DIR
                        << "/gaits\"\n"  // line 7: the next line is 8
                        << controller;
    return path;
  }
  fs::path dir_;
};

TEST(WalkerPresets, NamesRoundTripAndUnknownNamesAreRefused) {
  for (WalkerPreset p : {WalkerPreset::kAdaptive, WalkerPreset::kChapter}) {
    WalkerPreset back = WalkerPreset::kAdaptive;
    ASSERT_TRUE(ParseWalkerPreset(WalkerPresetName(p), &back));
    EXPECT_EQ(back, p);
  }
  WalkerPreset p = WalkerPreset::kChapter;
  EXPECT_FALSE(ParseWalkerPreset("Chapter", &p));
  EXPECT_FALSE(ParseWalkerPreset("", &p));
  EXPECT_EQ(p, WalkerPreset::kChapter);  // unchanged on failure
}

TEST(WalkerPresets, TheChapterDiffersFromTheAdaptiveWalkerOnlyWhereDocumented) {
  const WalkerParams a = PresetWalkerParams(WalkerPreset::kAdaptive);
  const WalkerParams c = PresetWalkerParams(WalkerPreset::kChapter);
  EXPECT_TRUE(a.planner.enabled);
  EXPECT_FALSE(c.planner.enabled);
  EXPECT_TRUE(a.slope.enabled);
  EXPECT_FALSE(c.slope.enabled);
  EXPECT_TRUE(a.velocity_control.enabled);
  EXPECT_FALSE(c.velocity_control.enabled);
  EXPECT_FALSE(a.stall_recovery.enabled);
  EXPECT_FALSE(c.stall_recovery.enabled);
  EXPECT_FALSE(a.lift.keeps_rules);
  EXPECT_TRUE(c.lift.keeps_rules);
  EXPECT_EQ(a.fis_v_lead, 1.0);
  EXPECT_EQ(c.fis_v_lead, 1.0);
  // Everything else is shared: the PD gains, the velocity control, the push recovery.
  EXPECT_EQ(a.k_p, c.k_p);
  EXPECT_EQ(a.k_v, c.k_v);
  EXPECT_EQ(a.hip_kp, c.hip_kp);
  EXPECT_EQ(a.recovery.enabled, c.recovery.enabled);
  EXPECT_EQ(a.q0_d_min, -0.10);
  EXPECT_EQ(a.q0_d_max, 0.45);
  EXPECT_NEAR(c.q0_d_min * 180.0 / M_PI, -5.7, 1e-12);
  EXPECT_NEAR(c.q0_d_max * 180.0 / M_PI, 25.8, 1e-12);
  std::string error;
  EXPECT_TRUE(a.IsValid(&error)) << error;
  EXPECT_TRUE(c.IsValid(&error)) << error;
}

TEST(WalkerPresets, TheAdaptiveWalkerStepsOverLowerAndShorter) {
  const WalkerParams a = PresetWalkerParams(WalkerPreset::kAdaptive);
  const WalkerParams c = PresetWalkerParams(WalkerPreset::kChapter);
  EXPECT_EQ(a.lift.clearance, 0.05);
  EXPECT_EQ(a.lift.height_gain, 0.8);
  EXPECT_EQ(c.lift.height_gain, 0.0);
  EXPECT_EQ(a.lift.trailing_clearance, 0.04);
  EXPECT_EQ(c.lift.trailing_clearance, 0.0);
  EXPECT_EQ(a.planner.over_lift_release, 0.02);
  EXPECT_EQ(a.planner.l_over_max, 0.45);
  // The lift is at full height from 0.15 m before the near edge, ramped in over the 0.10 m
  // before that; the chapter's walker keeps the library's 0.10 m.
  EXPECT_EQ(a.lift.lead, 0.15);
  EXPECT_EQ(c.lift.lead, FootLiftParams().lead);
  const Obstacle o{2.0, 0.2, 0.05};
  EXPECT_EQ(LiftRamp(a.lift, o, 0.02, 0.02, 2.0 - 0.15), 1.0);
  EXPECT_NEAR(LiftRamp(a.lift, o, 0.02, 0.02, 2.0 - 0.20), 0.5, 1e-12);
  EXPECT_EQ(LiftRamp(a.lift, o, 0.02, 0.02, 2.0 - 0.26), 0.0);
  EXPECT_NEAR(LiftRamp(c.lift, o, 0.02, 0.02, 2.0 - 0.15), 0.5, 1e-12);
  // The chapter's walker keeps the library's lift (its planner is off).
  EXPECT_EQ(c.lift.clearance, FootLiftParams().clearance);
  EXPECT_EQ(c.planner.over_lift_release, StepPlannerParams().over_lift_release);
  EXPECT_EQ(c.planner.l_over_max, StepPlannerParams().l_over_max);
  std::string error;
  EXPECT_TRUE(a.IsValid(&error)) << error;
}

// The adaptive walker asks for approach steps of at most 0.40 m (the library 0.45 m): 0.55 m
// before a near edge leaves 0.49 m to the last foot, which the library asks as one step (0.04 m
// over its l_max, against 0.065 m under l_min for two) and the preset as two of 0.245 m (0.09 m
// over its l_max for one).
TEST(WalkerPresets, TheAdaptiveWalkerAsksShorterApproachSteps) {
  const WalkerParams a = PresetWalkerParams(WalkerPreset::kAdaptive);
  const WalkerParams c = PresetWalkerParams(WalkerPreset::kChapter);
  EXPECT_EQ(a.planner.l_max, 0.40);
  EXPECT_EQ(c.planner.l_max, StepPlannerParams().l_max);
  EXPECT_EQ(StepPlannerParams().l_max, 0.45);
  StepPlannerParams library = a.planner;
  library.l_max = StepPlannerParams().l_max;
  const StepPlan one = PlanStep(library, 0.55, 0.2);
  EXPECT_EQ(one.approach_steps, 1);
  EXPECT_NEAR(one.step_length, 0.49, 1e-12);
  const StepPlan two = PlanStep(a.planner, 0.55, 0.2);
  EXPECT_EQ(two.approach_steps, 2);
  EXPECT_NEAR(two.step_length, 0.245, 1e-12);
  // Within [l_min, 0.40] both ask the same single step.
  EXPECT_EQ(PlanStep(a.planner, 0.44, 0.2).approach_steps, 1);
  EXPECT_NEAR(PlanStep(a.planner, 0.44, 0.2).step_length, 0.38, 1e-12);
  EXPECT_NEAR(PlanStep(library, 0.44, 0.2).step_length, 0.38, 1e-12);
}

TEST(FootLift, TheClearanceGrowsWithTheObstacleOnlyWithAHeightGain) {
  FootLiftParams p;
  p.clearance = 0.04;
  EXPECT_EQ(LiftClearance(p, 0.07), 0.04);  // off: the clearance alone
  p.height_gain = 0.8;
  EXPECT_EQ(LiftClearance(p, 0.02), 0.04);  // a low obstacle: the clearance
  EXPECT_DOUBLE_EQ(LiftClearance(p, 0.07), 0.056);
  EXPECT_DOUBLE_EQ(LiftClearance(p, 0.05), 0.04);
  WalkerParams w = PresetWalkerParams(WalkerPreset::kAdaptive);
  w.lift.height_gain = -0.5;
  std::string error;
  EXPECT_FALSE(w.IsValid(&error));
  EXPECT_NE(error.find("lift_height_gain"), std::string::npos) << error;
}

// The trailing leg's swing gets trailing_clearance on top of the clearance, the step over none.
TEST(FootLift, TheTrailingLegLiftsHigherByItsOwnClearance) {
  FootLiftParams p;
  p.clearance = 0.04;
  p.height_gain = 0.8;
  EXPECT_EQ(LiftClearance(p, 0.02, true), 0.04);  // off by default: the same clearance
  p.trailing_clearance = 0.04;
  EXPECT_EQ(LiftClearance(p, 0.02, false), 0.04);
  EXPECT_DOUBLE_EQ(LiftClearance(p, 0.02, true), 0.08);
  EXPECT_DOUBLE_EQ(LiftClearance(p, 0.07, true), 0.056 + 0.04);  // on top of the height gain
  WalkerParams w = PresetWalkerParams(WalkerPreset::kAdaptive);
  w.lift.trailing_clearance = -0.01;
  std::string error;
  EXPECT_FALSE(w.IsValid(&error));
  EXPECT_NE(error.find("lift_trailing_clearance"), std::string::npos) << error;
}

TEST(FootLift, TheLiftLetsGoOfAJointNoFasterThanItsReleaseRate) {
  FootLiftParams p;
  const Eigen::Vector2d last(0.4, -0.7);  // hip raised, knee flexed by the lift (rad)
  const Eigen::Vector2d asked(0.0, 0.0);  // the foot past the far edge: let go at once
  // Off (the library's default): as asked.
  EXPECT_EQ(p.release_rate, 0.0);
  EXPECT_EQ(LimitLiftRelease(p, asked, last, 0.001), asked);
  p.release_rate = 7.0;
  const Eigen::Vector2d d = LimitLiftRelease(p, asked, last, 0.001);
  EXPECT_DOUBLE_EQ(d[0], 0.4 - 0.007);
  EXPECT_DOUBLE_EQ(d[1], -0.7 + 0.007);
  // A small release within the rate, a growing offset and one changing sign: as asked.
  EXPECT_EQ(LimitLiftRelease(p, Eigen::Vector2d(0.395, -0.695), last, 0.001),
            Eigen::Vector2d(0.395, -0.695));
  EXPECT_EQ(LimitLiftRelease(p, Eigen::Vector2d(0.6, -0.9), last, 0.001),
            Eigen::Vector2d(0.6, -0.9));
  EXPECT_EQ(LimitLiftRelease(p, Eigen::Vector2d(-0.1, 0.1), last, 0.001),
            Eigen::Vector2d(-0.1, 0.1));
  // No time elapsed (the swing's first lifted period): as asked.
  EXPECT_EQ(LimitLiftRelease(p, asked, last, 0.0), asked);
  // Released over 0.1 s at 7 rad/s, the knee's 0.7 rad is let go of in 100 periods of 1 ms.
  Eigen::Vector2d x = last;
  int periods = 0;
  while (x[1] < 0.0 && periods < 1000) {
    x = LimitLiftRelease(p, asked, x, 0.001);
    ++periods;
  }
  EXPECT_EQ(x[1], 0.0);
  EXPECT_NEAR(periods, 100, 1);
}

TEST(WalkerPresets, TheAdaptiveWalkerPacesTheLiftsRelease) {
  EXPECT_EQ(PresetWalkerParams(WalkerPreset::kAdaptive).lift.release_rate, 7.0);
  EXPECT_EQ(PresetWalkerParams(WalkerPreset::kChapter).lift.release_rate, 0.0);
  WalkerParams w = PresetWalkerParams(WalkerPreset::kAdaptive);
  w.lift.release_rate = -1.0;
  std::string error;
  EXPECT_FALSE(w.IsValid(&error));
  EXPECT_NE(error.find("lift_release_rate"), std::string::npos) << error;
}

TEST_F(WalkerPresetsTest, TheLiftReleaseRateIsReadOverThePreset) {
  EXPECT_EQ(LoadScenario(Write("")).walker.lift.release_rate, 7.0);
  EXPECT_EQ(LoadScenario(Write("lift_release_rate = 5.5\n")).walker.lift.release_rate, 5.5);
  EXPECT_THROW(LoadScenario(Write("lift_release_rate = -1\n")), InputError);
}

TEST_F(WalkerPresetsTest, TheStanceKneesLandingIsTheAdaptiveWalkersAndReadInDegrees) {
  const WalkerParams a = LoadScenario(Write("")).walker;
  EXPECT_EQ(a.stance_knee_rate, 2.0);
  EXPECT_EQ(a.stance_knee_flexed, -0.3);
  const WalkerParams c = PresetWalkerParams(WalkerPreset::kChapter);
  EXPECT_EQ(c.stance_knee_rate, 0.0);  // the chapter's eq. 23 as it is
  const WalkerParams set =
      LoadScenario(Write("stance_knee_rate = 3.5\nstance_knee_flexed_deg = -45\n")).walker;
  EXPECT_EQ(set.stance_knee_rate, 3.5);
  EXPECT_NEAR(set.stance_knee_flexed, -M_PI / 4, 1e-15);
  for (const char* bad : {"stance_knee_rate = -1\n", "stance_knee_flexed_deg = 10\n",
                          "stance_knee_flexed_deg = -200\n"}) {
    EXPECT_THROW(LoadScenario(Write(bad)), InputError) << bad;
  }
}

TEST_F(WalkerPresetsTest, TheLiftHeightGainIsReadOverThePreset) {
  EXPECT_EQ(LoadScenario(Write("")).walker.lift.height_gain, 0.8);
  EXPECT_EQ(LoadScenario(Write("lift_height_gain = 0.5\n")).walker.lift.height_gain, 0.5);
  EXPECT_THROW(LoadScenario(Write("lift_height_gain = -1\n")), InputError);
}

TEST(WalkerPresets, TheAdaptiveWalkerLeansBackFurtherForAStepDown) {
  const WalkerParams a = PresetWalkerParams(WalkerPreset::kAdaptive);
  const WalkerParams c = PresetWalkerParams(WalkerPreset::kChapter);
  EXPECT_EQ(a.steps.down_lean, -6.0);
  EXPECT_EQ(c.steps.down_lean, TerrainStepParams().down_lean);  // the chapter's walker: unchanged
  EXPECT_EQ(a.steps.up_lean, c.steps.up_lean);                  // a step up: as before
  // A swing about to cross a 4 cm step down: q0_d moves back by 6 rad/m times the drop.
  Terrain t;
  t.ground = GroundProfile({{2.0, 0.0, -0.04}});
  TerrainSteps steps(a.steps);
  steps.OnTouchdown(t, 1.0, Vec2(1.8, 0.0), Vec2(1.45, 0.0));
  EXPECT_NEAR(steps.TrunkOffset(), -6.0 * 0.04, 1e-12);
}

TEST_F(WalkerPresetsTest, OnlyTheTypeGivesTheAdaptiveWalker) {
  const Scenario s = LoadScenario(Write(""));
  EXPECT_EQ(s.preset, WalkerPreset::kAdaptive);
  EXPECT_TRUE(s.walker.planner.enabled);
  EXPECT_EQ(s.walker.fis_v_lead, 1.0);
  EXPECT_FALSE(s.walker.lift.keeps_rules);
  EXPECT_EQ(s.walker.steps.down_lean, -6.0);
  EXPECT_EQ(LoadScenario(Write("[controller.steps]\ndown_lean = -4.0\n")).walker.steps.down_lean,
            -4.0);
}

TEST_F(WalkerPresetsTest, KeysAreReadOverThePreset) {
  const Scenario s = LoadScenario(Write("preset = \"chapter\"\nk_p = 0.3\n"));
  EXPECT_EQ(s.preset, WalkerPreset::kChapter);
  EXPECT_FALSE(s.walker.planner.enabled);
  EXPECT_TRUE(s.walker.lift.keeps_rules);
  EXPECT_EQ(s.walker.k_p, 0.3);
  const Scenario t = LoadScenario(Write(
      "preset = \"chapter\"\nlift_keeps_rules = false\n[controller.planner]\nenabled = true\n"));
  EXPECT_TRUE(t.walker.planner.enabled);
  EXPECT_FALSE(t.walker.lift.keeps_rules);
}

TEST_F(WalkerPresetsTest, TheChapterBaselineTakesTheScenariosKeys) {
  const Scenario s = LoadScenario(Write("baselines = [\"chapter\"]\nk_p = 0.3\n"));
  EXPECT_TRUE(s.walker.planner.enabled);
  EXPECT_FALSE(s.chapter_walker.planner.enabled);
  EXPECT_TRUE(s.chapter_walker.lift.keeps_rules);
  EXPECT_EQ(s.chapter_walker.k_p, 0.3);
  EXPECT_EQ(s.walker.k_p, 0.3);
  // The warm-up comes from the start gait for both.
  EXPECT_EQ(s.chapter_walker.q0_d_initial, s.walker.q0_d_initial);
  EXPECT_EQ(s.chapter_walker.warmup_steps, s.walker.warmup_steps);
  const std::vector<std::string> variants = ScenarioVariants(s);
  EXPECT_NE(std::find(variants.begin(), variants.end(), "chapter"), variants.end());
}

TEST_F(WalkerPresetsTest, BadPresetsAreRefusedNamingFileAndKey) {
  const std::string path = Write("preset = \"paper\"\n");
  try {
    LoadScenario(path);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.key(), "controller.preset") << e.what();
    EXPECT_EQ(e.line(), 8) << e.what();
    EXPECT_NE(std::string(e.what()).find("\"adaptive\", \"chapter\""), std::string::npos);
  }
  const std::string twice = Write("preset = \"chapter\"\nbaselines = [\"chapter\"]\n");
  try {
    LoadScenario(twice);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "controller.baselines") << e.what();
  }
}

}  // namespace
}  // namespace rabbit
