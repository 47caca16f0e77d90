// Scenario files: the shipped examples load; every kind of bad input is refused with an
// InputError that names the file, the line and the key.
#include "rabbit/scenario/scenario.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "rabbit/io/error.h"
#include "rabbit/io/toml_reader.h"
#include "rabbit/scenario/suite.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

class ScenarioFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rabbit_scenario_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Write(const std::string& name, const std::string& text) {
    const fs::path path = dir_ / name;
    std::ofstream(path) << text;
    return path.string();
  }
  // Expects LoadScenario to throw an InputError whose message holds every fragment.
  void ExpectError(const std::string& text, int line, const std::string& key,
                   const std::string& fragment) {
    const std::string path = Write("bad.toml", text);
    try {
      LoadScenario(path);
      ADD_FAILURE() << "no error for:\n" << text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      if (line > 0) {
        EXPECT_EQ(e.line(), line) << e.what();
      }
      EXPECT_EQ(e.key(), key) << e.what();
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }
  fs::path dir_;
};

const char* kMinimal = R"(
[simulation]
duration = 1.0
[initial]
y = 0.9
)";

TEST_F(ScenarioFileTest, EveryDocumentedCriterionIsAKey) {
  // docs/outcomes.md's criteria table: every key it lists is read from [criteria] (a key the
  // reader does not know is an error), and the reader knows no key it leaves out.
  std::ifstream in(std::string(RABBIT_SOURCE_DIR) + "/docs/outcomes.md");
  std::string line, table;
  bool inside = false;
  int keys = 0;
  while (std::getline(in, line)) {
    if (line.rfind("## ", 0) == 0) inside = line == "## Criteria";
    if (!inside || line.rfind("| `", 0) != 0) continue;
    const std::string key = line.substr(3, line.find('`', 3) - 3);
    const std::string value = key == "allow_obstacle_contact"          ? "false"
                              : key.find("steps") != std::string::npos ? "3"
                                                                       : "0.5";
    table += key + " = " + value + "\n";
    ++keys;
  }
  EXPECT_EQ(keys, 14);  // PassCriteria's fields (the stall watch's three)
  const Scenario s =
      LoadScenario(Write("criteria.toml", std::string(kMinimal) + "[criteria]\n" + table));
  EXPECT_EQ(s.criteria.min_travel_ratio, 0.5);
  EXPECT_EQ(s.criteria.stall.no_touchdown, 0.5);
  EXPECT_EQ(s.criteria.stall.window, 0.5);
  EXPECT_EQ(s.criteria.stall.min_advance, 0.5);
  ExpectError(std::string(kMinimal) + "[criteria]\nmin_travel_ratio = -0.1\n", 7,
              "criteria.min_travel_ratio", "must be >= 0");
  ExpectError(std::string(kMinimal) + "[criteria]\nstall_window_s = inf\n", 7,
              "criteria.stall_window_s", "finite");
  ExpectError("expect_outcome = \"crashed\"\n" + std::string(kMinimal), 1, "expect_outcome",
              "\"stalled\"");
}

TEST_F(ScenarioFileTest, ShippedScenariosLoad) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(RABBIT_SOURCE_DIR) / "scenarios")) {
    if (entry.path().extension() != ".toml" || entry.path().filename() == "model.toml") continue;
    EXPECT_NO_THROW(LoadSuite(entry.path().string())) << entry.path();  // a scenario: of one
    ++count;
  }
  EXPECT_GE(count, 4);
}

TEST_F(ScenarioFileTest, DefaultsAndDegreesAtTheEdge) {
  const Scenario s = LoadScenario(Write("ok.toml", std::string(kMinimal) + R"(
q0_deg = 90.0
[controller]
type = "pd_hold"
kp = [1, 2, 3, 4]
kd = 5
target_deg = [180, 0, 0, 0]
)"));
  EXPECT_EQ(s.name, "ok");
  EXPECT_DOUBLE_EQ(s.q0[kQ0], M_PI / 2);
  EXPECT_EQ(s.controller, ControllerKind::kPdHold);
  EXPECT_DOUBLE_EQ(s.pd_hold.kp[3], 4.0);
  EXPECT_DOUBLE_EQ(s.pd_hold.kd[0], 5.0);
  EXPECT_DOUBLE_EQ(s.pd_hold.target[0], M_PI);
  EXPECT_DOUBLE_EQ(s.options.control_period, 1e-3);
  EXPECT_DOUBLE_EQ(s.model.trunk_mass, 12.0);
}

TEST_F(ScenarioFileTest, FixedStepIsOptIn) {
  EXPECT_EQ(LoadScenario(Write("default.toml", kMinimal)).options.integrator.fixed_step, 0.0);
  const Scenario s = LoadScenario(
      Write("fixed.toml", "[simulation]\nduration = 1.0\nfixed_step = 5e-4\n[initial]\ny = 0.9\n"));
  EXPECT_EQ(s.options.integrator.fixed_step, 5e-4);
  EXPECT_EQ(s.options.integrator.kind, IntegratorKind::kArkodeErk);
}

TEST_F(ScenarioFileTest, FootClearancePlacesLowestFoot) {
  const Scenario s = LoadScenario(Write("ok.toml", R"(
[simulation]
duration = 1.0
[initial]
foot_clearance = 0.02
q11_deg = 10
q21_deg = -10
)"));
  const Model model(s.model);
  EXPECT_NEAR(std::min(FootPosition(model, s.q0, 0).y(), FootPosition(model, s.q0, 1).y()), 0.02,
              1e-12);
}

// [terrain] slopes: the ground profile, in either TOML form; [initial] foot_clearance measures
// from the profile under each foot.
TEST_F(ScenarioFileTest, SlopeProfileIsReadAndPlacesTheFeet) {
  constexpr double kDeg = M_PI / 180.0;
  const Scenario s = LoadScenario(Write("ok.toml", R"(
[simulation]
duration = 1.0
[terrain]
slopes = [
  { x_start = 2.0, slope_deg = -3.0 },   # up 3 deg
  { x_start = 6.0, slope_deg = 2.0 },
  { x_start = 9.0, slope_deg = 0 },
]
[[terrain.obstacles]]
x_start = 10.0
length = 0.2
height = 0.05
[initial]
x = 4.0
foot_clearance = 0.01
q11_deg = 10
q21_deg = -10
)"));
  const std::vector<SlopeBreak>& b = s.terrain.ground.breaks();
  ASSERT_EQ(b.size(), 3u);
  EXPECT_EQ(b[0].x_start, 2.0);
  EXPECT_DOUBLE_EQ(b[0].slope, -3.0 * kDeg);
  EXPECT_DOUBLE_EQ(b[1].slope, 2.0 * kDeg);
  EXPECT_EQ(b[2].slope, 0.0);
  EXPECT_EQ(s.model.slope, 0.0);  // the world frame: gravity vertical
  EXPECT_NEAR(s.terrain.ObstacleBase(0), 4.0 * std::tan(3 * kDeg) - 3.0 * std::tan(2 * kDeg),
              1e-12);
  const Model model(s.model);
  double lowest = 1e9;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const Vec2 foot = FootPosition(model, s.q0, leg);
    lowest = std::min(lowest, foot.y() - s.terrain.GroundHeight(foot.x()));
  }
  EXPECT_NEAR(lowest, 0.01, 1e-12);
  EXPECT_GT(s.q0[kY], 0.9);  // lifted with the ground (0.1 m up at x = 4)

  // The [[terrain.slopes]] form is the same; an empty array is flat ground.
  const Scenario same = LoadScenario(Write("same.toml", std::string(kMinimal) + R"(
[[terrain.slopes]]
x_start = 2.0
slope_deg = -3.0
)"));
  ASSERT_EQ(same.terrain.ground.breaks().size(), 1u);
  EXPECT_EQ(same.terrain.GroundHeight(5.0), s.terrain.GroundHeight(5.0));
  const Scenario none =
      LoadScenario(Write("none.toml", std::string(kMinimal) + "[terrain]\nslopes = []\n"));
  EXPECT_TRUE(none.terrain.ground.is_flat_zero());
}

// Steps join the profile: inside a slope piece they keep its slope, at a slope breakpoint they
// join it; obstacles stand on the upper level.
TEST_F(ScenarioFileTest, TerrainStepsJoinTheProfile) {
  constexpr double kDeg = M_PI / 180.0;
  const Scenario s = LoadScenario(Write("steps.toml", std::string(kMinimal) + R"(
[terrain]
slopes = [{ x_start = 2.0, slope_deg = -3.0 }, { x_start = 6.0, slope_deg = 0.0 }]
steps = [{ x_start = 4.0, rise = 0.03 }, { x_start = 6.0, rise = -0.05 }, { x_start = 8.0, rise = 0.02 }]
[[terrain.obstacles]]
x_start = 9.0
length = 0.2
height = 0.05
)"));
  const std::vector<SlopeBreak>& b = s.terrain.ground.breaks();
  ASSERT_EQ(b.size(), 4u);
  EXPECT_EQ(b[1].x_start, 4.0);
  EXPECT_DOUBLE_EQ(b[1].slope, -3.0 * kDeg);  // inside the 3 deg climb
  EXPECT_EQ(b[1].rise, 0.03);
  EXPECT_EQ(b[2].x_start, 6.0);  // joined with the slope breakpoint
  EXPECT_EQ(b[2].rise, -0.05);
  EXPECT_EQ(b[2].slope, 0.0);
  EXPECT_EQ(b[3].slope, 0.0);
  const double climb = 4.0 * std::tan(3 * kDeg);
  EXPECT_NEAR(s.terrain.GroundHeight(7.0), climb + 0.03 - 0.05, 1e-12);
  EXPECT_NEAR(s.terrain.ObstacleTop(0), climb + 0.03 - 0.05 + 0.02 + 0.05, 1e-12);
}

// Pushes given as an impulse, or timed by a touchdown or the hip's position.
TEST_F(ScenarioFileTest, PushesByImpulseAndEvent) {
  const Scenario s = LoadScenario(Write("push.toml", std::string(kMinimal) + R"(
[[push]]
after_touchdown = 7
phase = 0.25
duration = 0.05
impulse_n_s = -4.0
[[push]]
at_hip_x = 3.0
force_x = 30.0
[[push]]
start = 2.0
impulse_n_s = 6.0
)"));
  ASSERT_EQ(s.pushes.size(), 3u);
  EXPECT_EQ(s.pushes[0].after_touchdown, 7);
  EXPECT_EQ(s.pushes[0].phase, 0.25);
  EXPECT_TRUE(std::isnan(s.pushes[0].at_hip_x));
  EXPECT_DOUBLE_EQ(s.pushes[0].force.x() * s.pushes[0].duration, -4.0);
  EXPECT_TRUE(s.pushes[0].event_timed());
  EXPECT_EQ(s.pushes[1].at_hip_x, 3.0);
  EXPECT_EQ(s.pushes[1].after_touchdown, 0);
  EXPECT_EQ(s.pushes[1].force.x(), 30.0);
  EXPECT_FALSE(s.pushes[2].event_timed());
  EXPECT_EQ(s.pushes[2].start, 2.0);
  EXPECT_DOUBLE_EQ(s.pushes[2].force.x(), 60.0);  // over the default 0.1 s
}

TEST_F(ScenarioFileTest, BadSlopeProfilesNameTheirLineAndKey) {
  const std::string head = std::string(kMinimal) + "[terrain]\nslopes = [\n";  // lines 6, 7
  ExpectError(
      head + "  { x_start = 2.0, slope_deg = 1.0 },\n  { x_start = 1.0, slope_deg = 1 },\n]\n", 9,
      "terrain.slopes[2].x_start", "increasing x_start (the previous one is at 2");
  ExpectError(
      head + "  { x_start = 2.0, slope_deg = 1.0 },\n  { x_start = 2.0, slope_deg = 0 },\n]\n", 9,
      "terrain.slopes[2].x_start", "increasing x_start");
  ExpectError(head + "  { x_start = 2.0, slope_deg = 30.0 },\n]\n", 8,
              "terrain.slopes[1].slope_deg", "below 30 deg");
  ExpectError(head + "  { x_start = 2.0, slope_deg = -45 },\n]\n", 8, "terrain.slopes[1].slope_deg",
              "below 30 deg");
  ExpectError(head + "  { x_start = 2.0, slope_deg = nan },\n]\n", 8, "terrain.slopes[1].slope_deg",
              "finite");
  ExpectError(head + "  { x_start = inf, slope_deg = 1 },\n]\n", 8, "terrain.slopes[1].x_start",
              "finite");
  ExpectError(head + "  { x_start = 2e5, slope_deg = 1 },\n]\n", 8, "terrain.slopes[1].x_start",
              "1e4");
  ExpectError(head + "  { x_start = 2.0 },\n]\n", 8, "terrain.slopes[1]",
              "missing required key 'slope_deg'");
  ExpectError(head + "  { x_start = 2.0, slope_deg = 1, height = 3 },\n]\n", 8,
              "terrain.slopes[1].height", "unknown key");
  ExpectError(head + "  { x_start = 2.0, slope_deg = \"steep\" },\n]\n", 8,
              "terrain.slopes[1].slope_deg", "expected a number");
  // The array-of-pairs form is not the key's form.
  ExpectError(std::string(kMinimal) + "[terrain]\nslopes = [[2.0, 3.0]]\n", 7, "terrain.slopes",
              "expected an array of tables");
  // Not with the tilted-gravity uniform slope.
  ExpectError(std::string(kMinimal) +
                  "[terrain]\nslope_deg = 5\nslopes = [{ x_start = 2.0, slope_deg = 1 }]\n",
              8, "terrain.slopes", "does not combine with a uniform slope_deg");
  // Obstacles stand on flat parts only.
  ExpectError(std::string(kMinimal) +
                  "[terrain]\nslopes = [{ x_start = 2.0, slope_deg = 1 }]\n"
                  "[[terrain.obstacles]]\nx_start = 1.9\nlength = 0.2\nheight = 0.05\n",
              9, "terrain.obstacles[1].x_start", "stands on sloped ground");
}

TEST_F(ScenarioFileTest, ModelFileWithOverrides) {
  Write("model.toml", "[model]\ntrunk_mass = 15.0\nshin_length = 0.5\n");
  const Scenario s = LoadScenario(Write("ok.toml", std::string(kMinimal) + R"(
[model]
file = "model.toml"
shin_length = 0.45
)"));
  EXPECT_DOUBLE_EQ(s.model.trunk_mass, 15.0);
  EXPECT_DOUBLE_EQ(s.model.shin_length, 0.45);
}

TEST_F(ScenarioFileTest, UnknownKeyNamesKeyAndLine) {
  ExpectError(std::string(kMinimal) + "q0_dge = 3\n", 6, "initial.q0_dge", "unknown key");
  ExpectError("[simulation]\nduration = 1\nrtoll = 1e-6\n[initial]\ny = 1\n", 3, "simulation.rtoll",
              "unknown key");
  ExpectError(std::string("speed = 3\n") + kMinimal, 1, "speed", "unknown key");
  // A model file that does not exist: the scenario's file, line and key, not just the path.
  ExpectError(std::string("[model]\nfile = \"nowhere.toml\"\n") + kMinimal, 2, "model.file",
              "no model file");
}

TEST_F(ScenarioFileTest, WrongTypesAndValues) {
  ExpectError("[simulation]\nduration = \"long\"\n[initial]\ny = 1\n", 2, "simulation.duration",
              "expected a number");
  ExpectError("[simulation]\nduration = nan\n[initial]\ny = 1\n", 2, "simulation.duration",
              "finite");
  ExpectError("[simulation]\nduration = -1\n[initial]\ny = 1\n", 2, "simulation.duration",
              "[0, 3600] s");
  ExpectError("[simulation]\nduration = 1\nintegrator = \"euler\"\n[initial]\ny = 1\n", 3,
              "simulation.integrator", "cvode");
  ExpectError(std::string(kMinimal) + "[model]\nshin_mass = -3\n", 0, "model", "shin_mass");
  ExpectError(std::string(kMinimal) + "[contact]\nmu_s = 0.1\n", 0, "contact", "lambda_g");
  ExpectError(std::string(kMinimal) + "[controller]\ntype = \"walker\"\n", 7, "controller.type",
              "unknown controller");
  ExpectError(std::string(kMinimal) + "[controller]\ntype = \"pd_hold\"\nkp = [1, 2]\n", 8,
              "controller.kp", "expected 4 numbers");
  ExpectError(
      std::string(kMinimal) + "[[terrain.obstacles]]\nx_start = 1\nlength = 0.2\nheight = -0.05\n",
      9, "terrain.obstacles[1].height", "> 0");
}

TEST_F(ScenarioFileTest, ImpossibleStatesAndSettingsAreRefused) {
  ExpectError("[simulation]\nduration = 1\n[initial]\ny = 0.5\n", 0, "initial",
              "below its surface");
  ExpectError(
      "[simulation]\nduration = 1\n[initial]\nfoot_clearance = 0\nq11_deg = 10\n"
      "q21_deg = -10\n[[terrain.obstacles]]\nx_start = 0.05\nlength = 0.08\nheight = 0.3\n",
      0, "initial", "inside obstacle");
  ExpectError("[simulation]\nduration = 1\n[initial]\ny = 1\nxd = 1e300\n", 0, "initial", "rates");
  ExpectError("[simulation]\nduration = 1\ncontrol_rate_hz = 1e300\n[initial]\ny = 1\n", 3,
              "simulation.control_rate_hz", "Hz");
  ExpectError("[simulation]\nduration = 1e7\n[initial]\ny = 1\n", 2, "simulation.duration",
              "[0, 3600] s");
  ExpectError("[simulation]\nduration = 3000\ncontrol_rate_hz = 1e5\n[initial]\ny = 1\n", 2,
              "simulation.duration", "too long");
  ExpectError("[simulation]\nduration = 3000\nrecord_every = 1\n[initial]\ny = 1\n", 3,
              "simulation.record_every", "more than 1e+06 samples");
  ExpectError("[simulation]\nduration = 1\nrecord_every = 0\n[initial]\ny = 1\n", 3,
              "simulation.record_every", "[1, 1000000]");
  ExpectError("[simulation]\nduration = 1\nintegrator = \"cvode\"\norder = 7\n[initial]\ny = 1\n",
              0, "simulation", "1..5");
  ExpectError("[simulation]\nduration = 1\nfixed_step = -0.001\n[initial]\ny = 1\n", 0,
              "simulation", "fixed_step must be in [0, 1] s");
  ExpectError(
      "[simulation]\nduration = 1\nintegrator = \"cvode\"\nfixed_step = 0.001\n[initial]\ny = 1\n", 0,
      "simulation", "fixed_step needs the arkode integrator");
  ExpectError("[simulation]\nduration = 1\nrecord_every = 4294967296\n[initial]\ny = 1\n", 3,
              "simulation.record_every", "integer in");
  ExpectError(std::string("name = \"../escape\"\n") + kMinimal, 1, "name", "letters");
}

TEST_F(ScenarioFileTest, MissingPiecesAndSyntax) {
  ExpectError("[initial]\ny = 1\n", 0, "simulation", "missing required key 'duration'");
  ExpectError("[simulation]\nduration = 1\n", 0, "initial", "exactly one of");
  ExpectError("[simulation]\nduration = 1\n[initial]\ny = 1\nfoot_clearance = 0\n", 0, "initial",
              "exactly one of");
  ExpectError("[simulation\nduration = 1\n", 1, "", "TOML syntax error");
  try {
    LoadScenario((dir_ / "missing.toml").string());
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no such file"), std::string::npos);
  }
}

TEST_F(ScenarioFileTest, PragmaticControllerFromAGaitFile) {
  const std::string gait = std::string(RABBIT_SOURCE_DIR) + "/gaits/reference/vm_0.60.csv";
  const Scenario s = LoadScenario(Write("walk.toml",
                                        "[simulation]\nduration = 1\n"
                                        "[controller]\ntype = \"pragmatic\"\n"
                                        "gait = \"" +
                                            gait + "\"\nq0_d_deg = 3.0\n"));
  EXPECT_EQ(s.controller, ControllerKind::kPragmatic);
  EXPECT_NEAR(s.walking.rules.q0_d, 3.0 * M_PI / 180.0, 1e-12);  // overridden
  EXPECT_GT(s.qd0[kX], 0.0);                                     // the walking start's push
  ExpectError("[simulation]\nduration = 1\n[controller]\ntype = \"pragmatic\"\npulse = 3\n", 5,
              "controller.pulse", "unknown key");
  ExpectError(
      "[simulation]\nduration = 1\n[controller]\ntype = \"pragmatic\"\n"
      "[initial]\ny = 1\n",
      6, "initial.y", "unknown key");
}

TEST_F(ScenarioFileTest, ModelFileErrorsNameThatFile) {
  const std::string model = Write("model.toml", "[model]\ntrunk_mas = 15.0\n");
  try {
    LoadModelFile(model);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), model);
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.key(), "model.trunk_mas");
  }
}

}  // namespace
}  // namespace rabbit
