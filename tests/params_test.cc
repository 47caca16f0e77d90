// Parameter overlays (--params, best.toml): the overlay's numbers replace settings in every scenario
// of a suite, whether the suite writes the key or leaves its default, array elements and the FLL's
// membership functions included; a path that names no numeric setting is an InputError naming the
// overlay's file and line.
#include "rabbit/scenario/params.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "rabbit/io/error.h"
#include "rabbit/learn/fll.h"
#include "rabbit/model/params.h"
#include "rabbit/scenario/suite.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

const std::string kRoot = RABBIT_SOURCE_DIR;

class ParamsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rabbit_params_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Write(const std::string& name, const std::string& text) {
    const fs::path path = dir_ / name;
    std::ofstream(path) << text;
    return path.string();
  }
  ParamOverlay Overlay(const std::string& text) {
    return LoadParamOverlay(Write("params.toml", text));
  }
  fs::path dir_;
};

TEST_F(ParamsTest, NestedQuotedAndArrayFormsSpellTheSamePaths) {
  const ParamOverlay o = Overlay(
      "[params]\n\"controller.k_p\" = 0.25\n[params.controller]\nk_v = 0.5\n"
      "[params.controller.sets.d_obs]\nSmall = [0, 0.12, 0.3]\n");
  ASSERT_EQ(o.values.size(), 5u);
  const std::map<std::string, double> patches = *o.Patches();
  EXPECT_EQ(patches.at("controller.k_p"), 0.25);
  EXPECT_EQ(patches.at("controller.k_v"), 0.5);
  EXPECT_EQ(patches.at("controller.sets.d_obs.Small.1"), 0.0);
  EXPECT_EQ(patches.at("controller.sets.d_obs.Small.2"), 0.12);
  EXPECT_EQ(patches.at("controller.sets.d_obs.Small.3"), 0.3);
  for (const ParamValue& v : o.values) {
    if (v.path == "controller.k_p") {
      EXPECT_EQ(v.line, 2);
    }
  }
}

TEST_F(ParamsTest, BadOverlayFilesAreInputErrors) {
  struct Case {
    const char* text;
    int line;
    const char* fragment;
  };
  for (const Case& c : {Case{"[params]\n\"controller.k_p\" = \"x\"\n", 2, "expected a number"},
                        Case{"[params]\n\"controller..k_p\" = 1.0\n", 2, "bad key path"},
                        Case{"[params]\n\"a.0\" = 1.0\n", 2, "bad key path"},
                        Case{"[params]\n\"a.b\" = 1.0\n[params.a]\nb = 2.0\n", 0, "given twice"},
                        Case{"[other]\nx = 1\n", 1, "unknown key"},
                        Case{"x = 1\n", 1, "unknown key"},
                        Case{"[params]\n\"a\" = nan\n", 2, "finite"},
                        Case{"[params]\n\"controller.velocity_control.k_p\" = []\n", 2,
                             "an empty array sets nothing"}}) {
    try {
      Overlay(c.text);
      ADD_FAILURE() << "no error for " << c.text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(c.fragment), std::string::npos) << e.what();
      if (c.line > 0) {
        EXPECT_EQ(e.line(), c.line) << e.what();
      }
    }
  }
}

TEST_F(ParamsTest, OverlayReachesEveryScenarioDefaultsAndArrayElements) {
  const std::string suite = kRoot + "/scenarios/paper.toml";
  const Suite base = LoadSuite(suite);
  const ParamOverlay o = Overlay(
      "[params]\n"
      "\"controller.k_p\" = 0.31\n"             // written in the suite's [defaults]
      "\"controller.lift_clearance\" = 0.07\n"  // not written: its default
      "\"controller.sets.d_obs.Small.2\" = 0.12\n"
      "\"controller.sets.V_M.V1.1\" = 0.5\n"  // Ramp start end, as the FLL writes it
      "\"noise.v_m_std\" = 0.01\n");
  const Suite tuned = LoadSuite(suite, &o);
  ASSERT_EQ(tuned.scenarios.size(), base.scenarios.size());
  const Membership shipped_v1 =
      LoadFll(kRoot + "/gaits/gait_pattern.fll").inputs[0].sets[0].membership;
  for (size_t i = 0; i < tuned.scenarios.size(); ++i) {
    const Scenario& s = tuned.scenarios[i];
    SCOPED_TRACE(s.name);
    EXPECT_DOUBLE_EQ(s.walker.k_p, 0.31);
    EXPECT_DOUBLE_EQ(s.walker.lift.clearance, 0.07);
    EXPECT_DOUBLE_EQ(s.walker.v_m_noise, 0.01);
    EXPECT_DOUBLE_EQ(s.walker.k_v, base.scenarios[i].walker.k_v);  // untouched
    EXPECT_FALSE(base.scenarios[i].fis.has_value());
    ASSERT_TRUE(s.fis.has_value());
    const FuzzyInput& d_obs = s.fis->inputs[1];
    ASSERT_EQ(d_obs.name, "d_obs");
    EXPECT_EQ(d_obs.sets[1].name, "Small");
    EXPECT_DOUBLE_EQ(d_obs.sets[1].membership.a, 0.0);
    EXPECT_DOUBLE_EQ(d_obs.sets[1].membership.b, 0.12);
    EXPECT_DOUBLE_EQ(d_obs.sets[1].membership.c, 0.3);
    // V_M V1 (of eight gaits) is "Ramp V_2 V_1" (falling) in the shipped FLL: its start becomes
    // 0.5, its end stays.
    const Membership& vs = s.fis->inputs[0].sets[0].membership;
    EXPECT_EQ(vs.shape, Membership::Shape::kRampDown);
    EXPECT_DOUBLE_EQ(vs.b, 0.5);
    EXPECT_DOUBLE_EQ(vs.a, shipped_v1.a);
  }
  // An element of an array the suite writes: the obstacle of scenario "obstacle" moves, the
  // family's members keep their drawn positions' other keys.
  const ParamOverlay moved = Overlay("[params]\n\"terrain.obstacles.1.height\" = 0.04\n");
  const Suite obstacles = LoadSuite(kRoot + "/scenarios/obstacle_sweep.toml", &moved);
  for (const Scenario& s : obstacles.scenarios) {
    ASSERT_EQ(s.terrain.obstacles.size(), 1u);
    EXPECT_DOUBLE_EQ(s.terrain.obstacles[0].height, 0.04);
  }
}

TEST_F(ParamsTest, PathsThatNameNoNumericSettingNameTheOverlay) {
  const std::string suite = kRoot + "/scenarios/paper.toml";
  for (const char* path : {"controller.k_pp", "controller.type", "controller.sets.d_obs.Small.4",
                           "controller.sets.d_obs.Tiny.1", "terrain.obstacles.2.height",
                           "criteria"}) {
    const ParamOverlay o = Overlay(std::string("[params]\n\n\"") + path + "\" = 1.0\n");
    try {
      LoadSuite(suite, &o);
      ADD_FAILURE() << "no error for " << path;
    } catch (const InputError& e) {
      EXPECT_EQ(e.key(), path) << e.what();
      EXPECT_EQ(e.line(), 3) << e.what();
      EXPECT_NE(std::string(e.what()).find("params.toml"), std::string::npos) << e.what();
    }
  }
}

TEST_F(ParamsTest, IntegerSettingsTakeOnlyIntegers) {
  const std::string suite = kRoot + "/scenarios/paper.toml";
  const ParamOverlay ok = Overlay("[params]\n\"controller.warmup_steps\" = 4\n");
  EXPECT_EQ(LoadSuite(suite, &ok).scenarios[0].walker.warmup_steps, 4);
  const ParamOverlay bad = Overlay("[params]\n\"controller.warmup_steps\" = 4.5\n");
  EXPECT_THROW(LoadSuite(suite, &bad), InputError);
}

TEST_F(ParamsTest, PatchedValuesAreCheckedAsWrittenOnes) {
  // q0_d_initial_deg outside [q0_d_min_deg, q0_d_max_deg] is an error when written, so when patched.
  const ParamOverlay bad = Overlay("[params]\n\"controller.q0_d_initial_deg\" = 40\n");
  EXPECT_THROW(LoadSuite(kRoot + "/scenarios/paper.toml", &bad), InputError);
  const ParamOverlay ok = Overlay("[params]\n\"controller.q0_d_initial_deg\" = 10\n");
  EXPECT_NEAR(LoadSuite(kRoot + "/scenarios/paper.toml", &ok).scenarios[0].walker.q0_d_initial,
              10.0 * M_PI / 180.0, 1e-15);
}

TEST_F(ParamsTest, AnInvalidMembershipFunctionIsAnInputError) {
  // Small's peak beyond its right foot.
  const ParamOverlay bad = Overlay("[params]\n\"controller.sets.d_obs.Small.2\" = 0.4\n");
  EXPECT_THROW(LoadSuite(kRoot + "/scenarios/paper.toml", &bad), InputError);
}

TEST_F(ParamsTest, OverlayTomlReadsBackExactly) {
  ParamOverlay o;
  o.values = {{"controller.k_p", 0.1 + 0.2, 0, ""}, {"controller.sets.d_obs.Small.2", 1e-7, 0, ""}};
  const ParamOverlay back = LoadParamOverlay(Write("best.toml", ParamOverlayToml(o, "a\nb")));
  ASSERT_EQ(back.values.size(), 2u);
  EXPECT_EQ(back.values[0].value, 0.1 + 0.2);
  EXPECT_EQ(back.values[1].value, 1e-7);
  EXPECT_EQ(back.values[1].path, "controller.sets.d_obs.Small.2");
}

}  // namespace
}  // namespace rabbit
