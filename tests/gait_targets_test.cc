// The targets file of a gait database: names, roles, per-target bounds, and every kind of bad
// input refused with an InputError naming the file, line and key.
#include "gait_targets.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include "rabbit/io/error.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

class GaitTargetsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rabbit_gait_targets_" + std::to_string(::getpid()) + "_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Write(const std::string& text) {
    const std::string path = (dir_ / "targets.toml").string();
    std::ofstream(path) << text;
    return path;
  }
  // The InputError's message for a bad targets file (empty if it reads).
  std::string Error(const std::string& text) {
    try {
      ReadGaitTargets(Write(text));
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

TEST_F(GaitTargetsTest, NamesRolesAndBounds) {
  const std::vector<GaitTarget> t =
      ReadGaitTargets(Write("[bounds]\nq0_d_deg = [-5, 20]\n"
                            "[[gait]]\nv_m = 0.6\nl_step = 0.34\n"
                            "[[gait]]\nv_m = 0.6\nl_step = 0.27\nrole = \"library\"\nbudget = 900\n"
                            "[gait.bounds]\nqr1_dsw_deg = [10, 60]\n"
                            "[[gait]]\nv_m = 0.6\nl_step = 0.3\nrole = \"library\"\nname = "
                            "\"short\"\nseed = 4\n"))
          .gaits;
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t[0].name, "vm_0.60");
  EXPECT_EQ(t[0].role, GaitRole::kSpeed);
  EXPECT_EQ(t[1].name, "vm_0.60_l_0.27");
  EXPECT_EQ(t[1].role, GaitRole::kLibrary);
  EXPECT_EQ(t[1].synthesis.budget, 900);
  EXPECT_EQ(t[1].synthesis.target_l_step, 0.27);
  EXPECT_EQ(t[2].name, "short");
  EXPECT_EQ(t[2].synthesis.seed, 4u);
  // Bounds: the file's [bounds] over the defaults, then the target's own.
  const auto defaults = DefaultSynthesisBounds();
  for (const GaitTarget& g : t) EXPECT_EQ(g.synthesis.bounds[2], std::make_pair(-5.0, 20.0));
  EXPECT_EQ(t[0].synthesis.bounds[0], defaults[0]);
  EXPECT_EQ(t[1].synthesis.bounds[0], std::make_pair(10.0, 60.0));
  EXPECT_EQ(t[2].synthesis.bounds[0], defaults[0]);
  EXPECT_GT(t[1].line, t[0].line);
}

// [gait.start]: any searched parameter, in the units of the bounds, within the target's bounds
// (the wide box here); the unset ones stay unset. The start is part of the target's inputs.
TEST_F(GaitTargetsTest, StartIsReadInTheUnitsOfTheBounds) {
  const std::vector<GaitTarget> t =
      ReadGaitTargets(Write("[[gait]]\nv_m = 0.8\n[gait.bounds]\nq0_d_deg = [-5, 25]\n"
                            "[gait.start]\nq0_d_deg = 20\nhip_kp = 700\n"
                            "[[gait]]\nv_m = 0.6\n"))
          .gaits;
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].synthesis.start[2], 20.0);   // q0_d_deg
  EXPECT_EQ(t[0].synthesis.start[5], 700.0);  // hip_kp
  EXPECT_FALSE(t[0].synthesis.start[0].has_value());
  EXPECT_EQ(StartGaitSpec(t[0].synthesis).rules.q0_d, 20.0 * M_PI / 180.0);
  for (const auto& v : t[1].synthesis.start) EXPECT_FALSE(v.has_value());
  GaitTarget moved = t[0];
  moved.synthesis.start[5] = 701.0;
  EXPECT_NE(TargetInputsText(moved), TargetInputsText(t[0]));
  EXPECT_NE(TargetInputsText(t[0]).find("start q0_d_deg 20"), std::string::npos);
  // Every shipped speed gait starts at its parameters: all ten given.
  for (const GaitTarget& g :
       ReadGaitTargets(std::string(RABBIT_SOURCE_DIR) + "/gaits/targets.toml").gaits) {
    for (int i = 0; i < kSynthesisParams; ++i) {
      EXPECT_TRUE(g.synthesis.start[i].has_value()) << g.name << " " << kSynthesisParamNames[i];
    }
  }
}

TEST_F(GaitTargetsTest, DefaultNames) {
  EXPECT_EQ(DefaultGaitName(0.6, 0.0, GaitRole::kSpeed), "vm_0.60");
  EXPECT_EQ(DefaultGaitName(0.6, 0.34, GaitRole::kSpeed), "vm_0.60");
  EXPECT_EQ(DefaultGaitName(0.6, 0.27, GaitRole::kLibrary), "vm_0.60_l_0.27");
  EXPECT_EQ(DefaultGaitName(1.0, 0.5, GaitRole::kLibrary), "vm_1.00_l_0.50");
}

// gaits/targets.toml holds the shipped database: eight speed gaits and the library cells over
// speed x step length, at least 3 step lengths (the speed gait's included) at 5 speeds or more.
// gaits/library.toml is the search that found the cells: the same targets, but the library cells
// without their [gait.start].
TEST_F(GaitTargetsTest, TheShippedTargetsAreSpeedGaitsAndLibraryCells) {
  const std::vector<GaitTarget> t =
      ReadGaitTargets(std::string(RABBIT_SOURCE_DIR) + "/gaits/targets.toml").gaits;
  int speed = 0;
  std::map<long, int> step_lengths;  // speed in cm/s -> step lengths there, the speed gait's too
  for (const GaitTarget& g : t) {
    ++step_lengths[std::lround(100.0 * g.synthesis.target_v_m)];
    if (g.role == GaitRole::kSpeed) {
      ++speed;
      EXPECT_EQ(g.name, DefaultGaitName(g.synthesis.target_v_m, 0.0, GaitRole::kSpeed));
    } else {
      EXPECT_GT(g.synthesis.target_l_step, 0.0) << g.name;
      EXPECT_EQ(g.name, DefaultGaitName(g.synthesis.target_v_m, g.synthesis.target_l_step,
                                        GaitRole::kLibrary));
    }
    // Every shipped gait starts where it was found: all ten parameters given.
    for (const auto& value : g.synthesis.start) EXPECT_TRUE(value.has_value()) << g.name;
  }
  EXPECT_EQ(speed, 8);
  int speeds_with_three = 0;
  for (const auto& [v, n] : step_lengths) speeds_with_three += n >= 3 ? 1 : 0;
  EXPECT_GE(speeds_with_three, 5);
  // The search: the same targets in the same order, speed gaits as they are, library cells
  // without a start.
  const std::vector<GaitTarget> search =
      ReadGaitTargets(std::string(RABBIT_SOURCE_DIR) + "/gaits/library.toml").gaits;
  ASSERT_EQ(search.size(), t.size());
  for (size_t i = 0; i < t.size(); ++i) {
    GaitTarget shipped = t[i];
    if (shipped.role == GaitRole::kLibrary) {
      for (const auto& value : search[i].synthesis.start) EXPECT_FALSE(value) << shipped.name;
      shipped.synthesis.start = {};
    }
    EXPECT_EQ(TargetInputsText(search[i]), TargetInputsText(shipped)) << shipped.name;
    EXPECT_EQ(search[i].walker.rule_share, shipped.walker.rule_share) << shipped.name;
  }
}

TEST_F(GaitTargetsTest, BadInputNamesLineAndKey) {
  const std::string two_names =
      Error("[[gait]]\nv_m = 0.5\n[[gait]]\nv_m = 0.6\nname = \"vm_0.50\"\n");
  EXPECT_NE(two_names.find(":5"), std::string::npos) << two_names;
  EXPECT_NE(two_names.find("name"), std::string::npos) << two_names;
  EXPECT_NE(two_names.find("line 1"), std::string::npos) << two_names;
  const std::string two_cells = Error(
      "[[gait]]\nv_m = 0.6\nl_step = 0.3\nrole = \"library\"\n"
      "[[gait]]\nv_m = 0.6\nl_step = 0.3\nrole = \"library\"\nname = \"other\"\n");
  EXPECT_NE(two_cells.find("same (v_m, l_step)"), std::string::npos) << two_cells;
  EXPECT_NE(Error("[[gait]]\nv_m = 0.6\nrole = \"library\"\n").find("l_step"), std::string::npos);
  EXPECT_NE(Error("[[gait]]\nv_m = 0.6\nrole = \"fast\"\n").find("role"), std::string::npos);
  EXPECT_NE(Error("[[gait]]\nv_m = 0.6\nname = \"index\"\n").find("name"), std::string::npos);
  EXPECT_NE(Error("[[gait]]\nv_m = 0.6\nname = \"manifest\"\n").find("name"), std::string::npos);
  EXPECT_NE(Error("[[gait]]\nv_m = 0.6\nname = \"../x\"\n").find("name"), std::string::npos);
  EXPECT_NE(Error("[[gait]]\nv_m = 0.6\nspeed = 1\n").find("speed"), std::string::npos);
  const std::string bounds = Error("[[gait]]\nv_m = 0.6\n[gait.bounds]\nq0_d_deg = [20, 10]\n");
  EXPECT_NE(bounds.find("q0_d_deg"), std::string::npos) << bounds;
  EXPECT_NE(Error("[[gait]]\nv_m = 0.6\n[gait.bounds]\nknee = [1, 2]\n").find("knee"),
            std::string::npos);
  EXPECT_NE(Error("[bounds]\n").find("gait"), std::string::npos);
  // The fuzzy system needs one speed gait per velocity, 64 at most: refused here, not after the
  // build's synthesis. A library gait may share a speed gait's v_m.
  const std::string same_speed = Error(
      "[[gait]]\nv_m = 0.6\nl_step = 0.3\n[[gait]]\nv_m = 0.6\nl_step = 0.34\n"
      "name = \"other\"\n");
  EXPECT_NE(same_speed.find(":5: 'gait[2].v_m': a second speed gait at this v_m (the first is at "
                            "line 1"),
            std::string::npos)
      << same_speed;
  EXPECT_EQ(Error("[[gait]]\nv_m = 0.6\nl_step = 0.3\n[[gait]]\nv_m = 0.6\nl_step = 0.34\n"
                  "role = \"library\"\n"),
            "");
  std::string many;
  for (int k = 0; k < 65; ++k) many += "[[gait]]\nv_m = " + std::to_string(0.3 + 0.01 * k) + "\n";
  EXPECT_NE(Error(many).find("more than 64 speed gaits"), std::string::npos);
  many.resize(many.rfind("[[gait]]"));
  EXPECT_EQ(Error(many), "");
}

// The check suite is only named here (gaits generate ignores it; gaits build reads it first, in
// gait_build_test): its resolved path and the line that names it.
TEST_F(GaitTargetsTest, TheCheckSuiteIsNamedNotRead) {
  const GaitTargets t =
      ReadGaitTargets(Write("[check]\nsuite = \"none.toml\"\n[[gait]]\nv_m = 0.5\n"));
  EXPECT_EQ(t.check_suite, (dir_ / "none.toml").string());
  EXPECT_EQ(t.check_line, 2);
}

}  // namespace
}  // namespace rabbit
