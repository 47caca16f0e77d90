// The walker's response to a large disturbance (push_response.h): armed only in plain walking
// after three touchdowns with one command on level ground, its reference learnt from two steps
// that agree; a forward disturbance places the swing foot forward by the documented law and holds
// the pitch, a backward one hands the walk to the rules at the touchdown and places nothing with
// response_place_back = 0; off, nothing happens; and, on the full simulation, the default walker
// is unchanged bit for bit on an undisturbed walk and walks through the forward push that stalls
// it without the response.
#include "rabbit/control/push_response.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "rabbit/model/model.h"
#include "rabbit/scenario/params.h"
#include "rabbit/scenario/run.h"
#include "rabbit/scenario/scenario.h"

namespace rabbit {
namespace {

constexpr double kTolerance = 1e-12;
const std::string kRoot = RABBIT_SOURCE_DIR;

RecoveryParams Params() {
  RecoveryParams p;
  p.response_dead = 0.15;
  p.response_hold_steps = 2;
  p.response_rules_steps = 6;
  p.response_rules_dead = 0.6;
  p.response_place_gain = 0.3;
  p.response_place_max = 0.35;
  p.response_place_back = 0.0;
  p.placement_start = 0.3;
  p.placement_full = 0.7;
  return p;
}

// One step of 0.5 s at 1 kHz from t0 with v_orb = v (the command 0.6 m/s on level ground).
void Step(PushResponse* r, double t0, double v, bool plain = true) {
  r->Command(0.6, true);
  r->OnTouchdown(t0, 0.5);
  for (int k = 0; k < 500; ++k) r->Observe(t0 + 1e-3 * k, v, plain);
}

// Eight undisturbed steps from t = 0 at 0.5 m/s: armed from the fourth touchdown, each leg's
// reference learnt from its second step after that.
void Walk(PushResponse* r) {
  for (int n = 0; n < 8; ++n) Step(r, 0.5 * n, 0.5);
}

TEST(PushResponseTest, ForwardDisturbancePlacesTheFootAndHoldsThePitch) {
  PushResponse r(Params());
  Walk(&r);
  EXPECT_FALSE(r.step_disturbed());
  EXPECT_FALSE(r.HoldsPitch());
  // The step from t = 4 is pushed to 0.8 m/s from s = 0.3: the bins from s = 0.3 on see
  // d = 0.3, past the dead zone by 0.15.
  r.Command(0.6, true);
  r.OnTouchdown(4.0, 0.5);
  for (int k = 0; k < 150; ++k) r.Observe(4.0 + 1e-3 * k, 0.5, true);
  EXPECT_FALSE(r.step_disturbed());
  EXPECT_EQ(r.SwingOffset(4.1), 0.0);
  for (int k = 150; k < 400; ++k) r.Observe(4.0 + 1e-3 * k, 0.8, true);
  EXPECT_TRUE(r.step_disturbed());
  EXPECT_NEAR(r.disturbance(), 0.3, 1e-9);
  // At s = 0.5 (fade 0.5): 0.5 * 0.3 * 0.15 rad; beyond s = 0.7 the whole 0.045 rad.
  EXPECT_NEAR(r.SwingOffset(4.25), 0.5 * 0.3 * 0.15, 1e-9);
  EXPECT_NEAR(r.SwingOffset(4.4), 0.3 * 0.15, 1e-9);
  EXPECT_EQ(r.TrunkOffset(), 0.0);  // response_trunk_gain = 0
  // The pitch is held at the two touchdowns from the disturbed step's end; no rules (forward).
  r.Command(0.6, true);
  r.OnTouchdown(4.5, 0.5);
  EXPECT_TRUE(r.HoldsPitch());
  EXPECT_FALSE(r.TakesRules());
  for (int k = 0; k < 500; ++k) r.Observe(4.5 + 1e-3 * k, 0.5, true);
  EXPECT_FALSE(r.step_disturbed());
  r.Command(0.6, true);
  r.OnTouchdown(5.0, 0.5);
  EXPECT_TRUE(r.HoldsPitch());
  for (int k = 0; k < 500; ++k) r.Observe(5.0 + 1e-3 * k, 0.5, true);
  r.Command(0.6, true);
  r.OnTouchdown(5.5, 0.5);
  EXPECT_FALSE(r.HoldsPitch());
}

TEST(PushResponseTest, BackwardDisturbanceHandsTheWalkToTheRules) {
  PushResponse r(Params());
  Walk(&r);
  // Slowed to -0.2 m/s: d = -0.7, beyond -response_rules_dead; no placement backward.
  r.Command(0.6, true);
  r.OnTouchdown(4.0, 0.5);
  for (int k = 0; k < 450; ++k) r.Observe(4.0 + 1e-3 * k, k < 100 ? 0.5 : -0.2, true);
  EXPECT_NEAR(r.disturbance(), -0.7, 1e-9);
  EXPECT_EQ(r.SwingOffset(4.4), 0.0);
  EXPECT_FALSE(r.TakesRules());  // at the touchdown, not within the step
  r.Command(0.6, true);
  r.OnTouchdown(4.5, 0.5);
  EXPECT_TRUE(r.TakesRules());
  EXPECT_FALSE(r.TakesRules());  // once
  // With the whole placement backward too, the foot moves back: 0.3 (0.7 - 0.15) rad, and
  // 0.35 rad at most.
  RecoveryParams p = Params();
  p.response_place_back = 1.0;
  PushResponse back(p);
  Walk(&back);
  back.Command(0.6, true);
  back.OnTouchdown(4.0, 0.5);
  for (int k = 0; k < 450; ++k) back.Observe(4.0 + 1e-3 * k, k < 100 ? 0.5 : -0.2, true);
  EXPECT_NEAR(back.SwingOffset(4.4), -0.3 * 0.55, 1e-9);
  p.response_place_gain = 1.0;
  PushResponse clamped(p);
  Walk(&clamped);
  clamped.Command(0.6, true);
  clamped.OnTouchdown(4.0, 0.5);
  for (int k = 0; k < 450; ++k) clamped.Observe(4.0 + 1e-3 * k, k < 100 ? 0.5 : -0.2, true);
  EXPECT_NEAR(clamped.SwingOffset(4.4), -0.35, kTolerance);
}

TEST(PushResponseTest, NotArmedWhileTheCommandChangesOrOff) {
  // The command changes at every touchdown: never armed, so no disturbance.
  PushResponse r(Params());
  for (int n = 0; n < 8; ++n) {
    r.Command(0.4 + 0.05 * n, true);
    r.OnTouchdown(0.5 * n, 0.5);
    for (int k = 0; k < 500; ++k) r.Observe(0.5 * n + 1e-3 * k, n == 7 ? 1.5 : 0.5, true);
  }
  EXPECT_FALSE(r.step_disturbed());
  EXPECT_EQ(r.SwingOffset(3.9), 0.0);
  // Not plain walking (warm-up, planner, lift): nothing either.
  PushResponse q(Params());
  Walk(&q);
  Step(&q, 4.0, 1.5, false);
  EXPECT_FALSE(q.step_disturbed());
  // response_dead = 0: off.
  RecoveryParams p = Params();
  p.response_dead = 0.0;
  PushResponse off(p);
  Walk(&off);
  Step(&off, 4.0, 1.5);
  EXPECT_FALSE(off.step_disturbed());
  EXPECT_EQ(off.SwingOffset(4.4), 0.0);
  EXPECT_FALSE(off.HoldsPitch());
}

// The backward catch: latched from response_catch_from of the step once a backward disturbance
// has been seen, v_orb < 0 and the hip moves backward, until the touchdown; never without the
// disturbance (a walk whose own v_orb is negative) or with response_catch_back = 0; its reference
// puts a straight leg response_catch_back behind the capture point.
TEST(PushResponseTest, BackwardCatchAfterABackwardDisturbance) {
  RecoveryParams p = Params();
  p.response_catch_back = 0.05;
  p.response_catch_from = 0.7;
  PushResponse r(p);
  Walk(&r);
  r.Command(0.6, true);
  r.OnTouchdown(4.0, 0.5);
  // v_orb -0.2 from s = 0.2: d = -0.7 once the bin of s in [0.2, 0.3) is complete. The hip moves
  // backward before s = 0.7 (too early) and forward from 0.7 to 0.75 (not falling back yet).
  for (int k = 0; k < 350; ++k) r.Observe(4.0 + 1e-3 * k, k < 100 ? 0.5 : -0.2, true, -0.1);
  EXPECT_TRUE(r.step_disturbed());
  EXPECT_FALSE(r.Catching());  // s < 0.7
  for (int k = 351; k < 375; ++k) r.Observe(4.0 + 1e-3 * k, -0.2, true, 0.1);
  EXPECT_FALSE(r.Catching());  // the hip still moves forward
  r.Observe(4.376, -0.2, true, -0.1);
  EXPECT_TRUE(r.Catching());
  r.Observe(4.38, 0.3, true, 0.2);  // latched until the touchdown
  EXPECT_TRUE(r.Catching());
  // Applied to the swing leg's references while its foot is in the air only.
  Observation air;
  air.q[kY] = 0.85;
  air.foot_contact = {true, false};
  Eigen::Vector4d swing_ref(0.3, -0.9, 0.0, 0.0);
  r.ApplyCatch(air, 0, 0.87, &swing_ref);  // leg 0's foot is down: unchanged
  EXPECT_EQ(swing_ref, Eigen::Vector4d(0.3, -0.9, 0.0, 0.0));
  r.ApplyCatch(air, 1, 0.87, &swing_ref);
  EXPECT_NEAR(swing_ref[0], std::asin(-0.05 / 0.87), kTolerance);
  EXPECT_NEAR(swing_ref[1], -PushResponse::kCatchKnee, kTolerance);
  r.Command(0.6, true);
  r.OnTouchdown(4.5, 0.5);
  EXPECT_FALSE(r.Catching());
  // A walk whose own v_orb is negative late in the step is no disturbance: no catch.
  PushResponse slow(p);
  for (int n = 0; n < 9; ++n) {
    slow.Command(0.6, true);
    slow.OnTouchdown(0.5 * n, 0.5);
    for (int k = 0; k < 500; ++k) slow.Observe(0.5 * n + 1e-3 * k, -0.05, true, -0.1);
  }
  EXPECT_FALSE(slow.step_disturbed());
  EXPECT_FALSE(slow.Catching());
  // Off: never.
  p.response_catch_back = 0.0;
  PushResponse off(p);
  Walk(&off);
  off.Command(0.6, true);
  off.OnTouchdown(4.0, 0.5);
  for (int k = 0; k < 450; ++k) off.Observe(4.0 + 1e-3 * k, k < 100 ? 0.5 : -0.2, true, -0.1);
  EXPECT_TRUE(off.step_disturbed());
  EXPECT_FALSE(off.Catching());
  // The reference: hip at 0.85 m moving back at 0.3 m/s, trunk pitched 0.1 rad (rate 0.2).
  Observation obs;
  obs.q[kY] = 0.85;
  obs.q[kQ0] = 0.1;
  obs.qd[kX] = -0.3;
  obs.qd[kQ0] = 0.2;
  Eigen::Vector4d ref;
  r.CatchReference(obs, 0.87, &ref);
  const double behind = -0.3 * std::sqrt(0.85 / 9.81) - 0.05;
  EXPECT_NEAR(ref[0], std::asin(behind / 0.87) + 0.1, kTolerance);
  EXPECT_NEAR(ref[1], -PushResponse::kCatchKnee, kTolerance);
  EXPECT_NEAR(ref[2], 0.2, kTolerance);
  EXPECT_NEAR(ref[3], 0.0, kTolerance);
  // Moving forward: the foot goes response_catch_back behind the hip itself.
  obs.qd[kX] = 0.4;
  r.CatchReference(obs, 0.87, &ref);
  EXPECT_NEAR(ref[0], std::asin(-0.05 / 0.87) + 0.1, kTolerance);
}

// The forward reach: in a step disturbed forward beyond response_reach_dead, seen on the current
// bin's running mean before the bin is complete, and in the step after it, the swing thigh's
// reference is raised response_reach of the way toward a straight leg whose foot is on the hip's
// capture point; never lowered, never on the leg whose foot is down, nor with reach 0, nor in the
// second step after.
TEST(PushResponseTest, ForwardReachTowardTheCapturePoint) {
  RecoveryParams p = Params();
  p.response_reach = 0.8;
  p.response_reach_dead = 0.3;
  PushResponse r(p);
  Walk(&r);
  EXPECT_FALSE(r.Reaching());
  // The hip 0.85 m up, moving forward at 1.2 m/s, trunk pitched 0.1 rad; the swing foot (leg 1)
  // in the air; the pattern's reference puts the thigh 0.05 rad ahead of the trunk.
  Observation obs;
  obs.q[kY] = 0.85;
  obs.q[kQ0] = 0.1;
  obs.qd[kX] = 1.2;
  obs.foot_contact = {true, false};
  const double leg = 0.87;
  const Eigen::Vector4d pattern(0.15, -0.6, 0.3, 0.0);
  const double capture = 1.2 * std::sqrt(0.85 / 9.81);  // the capture point ahead of the hip
  // The foot's distance ahead of the hip for a straight leg at hip joint angle a.
  const auto foot = [&](double a) { return leg * std::sin(a - obs.q[kQ0]); };
  r.Command(0.6, true);
  r.OnTouchdown(4.0, 0.5);
  // Undisturbed up to s = 0.3, then v_orb 0.9 (d = 0.4 > 0.3): seen within the bin of s in
  // [0.3, 0.4), before it is complete.
  for (int k = 0; k < 150; ++k) r.Observe(4.0 + 1e-3 * k, 0.5, true, 0.6);
  EXPECT_FALSE(r.Reaching());
  Eigen::Vector4d ref = pattern;
  r.ApplyReach(obs, 1, leg, &ref);
  EXPECT_EQ(ref, pattern);
  for (int k = 150; k < 160; ++k) r.Observe(4.0 + 1e-3 * k, 0.9, true, 1.2);
  EXPECT_TRUE(r.Reaching());
  r.ApplyReach(obs, 1, leg, &ref);
  const double full = std::asin(capture / leg) + 0.1;  // the straight leg on the capture point
  EXPECT_NEAR(r.ReachReference(obs, leg), full, kTolerance);
  EXPECT_NEAR(foot(full), capture, 1e-9);
  EXPECT_NEAR(ref[0], pattern[0] + 0.8 * (full - pattern[0]), kTolerance);
  EXPECT_LT(std::abs(foot(ref[0]) - capture), 0.5 * std::abs(foot(pattern[0]) - capture));
  // The knee's reference and the rates are the pattern's.
  EXPECT_EQ(Eigen::Vector3d(ref.tail<3>()), Eigen::Vector3d(pattern.tail<3>()));
  // Not on the stance leg's (foot down), and never lowered: a pattern already further forward.
  Eigen::Vector4d stance_ref = pattern;
  r.ApplyReach(obs, 0, leg, &stance_ref);
  EXPECT_EQ(stance_ref, pattern);
  Eigen::Vector4d ahead(1.0, -0.6, 0.0, 0.0);
  r.ApplyReach(obs, 1, leg, &ahead);
  EXPECT_EQ(ahead[0], 1.0);
  // The step after the disturbed one reaches too; the one after that no more.
  for (int k = 160; k < 500; ++k) r.Observe(4.0 + 1e-3 * k, 0.9, true, 1.2);
  r.Command(0.6, true);
  r.OnTouchdown(4.5, 0.5);
  EXPECT_TRUE(r.Reaching());
  for (int k = 0; k < 500; ++k) r.Observe(4.5 + 1e-3 * k, 0.5, true, 0.6);
  r.Command(0.6, true);
  r.OnTouchdown(5.0, 0.5);
  EXPECT_FALSE(r.Reaching());
  // A forward disturbance within response_reach_dead (d = 0.2) reaches nothing.
  PushResponse mild(p);
  Walk(&mild);
  Step(&mild, 4.0, 0.7);
  EXPECT_TRUE(mild.step_disturbed());  // beyond response_dead
  EXPECT_FALSE(mild.Reaching());
  // Backward: nothing.
  PushResponse back(p);
  Walk(&back);
  Step(&back, 4.0, -0.2);
  EXPECT_FALSE(back.Reaching());
  // A long step: the disturbance seen past s = 1 (against the reference's last compared bin).
  PushResponse late(p);
  Walk(&late);
  late.Command(0.6, true);
  late.OnTouchdown(4.0, 0.5);
  for (int k = 0; k < 520; ++k) late.Observe(4.0 + 1e-3 * k, 0.5, true);
  EXPECT_FALSE(late.Reaching());
  for (int k = 520; k < 560; ++k) late.Observe(4.0 + 1e-3 * k, 0.9, true);
  EXPECT_TRUE(late.Reaching());
  // response_reach = 0 (the library default): the same disturbance changes nothing.
  p.response_reach = 0.0;
  PushResponse off(p);
  Walk(&off);
  off.Command(0.6, true);
  off.OnTouchdown(4.0, 0.5);
  for (int k = 0; k < 500; ++k) off.Observe(4.0 + 1e-3 * k, k < 150 ? 0.5 : 0.9, true, 1.2);
  EXPECT_TRUE(off.step_disturbed());
  EXPECT_FALSE(off.Reaching());
  Eigen::Vector4d off_ref = pattern;
  off.ApplyReach(obs, 1, leg, &off_ref);
  EXPECT_EQ(off_ref, pattern);
  // Library defaults: off.
  EXPECT_EQ(RecoveryParams().response_reach, 0.0);
  EXPECT_EQ(RecoveryParams().response_reach_dead, 0.3);
}

// response_reach_ref_min: the reach compares only the bins where the reference's |v_orb| is at
// least that. A reference near the pendulum's apex (v_orb 0.05 m/s, E = 0.0025 m^2/s^2) and a step
// at 0.45 m/s (E = 0.2025: the hip speed of a 0.5 m/s walk differs by about 0.2 m/s) reads as
// d = 0.4 > response_reach_dead: it reaches without the floor, not with one of 0.2 m/s; the same
// d on a reference of 0.5 m/s reaches with it.
TEST(PushResponseTest, ForwardReachSkipsBinsNearThePendulumsApex) {
  RecoveryParams p = Params();
  p.response_reach = 0.8;
  p.response_reach_dead = 0.3;
  const auto reaches = [](const RecoveryParams& params, double v_ref, double v) {
    PushResponse r(params);
    for (int n = 0; n < 8; ++n) Step(&r, 0.5 * n, v_ref);
    r.Command(0.6, true);
    r.OnTouchdown(4.0, 0.5);
    for (int k = 0; k < 500; ++k) r.Observe(4.0 + 1e-3 * k, k < 250 ? v_ref : v, true, 1.0);
    return r.Reaching();
  };
  EXPECT_TRUE(reaches(p, 0.05, 0.45));
  EXPECT_TRUE(reaches(p, -0.05, 0.35));
  p.response_reach_ref_min = 0.2;
  EXPECT_FALSE(reaches(p, 0.05, 0.45));
  EXPECT_FALSE(reaches(p, -0.05, 0.35));
  EXPECT_FALSE(reaches(p, 0.19, 0.59));
  EXPECT_TRUE(reaches(p, 0.21, 0.61));
  EXPECT_TRUE(reaches(p, 0.5, 0.9));
  // Within response_reach_dead on any reference: nothing.
  EXPECT_FALSE(reaches(p, 0.5, 0.75));
  EXPECT_EQ(RecoveryParams().response_reach_ref_min, 0.0);  // library default: every bin
}

TEST(PushResponseTest, InvalidParametersAreRefused) {
  std::string error;
  EXPECT_TRUE(Params().IsValid(&error)) << error;
  RecoveryParams p = Params();
  p.response_dead = 3.0;
  EXPECT_FALSE(p.IsValid(&error));
  p = Params();
  p.response_place_back = 1.5;
  EXPECT_FALSE(p.IsValid(&error));
  p = Params();
  p.response_rules_steps = -1;
  EXPECT_FALSE(p.IsValid(&error));
  p = Params();
  p.response_trunk_gain = -20.0;
  EXPECT_FALSE(p.IsValid(&error));
  p = Params();
  p.response_catch_back = 0.6;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("response_catch_back"), std::string::npos) << error;
  p = Params();
  p.response_catch_from = 2.0;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("response_catch_from"), std::string::npos) << error;
  p = Params();
  p.response_reach = 1.2;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("response_reach"), std::string::npos) << error;
  p.response_reach = -0.1;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("response_reach must be in [0, 1]"), std::string::npos) << error;
  p = Params();
  p.response_reach_dead = 2.5;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("response_reach_dead"), std::string::npos) << error;
  p.response_reach_dead = -0.1;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("response_reach_dead must be in [0, 2] m/s"), std::string::npos) << error;
  p = Params();
  p.response_reach_ref_min = -0.1;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("response_reach_ref_min must be in [0, 2] m/s"), std::string::npos) << error;
  p.response_reach_ref_min = 2.5;
  EXPECT_FALSE(p.IsValid(&error));
}

// The default walker with the response on and off on an undisturbed walk (push_forward.toml
// without its push): the same run, bit for bit.
TEST(PushResponseTest, NeutralOnAnUndisturbedWalk) {
  Scenario s = LoadScenario(kRoot + "/scenarios/push_forward.toml");
  ASSERT_GT(s.walker.recovery.response_dead, 0.0);  // on in the default (adaptive) preset
  s.pushes.clear();
  s.walker.log_every = 0;
  const std::shared_ptr<const GaitLibrary> library = LoadGaitLibrary(s.pattern);
  const RunOutput on = RunScenario(s, "fuzzy_cmac", library.get());
  s.walker.recovery.response_dead = 0.0;
  const RunOutput off = RunScenario(s, "fuzzy_cmac", library.get());
  // A walk, not two early falls that would compare equal.
  ASSERT_EQ(on.sim.outcome, Outcome::kCompleted);
  ASSERT_GT(on.metrics.steps, 10);
  EXPECT_EQ(on.sim.outcome, off.sim.outcome);
  EXPECT_EQ(on.metrics.steps, off.metrics.steps);
  EXPECT_EQ(on.metrics.distance, off.metrics.distance);
  EXPECT_EQ(on.metrics.energy, off.metrics.energy);
}

// push_forward.toml: the default walker without the response stalls after the push (one long
// step, then the velocity control leans the trunk back until the robot walks backward); with it
// the walk goes on.
TEST(PushResponseTest, ForwardPushIsWalkedThrough) {
  Scenario s = LoadScenario(kRoot + "/scenarios/push_forward.toml");
  s.walker.log_every = 0;
  const std::shared_ptr<const GaitLibrary> library = LoadGaitLibrary(s.pattern);
  const RunOutput with = RunScenario(s, "fuzzy_cmac", library.get());
  EXPECT_EQ(with.sim.outcome, Outcome::kCompleted) << with.sim.reason;
  EXPECT_TRUE(with.passed) << (with.failures.empty() ? "" : with.failures[0]);
  s.walker.recovery.response_dead = 0.0;
  const RunOutput without = RunScenario(s, "fuzzy_cmac", library.get());
  EXPECT_NE(without.sim.outcome, Outcome::kCompleted);
}

}  // namespace
}  // namespace rabbit
