// Scenario suites: [defaults] under every scenario, errors that name the line where the bad value
// stands (in the scenario or in the defaults), randomised families that expand deterministically,
// and the documented bad inputs (unknown controller, negative obstacle height, a velocity profile
// with no points, an unknown key), each an InputError with file, line and key.
#include "rabbit/scenario/suite.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "rabbit/io/error.h"
#include "suite_fixture.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

const std::string kRoot = RABBIT_SOURCE_DIR;

class SuiteTest : public testing::SuiteFileTest {
 protected:
  SuiteTest() : SuiteFileTest("rabbit_suite_test") {}
  void ExpectError(const std::string& text, int line, const std::string& key,
                   const std::string& fragment) {
    ExpectSuiteError(text, line, key, fragment);
  }
  // A walker suite on the shipped gaits, with `extra` appended.
  std::string Walker(const std::string& extra) {
    return "[suite]\nname = \"t\"\n[defaults.simulation]\nduration = 2.0\n"  // lines 1-4
           "[defaults.velocity]\nvalue = 0.6\n"                              // lines 5-6
           "[defaults.controller]\ntype = \"fuzzy_cmac\"\n"                  // lines 7-8
           "fll = \"" +
           kRoot +
           "/gaits/gait_pattern.fll\"\n"  // line 9
           "networks = \"" +
           kRoot +
           "/gaits/networks\"\n"  // line 10
           "gaits = \"" +
           kRoot + "/gaits/reference\"\n" +  // line 11
           extra;
  }
};

TEST_F(SuiteTest, ShippedPaperSuiteLoads) {
  const Suite suite = LoadSuite(kRoot + "/scenarios/paper.toml");
  EXPECT_EQ(suite.name, "paper");
  ASSERT_EQ(suite.scenarios.size(), 15u);  // (a), (b), (c) and 12 obstacles anywhere
  EXPECT_EQ(suite.scenarios[0].name, "ramp");
  EXPECT_EQ(suite.scenarios[0].velocity.kind, VelocityProfile::Kind::kSteps);
  EXPECT_EQ(suite.scenarios[0].start_gait, "vm_0.40");  // nearest V_d(0) = 0.4
  EXPECT_EQ(suite.scenarios[1].start_gait, "vm_0.60");
  ASSERT_EQ(suite.scenarios[2].terrain.obstacles.size(), 1u);
  EXPECT_DOUBLE_EQ(suite.scenarios[2].terrain.obstacles[0].height, 0.05);
  for (size_t i = 0; i < suite.scenarios.size(); ++i) {
    const Scenario& s = suite.scenarios[i];
    EXPECT_EQ(s.controller, ControllerKind::kFuzzyCmac);
    EXPECT_EQ(s.baselines.size(), i < 3 ? 2u : 0u);
    EXPECT_EQ(s.required, i < 3);
    EXPECT_EQ(s.expected_outcome, "completed");
  }
}

TEST_F(SuiteTest, DefaultsApplyAndScenariosOverrideThem) {
  const Suite suite = LoadSuite(Write(Walker(R"(k_p = 0.3
[[scenario]]
name = "a"
[[scenario]]
name = "b"
[scenario.controller]
k_p = 0.1
[scenario.simulation]
distance = 3.0
)")));
  ASSERT_EQ(suite.scenarios.size(), 2u);
  EXPECT_DOUBLE_EQ(suite.scenarios[0].walker.k_p, 0.3);
  EXPECT_DOUBLE_EQ(suite.scenarios[1].walker.k_p, 0.1);
  EXPECT_DOUBLE_EQ(suite.scenarios[0].options.duration, 2.0);
  EXPECT_DOUBLE_EQ(suite.scenarios[1].options.stop_distance, 3.0);
  // The rest of [defaults.controller] still applies under b's own [scenario.controller].
  EXPECT_EQ(suite.scenarios[1].controller, ControllerKind::kFuzzyCmac);
}

TEST_F(SuiteTest, ErrorsNameTheLineInTheScenarioOrInTheDefaults) {
  // In the scenario's own table (line 14).
  ExpectError(Walker("[[scenario]]\nname = \"a\"\n[scenario.controller]\nhip_kq = 3\n"), 15,
              "scenario[1].controller.hip_kq", "unknown key");
  // In the defaults (line 12), reported for the scenario that reads it.
  ExpectError(Walker("k_vv = 0.1\n[[scenario]]\nname = \"a\"\n"), 12, "scenario[1].controller.k_vv",
              "unknown key");
}

TEST_F(SuiteTest, RecoveryKeysAreChecked) {
  const std::string head = "[[scenario]]\nname = \"a\"\n[scenario.controller.recovery]\n";
  ExpectError(Walker(head + "placement_gain = -1\n"), 15,
              "scenario[1].controller.recovery.placement_gain", "must be in [0, 10]");
  ExpectError(Walker(head + "placement_max = 2\n"), 15,
              "scenario[1].controller.recovery.placement_max", "must be in [0, 1] rad");
  ExpectError(Walker(head + "nominal_steps = 0\n"), 15,
              "scenario[1].controller.recovery.nominal_steps", "");
  ExpectError(Walker(head + "backward_step_speed = 9\n"), 15,
              "scenario[1].controller.recovery.backward_step_speed", "[-5, 5]");
  ExpectError(Walker(head + "response_reach = 1.5\n"), 15,
              "scenario[1].controller.recovery.response_reach", "must be in [0, 1]");
  ExpectError(Walker(head + "response_reach_dead = -0.1\n"), 15,
              "scenario[1].controller.recovery.response_reach_dead", "must be in [0, 2] m/s");
  ExpectError(Walker(head + "response_reach_ref_min = 3\n"), 15,
              "scenario[1].controller.recovery.response_reach_ref_min", "must be in [0, 2] m/s");
  ExpectError(Walker(head + "placment_gain = 1\n"), 15,
              "scenario[1].controller.recovery.placment_gain", "unknown key");
  ExpectError(Walker(head + "enabled = 1\n"), 15, "scenario[1].controller.recovery.enabled", "");
  const Suite suite = LoadSuite(Write(Walker(head + "enabled = false\nplacement_gain = 0.4\n"
                                                    "response_reach = 0.5\n")));
  EXPECT_FALSE(suite.scenarios[0].walker.recovery.enabled);
  EXPECT_DOUBLE_EQ(suite.scenarios[0].walker.recovery.placement_gain, 0.4);
  EXPECT_DOUBLE_EQ(suite.scenarios[0].walker.recovery.response_reach, 0.5);
}

TEST_F(SuiteTest, BadInputOfTheIssue) {
  ExpectError(Walker("[[scenario]]\nname = \"a\"\n[scenario.controller]\ntype = \"fuzzy\"\n"), 15,
              "scenario[1].controller.type", "unknown controller \"fuzzy\"");
  ExpectError(Walker("[[scenario]]\nname = \"a\"\n[[scenario.terrain.obstacles]]\nx_start = 3.0\n"
                     "length = 0.2\nheight = -0.05\n"),
              17, "scenario[1].terrain.obstacles[1].height", "must be > 0");
  ExpectError(Walker("[[scenario]]\nname = \"a\"\n[scenario.velocity]\nprofile = \"ramp\"\n"
                     "points = []\n"),
              -1, "scenario[1].velocity.points", "no points");
  ExpectError(Walker("[[scenario]]\nname = \"a\"\nspeed = 3\n"), 14, "scenario[1].speed",
              "unknown key");
  ExpectError(Walker("[[scenario]]\nname = \"a\"\n[scenario.velocity]\nprofile = \"ramp\"\n"
                     "points = [[0, 0.5], [0, 0.6]]\n"),
              -1, "scenario[1].velocity.points", "times must increase");
  ExpectError(Walker("[[scenario]]\nname = \"a\"\n[scenario.controller]\nbaselines = [\"x\"]\n"),
              15, "scenario[1].controller.baselines", "unknown baseline");
  ExpectError(Walker("[[scenario]]\nname = \"a\"\n[[scenario]]\nname = \"a\"\n"), 0, "a",
              "two scenarios named");
  ExpectError(Walker("[[scenario]]\nname = \"a\"\n[scenario.controller]\nstart_gait = \"vm_9\"\n"),
              15, "scenario[1].controller.start_gait", "no gait");
  ExpectError(Walker("[[scenario]]\nname = \"a\"\n[[scenario.push]]\nstart = 1.0\nforce_x = nan\n"),
              16, "scenario[1].push[1].force_x", "finite");
  ExpectError("[suite]\nname = \"t\"\n", 1, "", "no [[scenario]]");
  // rule_share is a per-gait setting of the gait database: a positional array is refused,
  // naming its replacement.
  ExpectError(Walker("[[scenario]]\nname = \"a\"\n[scenario.controller]\nrule_share = [1, 0]\n"),
              15, "scenario[1].controller.rule_share", "walker.csv");
  ExpectError(Walker("[[scenario]]\nname = \"a\"\n[scenario.controller]\n"
                     "rule_share = [1, 0, 0, 0, 0, 1, 1, 1]\n"),
              15, "scenario[1].controller.rule_share", "rule_share column");
}

TEST_F(SuiteTest, FamiliesExpandDeterministically) {
  const std::string text = Walker(R"([[family]]
name = "obst"
count = 6
seed = 42
[family.scenario]
[[family.scenario.terrain.obstacles]]
x_start = 3.0
length = 0.2
height = 0.05
[family.scenario.velocity]
value = 0.6
[family.vary]
"terrain.obstacles.1.x_start" = [2.0, 2.5]
"velocity.value" = [0.5, 0.7]
)");
  const Suite a = LoadSuite(Write(text));
  const Suite b = LoadSuite(Write(text));
  ASSERT_EQ(a.scenarios.size(), 6u);
  std::set<double> positions;
  for (size_t i = 0; i < 6; ++i) {
    const Scenario& s = a.scenarios[i];
    char name[16];
    std::snprintf(name, sizeof name, "obst-%03zu", i);
    EXPECT_EQ(s.name, name);
    const double x = s.terrain.obstacles.at(0).x_start;
    EXPECT_GE(x, 2.0);
    EXPECT_LT(x, 2.5);
    EXPECT_DOUBLE_EQ(x,
                     FamilyDraw(42, static_cast<int>(i), "terrain.obstacles.1.x_start", 2.0, 2.5));
    EXPECT_DOUBLE_EQ(s.velocity.At(0.0),
                     FamilyDraw(42, static_cast<int>(i), "velocity.value", 0.5, 0.7));
    EXPECT_DOUBLE_EQ(s.terrain.obstacles[0].height, 0.05);  // not varied: the template's
    EXPECT_DOUBLE_EQ(x, b.scenarios[i].terrain.obstacles[0].x_start);
    EXPECT_EQ(s.seed, b.scenarios[i].seed);
    positions.insert(x);
  }
  EXPECT_EQ(positions.size(), 6u);
  EXPECT_NE(a.scenarios[0].seed, a.scenarios[1].seed);
  // Each member knows its family (the report's head-to-head groups by it); a plain scenario has
  // none.
  for (const Scenario& s : a.scenarios) EXPECT_EQ(s.family, "obst");
  const Suite paper = LoadSuite(kRoot + "/scenarios/paper.toml");
  EXPECT_EQ(paper.scenarios.front().family, "");
  EXPECT_EQ(paper.scenarios.back().family, "obstacle_anywhere");
}

// The robustness families' draws: an element of an array of arrays (velocity points), a magnitude
// with a random sign, and a varied key of a table taken whole ([velocity]) keeping the table's
// other keys.
TEST_F(SuiteTest, FamiliesVaryNestedArraysSignsAndWholeTables) {
  const std::string text = Walker(R"([[family]]
name = "v"
count = 40
seed = 7
[family.scenario.velocity]
profile = "steps"
points = [[0.0, 0.6], [10.0, 0.6]]
[[family.scenario.push]]
start = 8.0
duration = 0.1
force_x = 50.0
height = 0.2
[family.vary]
"velocity.points.2.2" = [0.3, 1.0]
"push.1.force_x" = { range = [20.0, 80.0], random_sign = true }
)");
  const Suite suite = LoadSuite(Write(text));
  ASSERT_EQ(suite.scenarios.size(), 40u);
  int negative = 0;
  for (size_t i = 0; i < suite.scenarios.size(); ++i) {
    const Scenario& s = suite.scenarios[i];
    const int member = static_cast<int>(i);
    EXPECT_EQ(s.velocity.kind, VelocityProfile::Kind::kSteps);  // the profile key survived
    ASSERT_EQ(s.velocity.points.size(), 2u);
    EXPECT_DOUBLE_EQ(s.velocity.points[0].second, 0.6);  // not varied
    EXPECT_DOUBLE_EQ(s.velocity.points[1].first, 10.0);
    EXPECT_DOUBLE_EQ(s.velocity.points[1].second,
                     FamilyDraw(7, member, "velocity.points.2.2", 0.3, 1.0));
    ASSERT_EQ(s.pushes.size(), 1u);
    const double magnitude = FamilyDraw(7, member, "push.1.force_x", 20.0, 80.0);
    const bool flip = FamilyDraw(7, member, "push.1.force_x#sign", 0.0, 1.0) < 0.5;
    EXPECT_DOUBLE_EQ(s.pushes[0].force.x(), flip ? -magnitude : magnitude);
    EXPECT_GE(std::abs(s.pushes[0].force.x()), 20.0);
    EXPECT_LT(std::abs(s.pushes[0].force.x()), 80.0);
    negative += s.pushes[0].force.x() < 0.0;
  }
  EXPECT_GT(negative, 10);  // both signs, about half each
  EXPECT_LT(negative, 30);
  const std::string head = Walker(
      "[[family]]\nname = \"f\"\ncount = 2\n"
      "[family.scenario.velocity]\nprofile = \"steps\"\n"
      "points = [[0.0, 0.6], [10.0, 0.6]]\n[family.vary]\n");
  ExpectError(head + "\"velocity.points.3.2\" = [0.3, 1.0]\n", 19,
              "family[1].vary.velocity.points.3.2", "1-based index within its 2");
  ExpectError(head + "\"velocity.points.1.3\" = [0.3, 1.0]\n", 19,
              "family[1].vary.velocity.points.1.3", "1-based index within its 2");
  ExpectError(head + "\"velocity.points.1\" = { random_sign = true }\n", 19,
              "family[1].vary.velocity.points.1.range", "missing required key 'range'");
}

// lift_keeps_rules ([controller], default false: the rule share is suspended while the foot lift
// is armed).
TEST_F(SuiteTest, LiftKeepsRulesIsAControllerKey) {
  EXPECT_FALSE(LoadSuite(Write(Walker("[[scenario]]\nname = \"a\"\n")))
                   .scenarios[0]
                   .walker.lift.keeps_rules);
  EXPECT_TRUE(LoadSuite(Write(Walker("lift_keeps_rules = true\n[[scenario]]\nname = \"a\"\n")))
                  .scenarios[0]
                  .walker.lift.keeps_rules);
  ExpectError(Walker("lift_keeps_rules = 2\n[[scenario]]\nname = \"a\"\n"), 12,
              "scenario[1].controller.lift_keeps_rules", "");
}

// The walk starts on the gait the walker walks at V_d(0). At 0.355 m/s the shipped vm_0.40 gait
// (0.390 m/s measured) is nearer than vm_0.30 (0.303 m/s), but the adaptive walker's gait choice
// keeps the slowest gait up to 0.75 of the way between them (0.368 m/s), so its walk starts on
// vm_0.30; the chapter's walker (no gait choice), a named start gait and a command above the
// switch start on the nearest gait.
TEST_F(SuiteTest, TheWalkStartsOnTheGaitTheWalkerWalksAtTheFirstCommand) {
  const std::string scenarios =
      "database = \"" + kRoot +
      "/gaits\"\n"
      "[[scenario]]\nname = \"adaptive\"\n[scenario.velocity]\nvalue = 0.355\n"
      "[[scenario]]\nname = \"chapter\"\n[scenario.velocity]\nvalue = 0.355\n"
      "[scenario.controller]\npreset = \"chapter\"\n"
      "[[scenario]]\nname = \"named\"\n[scenario.velocity]\nvalue = 0.355\n"
      "[scenario.controller]\nstart_gait = \"vm_0.40\"\n"
      "[[scenario]]\nname = \"above\"\n[scenario.velocity]\nvalue = 0.372\n";
  const Suite suite = LoadSuite(Write(Walker(scenarios)));
  ASSERT_EQ(suite.scenarios.size(), 4u);
  EXPECT_EQ(suite.scenarios[0].start_gait, "vm_0.30");
  EXPECT_EQ(suite.scenarios[1].start_gait, "vm_0.40");
  EXPECT_EQ(suite.scenarios[2].start_gait, "vm_0.40");
  EXPECT_EQ(suite.scenarios[3].start_gait, "vm_0.40");
  // The start state, the warm-up and the walker's initial values all come from the start gait
  // (vm_0.30: trunk pitch -1.5 deg, lock angle 12.5 deg, 0.303 m/s measured).
  const Scenario& a = suite.scenarios[0];
  EXPECT_NEAR(a.walking.rules.q0_d, -1.5 * M_PI / 180.0, 1e-12);
  EXPECT_NEAR(a.walker.warmup.qr1_dsw, 12.5 * M_PI / 180.0, 1e-12);
  EXPECT_NEAR(a.walker.q0_d_initial, -1.5 * M_PI / 180.0, 1e-12);
  EXPECT_NEAR(a.walker.v_m_initial, 0.303, 5e-4);
  EXPECT_NEAR(suite.scenarios[1].walker.v_m_initial, 0.390, 5e-4);
  // Keys of the scenario are read over the preset whichever gait the walk starts on.
  const Suite keyed = LoadSuite(Write(Walker("k_p = 0.3\n" + scenarios)));
  EXPECT_EQ(keyed.scenarios[0].start_gait, "vm_0.30");
  EXPECT_DOUBLE_EQ(keyed.scenarios[0].walker.k_p, 0.3);
  // The effective settings a tuning job reports are those of the gait the walk starts on (not the
  // nearest gait's: vm_0.40, 0 deg and 0.390 m/s).
  std::vector<std::map<std::string, double>> settings;
  LoadSuite(Write(Walker(scenarios)), nullptr, &settings);
  ASSERT_EQ(settings.size(), 4u);
  EXPECT_NEAR(settings[0].at("controller.q0_d_initial_deg"), -1.5, 1e-12);
  EXPECT_NEAR(settings[0].at("controller.v_m_initial"), a.walker.v_m_initial, 1e-12);
}

// [suite.targets]: success rates in (0, 1] for families or scenarios of the suite.
TEST_F(SuiteTest, TargetsNameGroupsOfTheSuite) {
  const std::string family = "[[family]]\nname = \"f\"\ncount = 2\n";
  const Suite suite = LoadSuite(Write(Walker("[suite.targets]\nf = 0.95\n" + family)));
  ASSERT_EQ(suite.targets.size(), 1u);
  EXPECT_EQ(suite.targets[0].first, "f");
  EXPECT_DOUBLE_EQ(suite.targets[0].second, 0.95);
  EXPECT_EQ(TargetsCsv(suite), "group,target_success_rate\nf,0.95\n");
  ExpectError(Walker("[suite.targets]\nf = 1.5\n" + family), 13, "suite.targets.f", "(0, 1]");
  ExpectError(Walker("[suite.targets]\ng = 0.5\n" + family), 13, "suite.targets.g",
              "no family or scenario");
}

// scenarios/robustness_train.toml is robustness.toml on other seeds: the same families and
// templates, only [suite] and each family's seed and count differ.
TEST_F(SuiteTest, RobustnessTrainingSuiteMatchesTheHeldOutOne) {
  const Suite held_out = LoadSuite(kRoot + "/scenarios/robustness.toml");
  const Suite train = LoadSuite(kRoot + "/scenarios/robustness_train.toml");
  const Suite ci = LoadSuite(kRoot + "/scenarios/robustness_ci.toml");
  std::map<std::string, int> held_out_count, train_count, ci_count;
  auto family = [](const std::string& name) { return name.substr(0, name.rfind('-')); };
  for (const Scenario& s : held_out.scenarios) ++held_out_count[family(s.name)];
  for (const Scenario& s : train.scenarios) ++train_count[family(s.name)];
  for (const Scenario& s : ci.scenarios) ++ci_count[family(s.name)];
  ASSERT_EQ(held_out_count.size(), train_count.size());
  ASSERT_EQ(held_out_count.size(), ci_count.size());
  for (const auto& [name, count] : held_out_count) {
    EXPECT_GE(count, 100) << name;  // at least 100 scenarios per family
    EXPECT_GE(train_count[name], 30) << name;
    EXPECT_GE(ci_count[name], 2) << name;  // CI: a few members per family
    EXPECT_LE(ci_count[name], 3) << name;
  }
  // The CI subset is the training suite's first members (the same seeds), never held-out ones.
  std::map<std::string, const Scenario*> train_by_name;
  for (const Scenario& s : train.scenarios) train_by_name[s.name] = &s;
  for (const Scenario& s : ci.scenarios) {
    ASSERT_EQ(train_by_name.count(s.name), 1u) << s.name;
    EXPECT_EQ(train_by_name[s.name]->seed, s.seed) << s.name;
  }
  // Line by line, the files differ only in the documented places.
  auto lines = [](const std::string& path) {
    std::ifstream in(path);
    std::vector<std::string> out;
    for (std::string line; std::getline(in, line);) {
      if (line.empty() || line[0] == '#' || line.rfind("name = \"robustness", 0) == 0 ||
          line.rfind("description = ", 0) == 0 || line.rfind("count = ", 0) == 0 ||
          line.rfind("seed = ", 0) == 0) {
        continue;
      }
      out.push_back(line);
    }
    return out;
  };
  EXPECT_EQ(lines(kRoot + "/scenarios/robustness.toml"),
            lines(kRoot + "/scenarios/robustness_train.toml"));
  EXPECT_EQ(lines(kRoot + "/scenarios/robustness.toml"),
            lines(kRoot + "/scenarios/robustness_ci.toml"));
  // No member's draws repeat across the two files (different family seeds).
  std::set<double> positions;
  for (const Scenario& s : held_out.scenarios) {
    if (family(s.name) == "obstacle") positions.insert(s.terrain.obstacles.at(0).x_start);
  }
  for (const Scenario& s : train.scenarios) {
    if (family(s.name) == "obstacle") {
      EXPECT_EQ(positions.count(s.terrain.obstacles.at(0).x_start), 0u) << s.name;
    }
  }
}

TEST_F(SuiteTest, RobustnessSuitesKeepTheDefaultTravelAndStallCriteria) {
  // The held-out and training suites measure success with the documented defaults: none of their
  // walking scenarios may ask for less forward travel or a looser stall watch.
  const PassCriteria defaults;
  for (const char* file : {"/scenarios/robustness.toml", "/scenarios/robustness_train.toml"}) {
    const Suite suite = LoadSuite(kRoot + file);
    ASSERT_FALSE(suite.scenarios.empty());
    for (const Scenario& s : suite.scenarios) {
      ASSERT_EQ(s.controller, ControllerKind::kFuzzyCmac) << s.name;
      EXPECT_EQ(s.criteria.min_travel_ratio, defaults.min_travel_ratio) << file << " " << s.name;
      EXPECT_EQ(s.criteria.stall.no_touchdown, defaults.stall.no_touchdown) << s.name;
      EXPECT_EQ(s.criteria.stall.window, defaults.stall.window) << s.name;
      EXPECT_EQ(s.criteria.stall.min_advance, defaults.stall.min_advance) << s.name;
    }
  }
  EXPECT_EQ(defaults.min_travel_ratio, 0.7);
  EXPECT_EQ(defaults.stall.no_touchdown, 2.0);
  EXPECT_EQ(defaults.stall.window, 3.0);
  EXPECT_EQ(defaults.stall.min_advance, 0.1);
}

TEST_F(SuiteTest, FamilyErrors) {
  const std::string head = Walker("[[family]]\nname = \"f\"\ncount = 2\n[family.vary]\n");
  ExpectError(head + "\"terrain.slope\" = [0, 1]\n", 16, "family[1].vary.terrain.slope",
              "names no value");
  ExpectError(head + "\"velocity.value\" = [0.7, 0.5]\n", 16, "family[1].vary.velocity.value",
              "low <= high");
  ExpectError(Walker("[[family]]\nname = \"f\"\ncount = 0\n"), 14, "family[1].count",
              "integer in [1, 10000]");
  // The review's crashes: paths through the member's name or seed, or past a leaf in an array.
  ExpectError(head + "\"name.x\" = [0, 1]\n", 16, "family[1].vary.name.x", "not varied");
  ExpectError(head + "\"seed\" = [0, 1]\n", 16, "family[1].vary.seed", "not varied");
  ExpectError(Walker("[[family]]\nname = \"f\"\ncount = 2\n[[family.scenario.terrain.obstacles]]\n"
                     "x_start = 3.0\nlength = 0.2\nheight = 0.05\n[family.vary]\n"
                     "\"terrain.obstacles.1.x_start.foo\" = [0, 1]\n"),
              20, "family[1].vary.terrain.obstacles.1.x_start.foo", "not a table");
}

TEST_F(SuiteTest, ReviewFindings) {
  // A scenario may change the controller type of its defaults: their keys do not leak in.
  const Suite mixed = LoadSuite(Write(
      Walker("[[scenario]]\nname = \"hold\"\n[scenario.initial]\ny = 0.9\n[scenario.controller]\n"
             "type = \"pd_hold\"\nkp = 300\n[[scenario]]\nname = \"walk\"\n")));
  ASSERT_EQ(mixed.scenarios.size(), 2u);
  EXPECT_EQ(mixed.scenarios[0].controller, ControllerKind::kPdHold);
  EXPECT_DOUBLE_EQ(mixed.scenarios[0].pd_hold.kp[0], 300.0);
  EXPECT_EQ(mixed.scenarios[1].controller, ControllerKind::kFuzzyCmac);
  // Names taken by the report's own files.
  ExpectError(Walker("[[scenario]]\nname = \"summary.csv\"\n"), 13, "scenario[1].name",
              "taken by the report");
  ExpectError(Walker("[[scenario]]\nname = \"shards\"\n"), 13, "scenario[1].name",
              "taken by the report");  // where a sharded run's parts wait for their merge
  ExpectError(Walker("[[scenario]]\nname = \"comparison.csv\"\n"), 13, "scenario[1].name",
              "taken by the report");
  // A constant profile with both a value and points.
  ExpectError(Walker("[[scenario]]\nname = \"a\"\n[scenario.velocity]\nvalue = 0.5\n"
                     "points = [[0, 0.6]]\n"),
              -1, "scenario[1].velocity.points", "not both");
  // Two families of one name, found before either expands.
  const std::string family = "[[family]]\nname = \"f\"\ncount = 2\n";
  ExpectError(Walker(family + family), 16, "family[2].name", "two families named");
  // The suite's total is bounded (cheap scenarios: 3 x 10000 > 20000).
  const std::string big =
      "[[family]]\nname = \"%\"\ncount = 10000\n[family.scenario]\n[family.scenario.simulation]\n"
      "duration = 1.0\n[family.scenario.initial]\ny = 0.9\n";
  std::string text;
  for (const char* n : {"a", "b", "c"}) {
    std::string f = big;
    f.replace(f.find('%'), 1, n);
    text += f;
  }
  ExpectError(text, -1, "family[3].count", "more than 20000 scenarios");
}

TEST_F(SuiteTest, TheMultiCmacBaselineAndItsSettings) {
  const Suite suite = LoadSuite(Write(Walker(
      "baselines = [\"pragmatic\", \"nearest_gait\", \"multi_cmac\"]\n"
      "[defaults.controller.multi_cmac]\ne_quantum_deg = 0.5\nhash_table_size = 1024\n"
      "[[scenario]]\nname = \"a\"\n[[scenario]]\nname = \"b\"\n[scenario.controller.multi_cmac]\n"
      "ridge = 0.01\nmax_iterations = 50\n")));
  ASSERT_EQ(suite.scenarios.size(), 2u);
  const Scenario& a = suite.scenarios[0];
  EXPECT_EQ(a.baselines, (std::vector<std::string>{"pragmatic", "nearest_gait", "multi_cmac"}));
  const double kTolerance = 1e-15;
  EXPECT_NEAR(a.multi_cmac.e_quantum, 0.5 * M_PI / 180.0, kTolerance);
  EXPECT_EQ(a.multi_cmac.hash_table_size, 1024);
  const MultiCmacPatternOptions defaults;
  EXPECT_EQ(a.multi_cmac.ridge, defaults.ridge);
  EXPECT_EQ(a.multi_cmac.grid_v_m_step, defaults.grid_v_m_step);
  EXPECT_EQ(suite.scenarios[1].multi_cmac.ridge, 0.01);
  EXPECT_EQ(suite.scenarios[1].multi_cmac.max_iterations, 50);
  EXPECT_EQ(suite.scenarios[1].multi_cmac.hash_table_size, 1024);  // from the defaults
  // Bad keys and values, named with their line (13: the first key of the table at line 12).
  const std::string table = "[defaults.controller.multi_cmac]\n";
  const std::string scenario = "[[scenario]]\nname = \"a\"\n";
  const std::string prefix = "scenario[1].controller.multi_cmac.";
  ExpectError(Walker(table + "e_widht = 6\n" + scenario), 13, prefix + "e_widht", "unknown key");
  ExpectError(Walker(table + "v_m_width = 4\n" + scenario), 13, prefix + "v_m_width",
              "must be >= layers (6)");
  ExpectError(Walker(table + "e_quantum_deg = -0.25\n" + scenario), 13, prefix + "e_quantum_deg",
              "must be > 0");
  ExpectError(Walker(table + "hash_table_size = 0\n" + scenario), 13, prefix + "hash_table_size",
              "4194304");
  ExpectError(Walker(table + "grid_d_obs_step = nan\n" + scenario), 13, prefix + "grid_d_obs_step",
              "finite");
  ExpectError(Walker(table + "tolerance = 2\n" + scenario), 13, prefix + "tolerance", "(0, 1)");
  ExpectError(Walker(table + "layers = \"six\"\n" + scenario), 13, prefix + "layers", "integer");
  ExpectError(Walker(scenario + "[scenario.controller.multi_cmac]\nridge = 0\n"), 15,
              prefix + "ridge", "must be > 0");
  ExpectError(
      Walker(scenario + "[scenario.controller]\nbaselines = [\"multi_cmac\", \"multi_cmac\"]\n"),
      15, "scenario[1].controller.baselines", "listed twice");
}

TEST_F(SuiteTest, AScenarioFileIsASuiteOfOne) {
  const Suite suite = LoadSuite(kRoot + "/scenarios/standing_pd_hold.toml");
  ASSERT_EQ(suite.scenarios.size(), 1u);
  EXPECT_EQ(suite.name, "standing_pd_hold");
}

// A suite read as one scenario (rabbit simulate) is named as a suite, whichever of its tables
// comes first, and not by the first scenario key it lacks.
TEST_F(SuiteTest, ASuiteIsNotAScenario) {
  EXPECT_NO_THROW(LoadScenario(kRoot + "/scenarios/standing_pd_hold.toml"));
  for (const std::string& text :
       {std::string("[suite]\nname = \"s\"\n"), std::string("[[scenario]]\nname = \"a\"\n"),
        std::string("[[family]]\nname = \"f\"\n")}) {
    SCOPED_TRACE(text);
    const std::string path = Write("suite.toml", text);
    try {
      LoadScenario(path);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()),
                path + ": this is a suite of scenarios: run it with `rabbit run`");
    }
  }
}

}  // namespace
}  // namespace rabbit
