// NLopt gait synthesis on a small budget: deterministic for a seed, never worse than its start,
// a given start that meets the criteria is the result in one walk, and the objective ranks walks
// as documented.
#include "gait_synthesis.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace rabbit {
namespace {

TEST(GaitSynthesisTest, CostRanksFallsBelowWalksAndTargetsCount) {
  SynthesisOptions o;
  o.target_v_m = 0.5;
  o.target_l_step = 0.3;
  GaitMetrics fell_early, fell_later, walks, on_target;
  fell_early.steps = 3;
  fell_early.fell = true;
  fell_early.walked_time = 1.5;
  fell_later.steps = 12;
  fell_later.fell = true;
  fell_later.walked_time = 6.0;
  walks.steps = on_target.steps = 25;
  walks.v_m = 0.6;
  walks.l_step = 0.3;
  on_target.v_m = 0.5;
  on_target.l_step = 0.3;
  EXPECT_GT(GaitCost(fell_early, o), GaitCost(fell_later, o));
  EXPECT_GT(GaitCost(fell_later, o), 1000.0);
  EXPECT_LT(GaitCost(walks, o), 1000.0);
  EXPECT_NEAR(GaitCost(on_target, o), 0.0, 1e-12);
  EXPECT_TRUE(MeetsCriteria(on_target, o));
  EXPECT_FALSE(MeetsCriteria(walks, o));
}

TEST(GaitSynthesisTest, SmallBudgetIsDeterministicAndImprovesOnItsStart) {
  const Model model{ModelParams{}};
  SimSetup setup;
  setup.model = &model;
  setup.options.record_every = 0;
  SynthesisOptions o;
  o.target_v_m = 0.45;
  o.budget = 40;
  o.walk_duration = 6.0;
  o.window = 6;
  int calls = 0;
  const SynthesisResult a =
      SynthesizeGait(setup, o, [&](const SynthesisProgress& p) { calls = p.evaluation; });
  const SynthesisResult b = SynthesizeGait(setup, o, nullptr);
  EXPECT_EQ(a.evaluations, calls);
  EXPECT_LE(a.evaluations, o.budget);
  EXPECT_EQ(a.cost, b.cost);
  EXPECT_EQ(a.spec.rules.qr1_dsw, b.spec.rules.qr1_dsw);
  EXPECT_EQ(a.spec.start_speed, b.spec.start_speed);
  // The start point's own cost bounds the result.
  const GaitRun start = WalkGait(setup, InitialGaitSpec(0.45), o.walk_duration, o.window);
  EXPECT_LE(a.cost, GaitCost(start.metrics, o));
}

TEST(GaitSynthesisTest, InvalidOptionsAreRefused) {
  SynthesisOptions o;
  std::string error;
  o.target_v_m = -1.0;
  EXPECT_FALSE(o.IsValid(&error));
  o = SynthesisOptions{};
  o.local_algorithm = "simplex";
  EXPECT_FALSE(o.IsValid(&error));
  o = SynthesisOptions{};
  o.start[2] = 20.0;  // q0_d_deg, beyond the default upper bound 15
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("start of q0_d_deg"), std::string::npos) << error;
  o.bounds[2] = {-5.0, 25.0};
  EXPECT_TRUE(o.IsValid(&error)) << error;
}

// The parameters of the shipped vm_0.40 (gaits/targets.toml's start for it): a gait at 0.39 m/s
// and L_step 0.243 m.
SynthesisOptions ShippedStartAt040() {
  SynthesisOptions o;
  o.target_v_m = 0.4;
  o.target_l_step = 0.24;
  const double start[kSynthesisParams] = {20, -4.200000000000003, 0, 75, 0.25, 770, 21, 450, 25,
                                          0.4};
  for (int i = 0; i < kSynthesisParams; ++i) o.start[i] = start[i];
  return o;
}

// A start that meets the criteria is the result, exactly as given, after one walk; unset
// parameters start at Table 2's values.
TEST(GaitSynthesisTest, AStartThatMeetsTheCriteriaIsTheResultInOneWalk) {
  const Model model{ModelParams{}};
  SimSetup setup;
  setup.model = &model;
  setup.options.record_every = 0;
  const SynthesisOptions o = ShippedStartAt040();
  const SynthesisResult r = SynthesizeGait(setup, o, nullptr);
  EXPECT_TRUE(r.success);
  EXPECT_EQ(r.evaluations, 1);
  EXPECT_EQ(r.walks, 1);
  for (int i = 0; i < kSynthesisParams; ++i) {
    EXPECT_EQ(SynthesisParamValue(r.spec, i), *o.start[i]) << kSynthesisParamNames[i];
  }
  EXPECT_EQ(r.spec.rules.qi2_dsw, -4.200000000000003 * M_PI / 180.0);  // not rounded on the way
  SynthesisOptions partial;
  partial.target_v_m = 0.5;
  partial.start[3] = 30.0;  // pulse_torque_nm
  const GaitSpec spec = StartGaitSpec(partial);
  EXPECT_EQ(spec.rules.pulse_torque, 30.0);
  EXPECT_EQ(spec.rules.qr1_dsw, InitialGaitSpec(0.5).rules.qr1_dsw);
  EXPECT_EQ(spec.start_speed, InitialGaitSpec(0.5).start_speed);
}

// A start that misses (the vm_0.40 parameters asked for 0.5 m/s) is where the search goes on from:
// more walks than the start's, within the budget, never worse than the start.
TEST(GaitSynthesisTest, AStartThatMissesIsWhereTheSearchGoesOnFrom) {
  const Model model{ModelParams{}};
  SimSetup setup;
  setup.model = &model;
  setup.options.record_every = 0;
  SynthesisOptions o = ShippedStartAt040();
  o.target_v_m = 0.5;
  o.target_l_step = 0.3;
  o.budget = 12;
  o.walk_duration = 4.0;
  o.window = 4;
  const SynthesisResult r = SynthesizeGait(setup, o, nullptr);
  const GaitRun start = WalkGait(setup, StartGaitSpec(o), o.walk_duration, o.window);
  EXPECT_FALSE(MeetsCriteria(start.metrics, o));
  EXPECT_GT(r.evaluations, 1);
  EXPECT_LE(r.evaluations, o.budget);
  EXPECT_LE(r.cost, GaitCost(start.metrics, o));
}

// A search that reaches the global stage gives the same result on 1 and 2 threads; on 2, the
// global stage's initial population is walked ahead and then asked for (so none walked in vain
// beyond what the search would walk itself), the values the search sees being the same.
TEST(GaitSynthesisTest, ThreadsDoNotChangeTheResult) {
  const Model model{ModelParams{}};
  SimSetup setup;
  setup.model = &model;
  setup.options.record_every = 0;
  SynthesisOptions o;
  o.target_v_m = 0.95;  // beyond the default bounds: the local stage misses, the global runs
  o.budget = 60;
  o.walk_duration = 3.0;
  o.window = 4;
  std::vector<double> costs1, costs2;
  const SynthesisResult one =
      SynthesizeGait(setup, o, [&](const SynthesisProgress& p) { costs1.push_back(p.cost); });
  o.threads = 2;
  const SynthesisResult two =
      SynthesizeGait(setup, o, [&](const SynthesisProgress& p) { costs2.push_back(p.cost); });
  EXPECT_FALSE(one.success);
  EXPECT_EQ(costs1, costs2);
  EXPECT_EQ(one.evaluations, two.evaluations);
  EXPECT_EQ(one.cost, two.cost);
  EXPECT_EQ(one.spec.rules.q0_d, two.spec.rules.q0_d);
  EXPECT_EQ(one.spec.rules.pulse_torque, two.spec.rules.pulse_torque);
  EXPECT_EQ(one.limits, two.limits);
  EXPECT_EQ(one.walks_ahead, 0);
  // The global stage has budget 30: its starting point and 29 forecast points.
  EXPECT_EQ(two.walks_ahead, o.budget / 2 - 1);
  // Every point walked ahead was one the search asked for: no more walks than on one thread.
  EXPECT_EQ(two.walks, one.walks);
}

TEST(GaitSynthesisTest, AMissNamesTheCriteriaTheBoundsAndTheBudget) {
  const Model model{ModelParams{}};
  SimSetup setup;
  setup.model = &model;
  setup.options.record_every = 0;
  SynthesisOptions o;
  o.target_v_m = 0.95;
  o.budget = 50;
  o.walk_duration = 4.0;
  o.window = 4;
  o.bounds[2] = {-5.0, 25.0};  // q0_d_deg
  SynthesisResult best;
  best.spec = InitialGaitSpec(0.8);
  best.spec.rules.q0_d = 25.0 * M_PI / 180.0;
  best.metrics.steps = 12;
  best.metrics.walked_time = 4.0;
  best.metrics.v_m = 0.85;
  best.metrics.l_step = 0.45;
  best.evaluations = 50;
  const std::vector<std::string> limits = DiagnoseMiss(setup, o, best);
  auto has = [&](const std::string& fragment) {
    for (const std::string& l : limits) {
      if (l.find(fragment) != std::string::npos) return true;
    }
    return false;
  };
  EXPECT_TRUE(has("V_M 0.850 m/s, 0.100 below the target 0.950"))
      << ::testing::PrintToString(limits);
  EXPECT_TRUE(has("q0_d_deg at its upper bound 25")) << ::testing::PrintToString(limits);
  EXPECT_TRUE(has("budget exhausted (50 walks)")) << ::testing::PrintToString(limits);
  EXPECT_FALSE(has("qi2_dsw_deg")) << ::testing::PrintToString(limits);
  best.evaluations = 20;
  const std::vector<std::string> early = DiagnoseMiss(setup, o, best);
  EXPECT_NE(early.back().find("converged after 20 of its 50"), std::string::npos) << early.back();
  // A search that misses reports its limits; one that meets its criteria reports none.
  SynthesisOptions small = o;
  small.budget = 12;
  const SynthesisResult missed = SynthesizeGait(setup, small, nullptr);
  ASSERT_FALSE(missed.success);
  ASSERT_FALSE(missed.limits.empty());
  EXPECT_NE(missed.limits.back().find("budget exhausted (12 walks)"), std::string::npos);
}

}  // namespace
}  // namespace rabbit
