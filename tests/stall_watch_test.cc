// The stall watch: scripted observations with known answers (no touchdown for 2 s, too little hip
// advance in 3 s, a walk that never stalls, checks turned off), and a robot that stands still in
// the simulator, which ends as stalled.
#include "rabbit/scenario/stall_watch.h"

#include <gtest/gtest.h>

#include <string>

#include "rabbit/control/basic_controllers.h"
#include "rabbit/scenario/scenario.h"
#include "rabbit/sim/simulator.h"

namespace rabbit {
namespace {

const std::string kRoot = RABBIT_SOURCE_DIR;
constexpr double kPeriod = 1e-3;  // s, the control period of the scripted runs

class ZeroController final : public Controller {
 public:
  Vec4 Compute(const Observation&) override { return Vec4::Zero(); }
};

// A scripted walk: hip at speed `speed`, one foot lifted for 0.3 s of every `step` seconds
// (step <= 0: both feet stay down).
Observation Walk(long k, double speed, double step) {
  Observation o;
  o.t = static_cast<double>(k) * kPeriod;
  o.q[kX] = speed * o.t;
  const double phase = step > 0.0 ? std::fmod(o.t, step) : 1.0;
  const bool lifted = step > 0.0 && phase >= 0.1 && phase < 0.4;
  const int leg = step > 0.0 && static_cast<long>(o.t / step) % 2 == 1 ? 1 : 0;
  o.foot_contact = {!(lifted && leg == 0), !(lifted && leg == 1)};
  o.foot_pos = {Vec2(o.q[kX] - 0.1, 0.0), Vec2(o.q[kX] + 0.1, 0.0)};
  return o;
}

// The time at which the watch first reports a stall over `seconds` of the script (-1: never).
double StallTime(const StallCriteria& criteria, double speed, double step, double seconds,
                 std::string* reason) {
  ZeroController inner;
  StallWatch watch(&inner, criteria);
  for (long k = 0; static_cast<double>(k) * kPeriod <= seconds; ++k) {
    const Observation o = Walk(k, speed, step);
    if (watch.CheckStall(o, reason)) return o.t;
    watch.Compute(o);
  }
  return -1.0;
}

TEST(StallWatchTest, NoTouchdownForTwoSecondsIsAStall) {
  std::string reason;
  const double t = StallTime(StallCriteria{}, 0.6, 0.0, 10.0, &reason);  // moving, never stepping
  EXPECT_NEAR(t, 2.001, 1e-9);
  EXPECT_NE(reason.find("stall_no_touchdown_s"), std::string::npos) << reason;
}

TEST(StallWatchTest, LessThanATenthOfAMetreInThreeSecondsIsAStall) {
  // Steps every 0.5 s but the hip creeps at 0.03 m/s: 0.09 m in 3 s.
  std::string reason;
  const double t = StallTime(StallCriteria{}, 0.03, 0.5, 10.0, &reason);
  EXPECT_NEAR(t, 3.0, 1e-9);
  EXPECT_NE(reason.find("stall_min_advance_m"), std::string::npos) << reason;
  EXPECT_NE(reason.find("0.0900 m"), std::string::npos) << reason;
  // Walking backward is no advance either.
  EXPECT_NEAR(StallTime(StallCriteria{}, -0.5, 0.5, 10.0, &reason), 3.0, 1e-9);
}

TEST(StallWatchTest, AWalkNeverStalls) {
  std::string reason;
  EXPECT_EQ(StallTime(StallCriteria{}, 0.6, 0.5, 20.0, &reason), -1.0) << reason;
  EXPECT_EQ(StallTime(StallCriteria{}, 0.04, 0.5, 20.0, &reason), -1.0) << reason;  // 0.12 m/3 s
}

TEST(StallWatchTest, ZeroTurnsEachCheckOff) {
  std::string reason;
  StallCriteria no_touchdown_only;
  no_touchdown_only.min_advance = 0.0;
  EXPECT_EQ(StallTime(no_touchdown_only, 0.0, 0.5, 10.0, &reason), -1.0);
  StallCriteria advance_only;
  advance_only.no_touchdown = 0.0;
  EXPECT_NEAR(StallTime(advance_only, 0.0, 0.0, 10.0, &reason), 3.0, 1e-9);
  StallCriteria none{0.0, 0.0, 0.0};
  EXPECT_FALSE(none.enabled());
  EXPECT_EQ(StallTime(none, 0.0, 0.0, 10.0, &reason), -1.0);
}

TEST(StallWatchTest, ARobotStandingStillInTheSimulatorEndsAsStalled) {
  // The pd_hold scenario stands on both feet: under the watch (as a walking controller would be),
  // the run ends after 2 s without a touchdown with the outcome `stalled`.
  const Scenario s = LoadScenario(kRoot + "/scenarios/standing_pd_hold.toml");
  const Model model(s.model);
  SimSetup setup = MakeSimSetup(s, &model);
  setup.options.duration = 5.0;
  PdHoldController hold(s.pd_hold);
  StallWatch watch(&hold, StallCriteria{});
  const SimResult r = Simulate(setup, s.q0, s.qd0, &watch);
  EXPECT_EQ(r.outcome, Outcome::kStalled) << r.reason;
  EXPECT_STREQ(OutcomeName(r.outcome), "stalled");
  EXPECT_NEAR(r.t_end, 2.001, 1e-9);
  EXPECT_NE(r.reason.find("no touchdown for 2 s"), std::string::npos) << r.reason;
  // Without the watch the same robot completes its 5 s.
  EXPECT_EQ(Simulate(setup, s.q0, s.qd0, &hold).outcome, Outcome::kCompleted);
}

}  // namespace
}  // namespace rabbit
