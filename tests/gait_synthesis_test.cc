// NLopt gait synthesis on a small budget: deterministic for a seed, never worse than its start,
// and the objective ranks walks as documented.
#include "gait_synthesis.h"

#include <gtest/gtest.h>

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
}

}  // namespace
}  // namespace rabbit
