// Family draws (rabbit/scenario/family_draws.h): the expression language against hand-computed
// values, named draws shared by several keys, keys derived from draws, the velocity profile with
// a drawn number of changes, integer draws, members.csv, and the errors for bad entries.
#include "rabbit/scenario/family_draws.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "rabbit/io/csv_table.h"
#include "rabbit/io/error.h"
#include "rabbit/scenario/suite.h"
#include "suite_fixture.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

const std::string kRoot = RABBIT_SOURCE_DIR;

class FamilyDrawsTest : public testing::SuiteFileTest {
 protected:
  FamilyDrawsTest() : SuiteFileTest("rabbit_family_draws_test") {}
  // A suite of one family on the shipped walker, with the family's body `family` (line 12 on).
  std::string Family(const std::string& family) {
    return "[suite]\nname = \"t\"\n[defaults.simulation]\nduration = 2.0\n"  // lines 1-4
           "[defaults.velocity]\nvalue = 0.6\n"                              // lines 5-6
           "[defaults.controller]\ntype = \"fuzzy_cmac\"\n"                  // lines 7-8
           "database = \"" +
           kRoot + "/gaits\"\n" +                  // line 9
           "[[family]]\nname = \"f\"\n" + family;  // lines 10-11
  }
  void ExpectError(const std::string& text, const std::string& key, const std::string& fragment) {
    ExpectSuiteError(text, -1, key, fragment);
  }
};

TEST(DrawExpressionTest, ArithmeticWithPrecedence) {
  const std::map<std::string, double> names = {{"a", 2.0}, {"b_2", 5.0}};
  double v = 0.0;
  std::string error;
  ASSERT_TRUE(EvaluateDrawExpression("a + b_2 * 3", names, &v, &error)) << error;
  EXPECT_DOUBLE_EQ(v, 17.0);
  ASSERT_TRUE(EvaluateDrawExpression("(a + b_2) * 3 - -1", names, &v, &error)) << error;
  EXPECT_DOUBLE_EQ(v, 22.0);
  ASSERT_TRUE(EvaluateDrawExpression(" 12 / a / 3 ", names, &v, &error)) << error;
  EXPECT_DOUBLE_EQ(v, 2.0);
  ASSERT_TRUE(EvaluateDrawExpression("1.5e1 - a", names, &v, &error)) << error;
  EXPECT_DOUBLE_EQ(v, 13.0);
  EXPECT_FALSE(EvaluateDrawExpression("a / (b_2 - 5)", names, &v, &error));
  EXPECT_NE(error.find("division by zero"), std::string::npos) << error;
  EXPECT_FALSE(EvaluateDrawExpression("a + c", names, &v, &error));
  EXPECT_NE(error.find("'c' names no draw"), std::string::npos) << error;
  EXPECT_FALSE(EvaluateDrawExpression("a +", names, &v, &error));
  EXPECT_FALSE(EvaluateDrawExpression("(a", names, &v, &error));
  EXPECT_NE(error.find("')' expected"), std::string::npos) << error;
  EXPECT_FALSE(EvaluateDrawExpression("a b", names, &v, &error));
  EXPECT_FALSE(EvaluateDrawExpression("", names, &v, &error));
  EXPECT_FALSE(EvaluateDrawExpression(std::string(200, '('), names, &v, &error));
}

// One drawn value shared by two velocity points, and a push whose force is derived from a drawn
// impulse and duration.
TEST_F(FamilyDrawsTest, SharedAndDerivedDraws) {
  const std::string text = Family(R"(count = 20
seed = 9
[family.scenario.velocity]
profile = "steps"
points = [[0.0, 0.6], [8.0, 0.6], [16.0, 0.6]]
[[family.scenario.push]]
start = 5.0
duration = 0.1
force_x = 0.0
[family.draw]
v = [0.3, 1.0]
impulse = { range = [2.0, 20.0], random_sign = true }
duration = [0.05, 0.2]
[family.vary]
"velocity.points.2.2" = "=v"
"velocity.points.3.2" = "= v"
"push.1.duration" = "=duration"
"push.1.force_x" = "=impulse / duration"
)");
  const Suite suite = LoadSuite(Write(text));
  ASSERT_EQ(suite.scenarios.size(), 20u);
  ASSERT_EQ(suite.members.size(), 1u);
  int negative = 0;
  for (int i = 0; i < 20; ++i) {
    const Scenario& s = suite.scenarios[i];
    const double v = FamilyDraw(9, i, "draw:v", 0.3, 1.0);
    EXPECT_DOUBLE_EQ(s.velocity.points[1].second, v);
    EXPECT_DOUBLE_EQ(s.velocity.points[2].second, v);
    EXPECT_DOUBLE_EQ(s.velocity.points[0].second, 0.6);
    const double magnitude = FamilyDraw(9, i, "draw:impulse", 2.0, 20.0);
    const double impulse =
        FamilyDraw(9, i, "draw:impulse#sign", 0.0, 1.0) < 0.5 ? -magnitude : magnitude;
    const double duration = FamilyDraw(9, i, "draw:duration", 0.05, 0.2);
    EXPECT_DOUBLE_EQ(s.pushes.at(0).duration, duration);
    // The impulse of the applied push is the drawn one.
    EXPECT_NEAR(s.pushes[0].force.x() * s.pushes[0].duration, impulse, 1e-12);
    negative += impulse < 0.0;
    // The member's row: the draws, then the keys.
    const MemberRow& row = suite.members[0].members[i];
    EXPECT_EQ(row.name, s.name);
    EXPECT_EQ(row.seed, s.seed);
    ASSERT_EQ(row.values.size(), 7u);
    std::map<std::string, double> values(row.values.begin(), row.values.end());
    EXPECT_DOUBLE_EQ(values.at("v"), v);
    EXPECT_DOUBLE_EQ(values.at("impulse"), impulse);
    EXPECT_DOUBLE_EQ(values.at("push.1.force_x"), s.pushes[0].force.x());
  }
  EXPECT_GT(negative, 3);
  EXPECT_LT(negative, 17);
}

// velocity.changes: the number of changes, their times and levels drawn per member.
TEST_F(FamilyDrawsTest, VelocityChangesDrawTheirCount) {
  const std::string text = Family(R"(count = 60
seed = 3
[family.scenario.simulation]
duration = 10.0
[family.vary]
"velocity.changes" = { count = [3, 5], every_s = [6.0, 10.0], v = [0.3, 1.0], first_s = [4.0, 5.0] }
"simulation.duration" = "=changes_end_s + 12"
)");
  const Suite suite = LoadSuite(Write(text));
  std::set<size_t> counts;
  for (size_t i = 0; i < suite.scenarios.size(); ++i) {
    const Scenario& s = suite.scenarios[i];
    EXPECT_EQ(s.velocity.kind, VelocityProfile::Kind::kSteps);
    const size_t changes = s.velocity.points.size() - 1;
    counts.insert(changes);
    EXPECT_DOUBLE_EQ(s.velocity.points[0].first, 0.0);
    EXPECT_GE(s.velocity.points[1].first, 4.0);
    EXPECT_LT(s.velocity.points[1].first, 5.0);
    for (size_t k = 0; k < s.velocity.points.size(); ++k) {
      EXPECT_GE(s.velocity.points[k].second, 0.3);
      EXPECT_LT(s.velocity.points[k].second, 1.0);
      if (k >= 2) {
        const double hold = s.velocity.points[k].first - s.velocity.points[k - 1].first;
        EXPECT_GE(hold, 6.0);
        EXPECT_LT(hold, 10.0);
      }
    }
    EXPECT_DOUBLE_EQ(s.options.duration, s.velocity.points.back().first + 12.0);
    const MemberRow& row = suite.members[0].members[i];
    EXPECT_EQ(row.values[0].first, "velocity.changes.count");
    EXPECT_EQ(row.values[0].second, static_cast<double>(changes));
  }
  EXPECT_EQ(counts, (std::set<size_t>{3, 4, 5}));  // every count, both ends included
  // With a ramp time, a ramp profile: hold, then ramp to the next level.
  const Suite ramps = LoadSuite(Write(Family(R"(count = 5
[family.scenario.velocity]
profile = "ramp"
points = [[0.0, 0.4], [1.0, 0.5]]
[family.vary]
"velocity.changes" = { count = 2, every_s = [5.0, 6.0], v = [0.4, 0.9], ramp_s = [2.0, 3.0] }
)")));
  for (const Scenario& s : ramps.scenarios) {
    EXPECT_EQ(s.velocity.kind, VelocityProfile::Kind::kRamp);
    ASSERT_EQ(s.velocity.points.size(), 5u);
    EXPECT_DOUBLE_EQ(s.velocity.points[0].second, s.velocity.points[1].second);
    const double ramp = s.velocity.points[2].first - s.velocity.points[1].first;
    EXPECT_GE(ramp, 2.0);
    EXPECT_LT(ramp, 3.0);
  }
}

TEST_F(FamilyDrawsTest, IntegerDrawsAndMembersCsv) {
  const Suite suite = LoadSuite(Write(Family(R"(count = 30
seed = 4
[[family.scenario.push]]
start = 5.0
force_x = 10.0
[family.draw]
k = { range = [1, 3], integer = true }
[family.vary]
"push.1.start" = "=k * 2"
"push.1.force_x" = [10.0, 20.0]
)")));
  std::set<double> starts;
  for (const Scenario& s : suite.scenarios) starts.insert(s.pushes.at(0).start);
  // A draw may use a draw named after it (an order where each comes after those it uses).
  const Suite chained = LoadSuite(Write(Family(R"(count = 3
[[family.scenario.push]]
start = 5.0
[family.draw]
a = "=z + 1"
z = [1.0, 2.0]
[family.vary]
"push.1.start" = "=a"
)")));
  for (int i = 0; i < 3; ++i) {
    EXPECT_DOUBLE_EQ(chained.scenarios[i].pushes[0].start,
                     FamilyDraw(1, i, "draw:z", 1.0, 2.0) + 1);
  }
  EXPECT_EQ(starts, (std::set<double>{2.0, 4.0, 6.0}));
  const std::string csv_path = (dir_ / "members.csv").string();
  std::ofstream(csv_path) << MembersCsv(suite);
  const CsvTable table = CsvTable::Read(csv_path);
  ASSERT_EQ(table.num_rows(), 30u);
  const size_t c_name = table.Column("scenario"), c_k = table.Column("k"),
               c_force = table.Column("push.1.force_x"), c_seed = table.Column("seed");
  for (size_t r = 0; r < 30; ++r) {
    const Scenario& s = suite.scenarios[r];
    EXPECT_EQ(table.Text(r, c_name), s.name);
    EXPECT_EQ(table.Text(r, table.Column("family")), "f");
    EXPECT_EQ(table.Text(r, c_seed), std::to_string(s.seed));
    EXPECT_DOUBLE_EQ(table.Number(r, c_k) * 2.0, s.pushes[0].start);
    EXPECT_DOUBLE_EQ(table.Number(r, c_force), s.pushes[0].force.x());
  }
  // No family: no members file.
  Suite plain;
  EXPECT_EQ(MembersCsv(plain), "");
}

TEST_F(FamilyDrawsTest, BadEntriesNameTheirKey) {
  const std::string head = Family("count = 2\n[[family.scenario.push]]\nstart = 5.0\n");
  ExpectError(head + "[family.draw]\n\"a-b\" = [0, 1]\n", "family[1].draw.a-b", "a draw's name");
  ExpectError(head + "[family.draw]\na = [1, 0]\n", "family[1].draw.a", "low <= high");
  ExpectError(head + "[family.draw]\na = \"x\"\n", "family[1].draw.a", "starting with '='");
  ExpectError(head + "[family.draw]\na = \"=c + 1\"\nb = [0, 1]\n", "family[1].draw.a",
              "'c' names no draw");
  ExpectError(head + "[family.draw]\na = \"=b + 1\"\nb = \"=a * 2\"\n", "family[1].draw.a",
              "in a circle");
  ExpectError(head + "[family.vary]\n\"push.1.start\" = \"=2 *\"\n", "family[1].vary.push.1.start",
              "at the end");
  ExpectError(head + "[family.draw]\nz = 0.0\n", "family[1].draw.z", "expected [low, high]");
  ExpectError(
      head + "[family.draw]\nz = [0.0, 0.0]\n[family.vary]\n\"push.1.start\" = \"=1 / z\"\n",
      "family[1].vary.push.1.start", "\"=1 / z\": division by zero");
  ExpectError(head + "[family.draw]\nk = { range = [0.5, 3], integer = true }\n",
              "family[1].draw.k.range", "whole-number bounds");
  ExpectError(head + "[family.vary]\n\"velocity.changes\" = { count = [3, 5], v = [0.3, 1.0] }\n",
              "family[1].vary.velocity.changes.every_s", "missing required key");
  ExpectError(
      head + "[family.vary]\n\"velocity.changes\" = { count = [3.5, 5], every_s = 6, v = 0.5 }\n",
      "family[1].vary.velocity.changes.count", "whole numbers");
  ExpectError(
      head + "[family.vary]\n\"velocity.changes\" = { count = 3, every_s = 6, v = [0.0, 1] }\n",
      "family[1].vary.velocity.changes.v", "(0, 3) m/s");
  ExpectError(head +
                  "[family.vary]\n\"velocity.changes\" = { count = 3, every_s = 6, v = 0.5 }\n"
                  "\"velocity.value\" = [0.3, 0.5]\n",
              "family[1].vary.velocity.value", "vary it there");
}

}  // namespace
}  // namespace rabbit
