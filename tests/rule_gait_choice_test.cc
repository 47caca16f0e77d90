// The choice between two neighbouring rule-walked gaits (rule_gait_choice.h): the nearer gait
// between two rule-walked ones (and, below rule_gait_choice_mixed_below, next to a tracked one),
// the input unchanged elsewhere, the choice only while the command holds, and the walker keys
// rule_gait_choice, rule_gait_choice_mixed_below, rule_gait_choice_mixed_point and
// rule_gait_choice_hold_rate (adaptive preset against the chapter's).
#include "rabbit/control/rule_gait_choice.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "rabbit/scenario/suite.h"
#include "suite_fixture.h"

namespace rabbit {
namespace {

// The shipped database's pattern: eight gaits, the slowest and the three fastest rule-walked.
const std::vector<double> kSpeeds = {0.30, 0.39, 0.49, 0.58, 0.69, 0.81, 0.89, 0.99};
const std::vector<double> kShare = {1, 0, 0, 0, 0, 1, 1, 1};

TEST(RuleGaitChoiceTest, BetweenTwoRuleWalkedGaitsTheNearerIsChosen) {
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.84, kSpeeds, kShare), 0.81);
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.86, kSpeeds, kShare), 0.89);
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.75, {0.5, 1.0}, {1, 1}), 1.0);  // the midpoint: the upper
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.93, kSpeeds, kShare), 0.89);
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.95, kSpeeds, kShare), 0.99);
}

TEST(RuleGaitChoiceTest, NextToATrackedGaitAndOutsideTheInputIsUnchanged) {
  for (double v : {0.20, 0.30, 0.35, 0.45, 0.75, 0.81, 0.89, 1.2}) {
    EXPECT_DOUBLE_EQ(ChooseRuleGait(v, kSpeeds, kShare), v) << v;
  }
  // No shares (the chapter's walker) or mismatched sizes: unchanged.
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.86, kSpeeds, {}), 0.86);
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.86, kSpeeds, {1, 1}), 0.86);
  EXPECT_TRUE(std::isnan(ChooseRuleGait(NAN, kSpeeds, kShare)));
}

TEST(RuleGaitChoiceTest, SpeedsInAnyOrder) {
  const std::vector<double> speeds = {0.9, 0.5, 0.8};
  const std::vector<double> share = {1, 0, 1};
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.83, speeds, share), 0.8);
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.88, speeds, share), 0.9);
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.70, speeds, share), 0.70);
}

std::vector<std::pair<double, double>> Pitches() {
  std::vector<std::pair<double, double>> p;
  for (double v : kSpeeds) p.push_back({v, 0.1});
  return p;
}

TEST(RuleGaitChoiceTest, OnlyWhileTheCommandHolds) {
  RuleGaitChoice choice(true, Pitches(), kShare);
  EXPECT_DOUBLE_EQ(choice.Input(0.86), 0.86);  // no command yet
  choice.OnCommand(0.86);
  EXPECT_FALSE(choice.holding());  // the first command: not yet held
  EXPECT_DOUBLE_EQ(choice.Input(0.86), 0.86);
  choice.OnCommand(0.86);
  EXPECT_TRUE(choice.holding());
  EXPECT_DOUBLE_EQ(choice.Input(0.86), 0.89);
  EXPECT_DOUBLE_EQ(choice.Input(0.60), 0.60);
  choice.OnCommand(0.83);  // a ramp: the blend
  EXPECT_DOUBLE_EQ(choice.Input(0.83), 0.83);
  choice.OnCommand(0.83);
  EXPECT_DOUBLE_EQ(choice.Input(0.83), 0.81);
}

// hold_rate: a command that moves by at most that much from one touchdown to the next (a slow
// ramp) holds; a larger move releases the choice into the blend as before.
TEST(RuleGaitChoiceTest, ASlowRampHoldsWithAHoldRate) {
  RuleGaitChoice choice(true, Pitches(), kShare, 0.0, 0.5, 0.02);
  choice.OnCommand(0.86);
  choice.OnCommand(0.86);
  ASSERT_TRUE(choice.holding());
  choice.OnCommand(0.845);  // 0.015 down: holds, and the input crosses the midpoint (0.85)
  EXPECT_TRUE(choice.holding());
  EXPECT_DOUBLE_EQ(choice.Input(0.845), 0.81);
  choice.OnCommand(0.83);  // 0.015 again: holds
  EXPECT_TRUE(choice.holding());
  choice.OnCommand(0.80);  // 0.03: the blend
  EXPECT_FALSE(choice.holding());
  EXPECT_DOUBLE_EQ(choice.Input(0.83), 0.83);
  // Without a hold rate the same slow ramp releases the choice at its first move.
  RuleGaitChoice exact(true, Pitches(), kShare);
  exact.OnCommand(0.86);
  exact.OnCommand(0.86);
  exact.OnCommand(0.859);
  EXPECT_FALSE(exact.holding());
  EXPECT_DOUBLE_EQ(exact.Input(0.859), 0.859);
}

// mixed_below: between a rule-walked and a tracked neighbour the nearer gait too, where the
// faster of the two is below it; elsewhere as without.
TEST(RuleGaitChoiceTest, MixedPairsBelowALimit) {
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.33, kSpeeds, kShare, 0.45), 0.30);
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.36, kSpeeds, kShare, 0.45), 0.39);
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.33, kSpeeds, kShare, 0.0), 0.33);   // off
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.33, kSpeeds, kShare, 0.39), 0.33);  // 0.39 is not below
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.45, kSpeeds, kShare, 0.45), 0.45);  // two tracked gaits
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.75, kSpeeds, kShare, 0.45), 0.75);  // 0.81 is above
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.74, kSpeeds, kShare, 0.85), 0.69);
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.84, kSpeeds, kShare, 0.45), 0.81);  // rule-walked pairs
  RuleGaitChoice choice(true, Pitches(), kShare, 0.45);
  choice.OnCommand(0.33);
  choice.OnCommand(0.33);
  EXPECT_DOUBLE_EQ(choice.Input(0.33), 0.30);
}

TEST(RuleGaitChoiceTest, MixedPairsSwitchAtMixedPoint) {
  // 0.75 of the way from 0.30 to 0.39 m/s: the switch at 0.3675 m/s.
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.36, kSpeeds, kShare, 0.45, 0.75), 0.30);
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.366, kSpeeds, kShare, 0.45, 0.75), 0.30);
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.368, kSpeeds, kShare, 0.45, 0.75), 0.39);
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.36, kSpeeds, kShare, 0.45, 0.5), 0.39);  // the midpoint
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.31, kSpeeds, kShare, 0.45, 0.0), 0.39);  // always the faster
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.38, kSpeeds, kShare, 0.45, 1.0), 0.30);  // always the slower
  // Two rule-walked gaits keep the midpoint.
  EXPECT_DOUBLE_EQ(ChooseRuleGait(0.86, kSpeeds, kShare, 0.45, 0.75), 0.89);
  RuleGaitChoice choice(true, Pitches(), kShare, 0.45, 0.75);
  choice.OnCommand(0.36);
  choice.OnCommand(0.36);
  EXPECT_DOUBLE_EQ(choice.Input(0.36), 0.30);
}

TEST(RuleGaitChoiceTest, OffIsTheInputAsItIs) {
  RuleGaitChoice choice(false, Pitches(), kShare);
  choice.OnCommand(0.86);
  choice.OnCommand(0.86);
  EXPECT_DOUBLE_EQ(choice.Input(0.86), 0.86);
  EXPECT_DOUBLE_EQ(RuleGaitChoice().Input(0.86), 0.86);
}

TEST(RuleGaitChoiceTest, NeedsASpeedPerGait) {
  EXPECT_THROW(RuleGaitChoice(true, {{0.8, 0.2}}, kShare), std::invalid_argument);
  EXPECT_NO_THROW(RuleGaitChoice(false, {{0.8, 0.2}}, kShare));
  EXPECT_NO_THROW(RuleGaitChoice(true, {{0.8, 0.2}}, {}));  // no shares: nothing to choose
}

class RuleGaitChoiceKeysTest : public testing::SuiteFileTest {
 protected:
  RuleGaitChoiceKeysTest() : SuiteFileTest("rabbit_rule_gait_choice_test") {}
  // The walk of WalkerKeysSuite with `line` (line 9) in [defaults.controller].
  static std::string Suite(const std::string& line) {
    std::string text = testing::WalkerKeysSuite("velocity_control", "");
    const std::string type = "type = \"fuzzy_cmac\"\n";
    text.replace(text.find(type), type.size(), type + line);
    return text;
  }
  // The walker settings the suite's only scenario loads with `line`.
  WalkerParams Walker(const std::string& line) {
    return LoadSuite(Write(Suite(line))).scenarios[0].walker;
  }
};

TEST_F(RuleGaitChoiceKeysTest, ReadAndValidated) {
  const WalkerParams adaptive = Walker(""), chapter = Walker("preset = \"chapter\"\n");
  EXPECT_TRUE(adaptive.rule_gait_choice);
  EXPECT_FALSE(chapter.rule_gait_choice);
  EXPECT_FALSE(Walker("rule_gait_choice = false\n").rule_gait_choice);
  ExpectSuiteError(Suite("rule_gait_choice = 1\n"), 9, "scenario[1].controller.rule_gait_choice",
                   "");
  EXPECT_DOUBLE_EQ(adaptive.rule_gait_choice_mixed_below, 0.45);
  EXPECT_DOUBLE_EQ(chapter.rule_gait_choice_mixed_below, 0.0);
  EXPECT_DOUBLE_EQ(Walker("rule_gait_choice_mixed_below = 0.6\n").rule_gait_choice_mixed_below,
                   0.6);
  ExpectSuiteError(Suite("rule_gait_choice_mixed_below = -0.1\n"), 9,
                   "scenario[1].controller.rule_gait_choice_mixed_below", "must be in [0, 3]");
  EXPECT_DOUBLE_EQ(adaptive.rule_gait_choice_mixed_point, 0.75);
  EXPECT_DOUBLE_EQ(chapter.rule_gait_choice_mixed_point, 0.5);
  EXPECT_DOUBLE_EQ(Walker("rule_gait_choice_mixed_point = 0.6\n").rule_gait_choice_mixed_point,
                   0.6);
  ExpectSuiteError(Suite("rule_gait_choice_mixed_point = 1.5\n"), 9,
                   "scenario[1].controller.rule_gait_choice_mixed_point", "must be in [0, 1]");
  EXPECT_DOUBLE_EQ(adaptive.rule_gait_choice_hold_rate, 0.02);
  EXPECT_DOUBLE_EQ(chapter.rule_gait_choice_hold_rate, 0.0);
  EXPECT_DOUBLE_EQ(Walker("rule_gait_choice_hold_rate = 0.05\n").rule_gait_choice_hold_rate, 0.05);
  ExpectSuiteError(Suite("rule_gait_choice_hold_rate = -0.01\n"), 9,
                   "scenario[1].controller.rule_gait_choice_hold_rate", "must be in [0, 1]");
  WalkerParams bad = adaptive;
  bad.rule_gait_choice_hold_rate = 1.5;
  std::string error;
  EXPECT_FALSE(bad.IsValid(&error));
  EXPECT_NE(error.find("rule_gait_choice_hold_rate"), std::string::npos) << error;
}

}  // namespace
}  // namespace rabbit
