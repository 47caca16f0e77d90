// The walker's push recovery (push_recovery.h): the pendulum's orbital velocity and the placement
// fade against hand computations; the nominal profile is learnt from undisturbed steps and a
// disturbance moves the swing thigh by the documented law; disabled, nothing happens; invalid
// parameters are refused; and, on the full simulation, a backward push and a forward push that
// made the walker fall without the recovery are walked through with it (the forward one with the
// tuned placement).
#include "rabbit/control/push_recovery.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "rabbit/model/model.h"
#include "rabbit/scenario/params.h"
#include "rabbit/scenario/run.h"
#include "rabbit/scenario/scenario.h"

namespace rabbit {
namespace {

constexpr double kTolerance = 1e-12;
const std::string kRoot = RABBIT_SOURCE_DIR;

TEST(PushRecoveryTest, OrbitalVelocityOfThePendulum) {
  // E = xd^2 - (g / y) dx^2: 0.36 - (9.81 / 0.9) 0.01 = 0.251, v = sqrt(0.251).
  EXPECT_NEAR(OrbitalVelocity(-0.1, 0.6, 0.9, 9.81), std::sqrt(0.36 - 9.81 / 0.9 * 0.01),
              kTolerance);
  // Symmetric in dx; negative when the hip cannot pass over the foot.
  EXPECT_NEAR(OrbitalVelocity(0.1, 0.6, 0.9, 9.81), OrbitalVelocity(-0.1, 0.6, 0.9, 9.81),
              kTolerance);
  EXPECT_NEAR(OrbitalVelocity(-0.1, 0.2, 0.9, 9.81), -std::sqrt(9.81 / 0.9 * 0.01 - 0.04),
              kTolerance);
  EXPECT_NEAR(OrbitalVelocity(0.0, 0.5, 0.9, 9.81), 0.5, kTolerance);
  // Moving back past the foot: negative; moving back but turning before the foot: positive.
  EXPECT_NEAR(OrbitalVelocity(0.0, -0.5, 0.9, 9.81), -0.5, kTolerance);
  EXPECT_NEAR(OrbitalVelocity(0.1, -0.2, 0.9, 9.81), std::sqrt(9.81 / 0.9 * 0.01 - 0.04),
              kTolerance);
}

TEST(PushRecoveryTest, PlacementFade) {
  EXPECT_EQ(PlacementFade(0.2, 0.3, 0.7), 0.0);
  EXPECT_NEAR(PlacementFade(0.5, 0.3, 0.7), 0.5, kTolerance);
  EXPECT_EQ(PlacementFade(0.9, 0.3, 0.7), 1.0);
  EXPECT_EQ(PlacementFade(0.3, 0.3, 0.3), 1.0);  // a step at start
}

// An observation with the hip at x over a stance foot at foot_x, hip speed xd, 0.9 m high.
Observation At(double t, double x, double xd, double foot_x) {
  Observation obs;
  obs.t = t;
  obs.q[kX] = x;
  obs.q[kY] = 0.9;
  obs.qd[kX] = xd;
  obs.foot_contact = {true, false};
  obs.foot_pos = {Vec2(foot_x, 0.0), Vec2(foot_x - 0.3, 0.0)};
  return obs;
}

// Walks `steps` steps of 0.5 s over stance foot 0 at 1 kHz, hip speed xd (dx = 0: v_orb = xd).
void Walk(PushRecovery* r, double t0, int steps, double xd) {
  for (int n = 0; n < steps; ++n) {
    const double td = t0 + 0.5 * n;
    r->OnTouchdown(td, 0.5);
    for (int k = 0; k < 500; ++k) r->Observe(At(td + 1e-3 * k, 0.0, xd, 0.0), 0);
  }
}

TEST(PushRecoveryTest, LearnsTheNominalAndPlacesTheFoot) {
  RecoveryParams p;
  p.placement_gain = 0.8;
  p.placement_dead = 0.1;
  p.placement_max = 0.3;
  p.placement_start = 0.3;
  p.placement_full = 0.7;
  PushRecovery r(p);
  Walk(&r, 0.0, 6, 0.5);
  EXPECT_NEAR(r.Nominal(0.4), 0.5, kTolerance);
  EXPECT_TRUE(std::isnan(r.Nominal(1.6)));  // beyond the bins
  r.OnTouchdown(3.0, 0.5);
  // Undisturbed: no offset.
  r.Observe(At(3.3, 0.0, 0.5, 0.0), 0);
  EXPECT_EQ(r.SwingOffset(3.3), 0.0);
  // Pushed forward to 0.8 m/s at s = 0.5 (fade 0.5): 0.5 * 0.8 * (0.3 - 0.1) = 0.08 rad.
  r.Observe(At(3.25, 0.0, 0.8, 0.0), 0);
  EXPECT_NEAR(r.v_orb(), 0.8, kTolerance);
  EXPECT_NEAR(r.SwingOffset(3.25), 0.08, kTolerance);
  // Beyond full: the whole offset; backward, clamped at -placement_max.
  EXPECT_NEAR(r.SwingOffset(3.4), 0.16, kTolerance);
  r.Observe(At(3.4, 0.0, -0.5, 0.0), 0);
  EXPECT_NEAR(r.SwingOffset(3.4), -0.3, kTolerance);
  // The disturbed step is not learnt.
  r.OnTouchdown(3.5, 0.5);
  EXPECT_NEAR(r.Nominal(0.4), 0.5, kTolerance);
}

TEST(PushRecoveryTest, BackwardStepAndDisabled) {
  RecoveryParams p;
  p.backward_step_speed = -0.1;
  p.placement_gain = 1.0;
  PushRecovery on(p);
  EXPECT_TRUE(on.AcceptsLandingBehind(At(0.0, 0.0, -0.2, 0.0)));
  EXPECT_FALSE(on.AcceptsLandingBehind(At(0.0, 0.0, -0.05, 0.0)));
  p.enabled = false;
  PushRecovery off(p);
  EXPECT_FALSE(off.AcceptsLandingBehind(At(0.0, 0.0, -0.2, 0.0)));
  Walk(&off, 0.0, 6, 0.5);
  off.Observe(At(3.4, 0.0, 1.5, 0.0), 0);
  EXPECT_EQ(off.SwingOffset(3.4), 0.0);
  EXPECT_TRUE(std::isnan(off.Nominal(0.4)));
}

TEST(PushRecoveryTest, InvalidParametersAreRefused) {
  std::string error;
  EXPECT_TRUE(RecoveryParams().IsValid(&error)) << error;
  RecoveryParams p;
  p.placement_gain = -0.1;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("placement_gain"), std::string::npos);
  p = RecoveryParams();
  p.placement_max = 1.5;
  EXPECT_FALSE(p.IsValid(&error));
  p = RecoveryParams();
  p.nominal_steps = 0;
  EXPECT_FALSE(p.IsValid(&error));
  p = RecoveryParams();
  p.backward_step_speed = std::nan("");
  EXPECT_FALSE(p.IsValid(&error));
}

// Push 18 of the training family (robustness_train.toml): -58.6 N for 0.124 s at 8.01 s, just
// before a touchdown. Without the recovery the walker stalls behind the new stance foot, rolls
// back onto its swing foot, keeps driving the lifted old stance leg as the trunk's support and
// falls at 9.5 s; with the backward step it walks on.
TEST(PushRecoveryTest, BackwardPushIsSurvivedWithTheRecoveryOnly) {
  Scenario s = LoadScenario(kRoot + "/scenarios/push_backward.toml");
  const std::shared_ptr<const GaitLibrary> library = LoadGaitLibrary(s.pattern);
  s.walker.log_every = 0;
  RunOutput with = RunScenario(s, "fuzzy_cmac", library.get());
  EXPECT_EQ(with.sim.outcome, Outcome::kCompleted) << with.sim.reason;
  EXPECT_TRUE(with.passed) << (with.failures.empty() ? "" : with.failures[0]);
  s.walker.recovery.enabled = false;
  RunOutput without = RunScenario(s, "fuzzy_cmac", library.get());
  EXPECT_EQ(without.sim.outcome, Outcome::kFell);
  EXPECT_LT(without.metrics.duration, 10.0);
}

// Push 20 of the training family: +58.1 N for 0.134 s at 8.10 s, just before a touchdown. The
// walker without the recovery falls at 10.0 s (with the default, backward step only, at 10.5 s),
// its steps hurried; with the tuned foot placement (scenarios/overlays/push_recovery_tuned.toml) it
// walks on.
TEST(PushRecoveryTest, ForwardPushIsSurvivedWithTheTunedPlacement) {
  const ParamOverlay tuned =
      LoadParamOverlay(kRoot + "/scenarios/overlays/push_recovery_tuned.toml");
  Scenario s = LoadScenario(kRoot + "/scenarios/push_forward.toml", &tuned);
  EXPECT_GT(s.walker.recovery.placement_gain, 0.0);
  const std::shared_ptr<const GaitLibrary> library = LoadGaitLibrary(s.pattern);
  s.walker.log_every = 0;
  RunOutput with = RunScenario(s, "fuzzy_cmac", library.get());
  EXPECT_EQ(with.sim.outcome, Outcome::kCompleted) << with.sim.reason;
  EXPECT_TRUE(with.passed) << (with.failures.empty() ? "" : with.failures[0]);
  s = LoadScenario(kRoot + "/scenarios/push_forward.toml");
  s.walker.log_every = 0;
  s.walker.recovery.enabled = false;
  RunOutput without = RunScenario(s, "fuzzy_cmac", library.get());
  EXPECT_EQ(without.sim.outcome, Outcome::kFell);
}

}  // namespace
}  // namespace rabbit
