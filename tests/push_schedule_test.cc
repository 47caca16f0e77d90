// Event-timed trunk pushes (rabbit/sim/push_schedule.h): touchdowns counted as the gait meter
// counts them, a start at a phase of the step's expected duration, the hip passing a point, both
// combined; and in the simulator, a push timed by the hip delivering its impulse when it starts.
#include "rabbit/sim/push_schedule.h"

#include <gtest/gtest.h>

#include <cmath>

#include "rabbit/control/basic_controllers.h"
#include "rabbit/control/gait_meter.h"
#include "rabbit/model/model.h"

namespace rabbit {
namespace {

// A synthetic gait sampled every 1 ms: the legs alternate, each in the air for 0.2 s and then in
// contact, so that touchdowns come every 0.4 s from t = 0.3 s (legs 1, 2, 1, ...); the hip moves
// at 0.5 m/s from x = 0.
struct Gait {
  static constexpr double kDt = 0.001;
  std::array<bool, kNumLegs> Contact(double t) const {
    std::array<bool, kNumLegs> c{};
    for (int leg = 0; leg < kNumLegs; ++leg) {
      const double cycle = std::fmod(t + 0.4 * leg + 0.1, 0.8);  // air in [0, 0.2) of each cycle
      c[leg] = !(cycle < 0.2 + 1e-12);
    }
    return c;
  }
  double HipX(double t) const { return 0.5 * t; }
};

TEST(PushScheduleTest, CountsTouchdownsAsTheGaitMeter) {
  std::vector<TrunkPush> pushes(1);
  pushes[0].start = 0.0;
  pushes[0].after_touchdown = 1000;  // never: only counting
  PushSchedule schedule(&pushes);
  GaitMeter meter;
  const Gait gait;
  for (long k = 0; k <= 3000; ++k) {
    const double t = static_cast<double>(k) * Gait::kDt;
    Observation obs;
    obs.t = t;
    obs.foot_contact = gait.Contact(t);
    meter.Update(obs);
    schedule.Update(t, gait.HipX(t), obs.foot_contact);
    ASSERT_EQ(schedule.touchdowns(), static_cast<int>(meter.steps().size())) << "t = " << t;
  }
  EXPECT_GE(schedule.touchdowns(), 6);
  EXPECT_TRUE(std::isnan(schedule.start(0)));
}

TEST(PushScheduleTest, StartsOnItsEvent) {
  std::vector<TrunkPush> pushes(4);
  pushes[0].start = 0.7;  // timed
  pushes[1].after_touchdown = 3;
  pushes[1].phase = 0.25;
  pushes[2].at_hip_x = 0.6;
  pushes[3].at_hip_x = 0.6;  // the 2nd touchdown after the hip passes 0.6 m
  pushes[3].after_touchdown = 2;
  pushes[3].phase = 0.5;
  PushSchedule schedule(&pushes);
  const Gait gait;
  std::vector<double> touchdowns;
  GaitMeter meter;
  for (long k = 0; k <= 3000; ++k) {
    const double t = static_cast<double>(k) * Gait::kDt;
    Observation obs;
    obs.t = t;
    obs.foot_contact = gait.Contact(t);
    if (meter.Update(obs)) touchdowns.push_back(t);
    schedule.Update(t, gait.HipX(t), obs.foot_contact);
  }
  ASSERT_GE(touchdowns.size(), 6u);
  EXPECT_DOUBLE_EQ(schedule.start(0), 0.7);
  // The 3rd touchdown plus a quarter of the step before it.
  EXPECT_NEAR(schedule.start(1), touchdowns[2] + 0.25 * (touchdowns[2] - touchdowns[1]), 1e-9);
  // The hip passes 0.6 m at t = 1.2 s, the first sample with 0.5 t >= 0.6.
  EXPECT_NEAR(schedule.start(2), 1.2, 1.5 * Gait::kDt);
  size_t after = 0;
  while (touchdowns[after] < schedule.start(2) - 1e-12) ++after;
  const size_t second = after + 1;  // the 2nd touchdown from there
  EXPECT_NEAR(schedule.start(3),
              touchdowns[second] + 0.5 * (touchdowns[second] - touchdowns[second - 1]), 1e-9);
  EXPECT_TRUE(schedule.Active(1, schedule.start(1)));
  EXPECT_TRUE(schedule.Active(1, schedule.start(1) + 0.099));
  EXPECT_FALSE(schedule.Active(1, schedule.start(1) + 0.1));
  EXPECT_FALSE(schedule.Active(1, schedule.start(1) - 0.001));
}

TEST(PushScheduleTest, EventTimedPushesAreChecked) {
  std::string error;
  TrunkPush p;
  p.after_touchdown = 2;
  p.phase = 1.5;
  EXPECT_FALSE(p.IsValid(&error));
  p.phase = 0.5;
  EXPECT_TRUE(p.IsValid(&error)) << error;
  p.start = 1.0;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("no start time"), std::string::npos) << error;
}

// No gravity, no ground: the robot drifts at 1 m/s, a push of 4 N s starts when the hip passes
// 0.25 m (the sample at t = 0.25 s) and the momentum afterwards is the drift's plus the impulse.
TEST(PushScheduleTest, AHipTimedPushDeliversItsImpulseInTheSimulator) {
  ModelParams params;
  params.gravity = 0.0;
  const Model model(params);
  SimSetup setup;
  setup.model = &model;
  setup.options.duration = 0.6;
  setup.options.contact = false;
  TrunkPush push;
  push.at_hip_x = 0.25;
  push.duration = 0.1;
  push.force = Vec2(40.0, 0.0);
  setup.pushes = {push};
  Vec7 q0 = Vec7::Zero();
  q0[kY] = 1.0;
  Vec7 qd0 = Vec7::Zero();
  qd0[kX] = 1.0;
  PassiveController passive;
  const SimResult r = Simulate(setup, q0, qd0, &passive);
  ASSERT_EQ(r.outcome, Outcome::kCompleted) << r.reason;
  ASSERT_EQ(r.push_starts.size(), 1u);
  EXPECT_NEAR(r.push_starts[0], 0.25, 1.5 * setup.options.control_period);
  // Momentum of the centre of mass from finite differences before and after the push.
  // Vec2, not auto: the expression would refer to the centres of mass after they are gone.
  auto momentum = [&](double t0, double t1) -> Vec2 {
    const SimSample* a = nullptr;
    const SimSample* b = nullptr;
    for (const SimSample& s : r.samples) {
      if (a == nullptr && s.t >= t0) a = &s;
      if (b == nullptr && s.t >= t1) b = &s;
    }
    return model.total_mass() * (CenterOfMass(model, b->q) - CenterOfMass(model, a->q)) /
           (b->t - a->t);
  };
  const Vec2 before = momentum(0.05, 0.2), after = momentum(0.45, 0.55);
  const double kTolerance = 1e-6;
  EXPECT_NEAR(after.x() - before.x(), 4.0, kTolerance * 4.0 + 1e-6);
  EXPECT_NEAR(after.y() - before.y(), 0.0, 1e-6);
}

}  // namespace
}  // namespace rabbit
