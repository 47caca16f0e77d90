// Simulator: energy conservation and dissipation, the contact acceptance numbers of
// docs/design/model.md (drop, standing slip, slope), event location, actuator saturation,
// obstacles, failures and determinism. Most tests run with both integrators.
#include "rabbit/sim/simulator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <string>
#include <thread>

#include "rabbit/control/basic_controllers.h"
#include "sim_fixture.h"

namespace rabbit {
namespace {

// The first cells (`name`) of the table rows under the heading `heading` of a Markdown file, up to
// the next heading of the same level.
std::vector<std::string> DocumentedNames(const std::string& path, const std::string& heading) {
  std::ifstream in(path);
  std::vector<std::string> names;
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    if (line.rfind("## ", 0) == 0) {
      inside = line == heading;
      continue;
    }
    if (!inside || line.rfind("| `", 0) != 0) continue;
    const size_t end = line.find('`', 3);
    if (end != std::string::npos) names.push_back(line.substr(3, end - 3));
  }
  return names;
}

TEST(OutcomeTest, TheVocabularyIsTheDocumentedOne) {
  const std::string doc = std::string(RABBIT_SOURCE_DIR) + "/docs/outcomes.md";
  const std::vector<std::string> documented = DocumentedNames(doc, "## Outcomes");
  std::vector<std::string> names;
  for (Outcome o : kAllOutcomes) names.push_back(OutcomeName(o));
  EXPECT_EQ(documented, names) << doc;
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
  for (Outcome o : kAllOutcomes) {
    Outcome parsed = Outcome::kCompleted;
    ASSERT_TRUE(ParseOutcome(OutcomeName(o), &parsed));
    EXPECT_EQ(parsed, o);
  }
  Outcome unused;
  EXPECT_FALSE(ParseOutcome("crashed", &unused));
}
using testing::HoldAt;
using testing::MeasureDrop;
using testing::kDeg;
using testing::SimulatorTest;
using testing::Stance;

TEST_P(SimulatorTest, ContactFreeTorqueFreeMotionConservesEnergy) {
  const Model model{ModelParams{}};
  SimSetup setup = BaseSetup(model, 5.0);
  setup.options.contact = false;
  setup.options.fall.enabled = false;
  setup.options.integrator.rtol = 1e-10;
  setup.options.integrator.atol = 1e-12;
  Vec7 q, qd;
  q << 0.0, 1.0, 0.17, 0.52, -0.70, -0.35, -0.17;
  qd << 0.3, 0.5, 0.52, 3.5, -2.6, -1.7, 0.87;
  PassiveController passive;
  const SimResult r = Simulate(setup, q, qd, &passive);
  ASSERT_EQ(r.outcome, Outcome::kCompleted) << r.reason;
  ASSERT_EQ(r.samples.size(), 5001u);
  // Relative to the energy of the motion (kinetic at start), so the zero of the potential does
  // not matter: conserved to 1e-6 over 5 s.
  const double kTolerance = 1e-6;
  const double e0 = TotalEnergy(r.samples.front());
  double worst = 0.0;
  for (const SimSample& s : r.samples) worst = std::max(worst, std::abs(TotalEnergy(s) - e0));
  EXPECT_LE(worst, kTolerance * std::abs(e0)) << "drift " << worst / std::abs(e0);
  EXPECT_GT(r.samples.front().kinetic, 10.0);  // there was real motion to conserve
}

TEST_P(SimulatorTest, WithContactAndDampingEnergyNeverIncreases) {
  // A passive collapse: touchdowns while moving, sliding, sticking and the knees folding; no
  // torque does work, so kinetic + potential + contact spring energy can only fall, except for
  // the one source the contact law has: when slip stops, the anchor rule loads the
  // tangential spring with exactly 0.5 k_t (x - x_c)^2. The balance below allows that and nothing
  // else, plus the integrator's error (rtol 1e-8) on a total of a few hundred joules.
  const Model model{ModelParams{}};
  SimSetup setup = BaseSetup(model, 2.0);
  setup.options.integrator.rtol = 1e-8;
  setup.options.integrator.atol = 1e-10;
  Vec7 q = Stance(model, 0.01, 15.0);
  q[kQ12] = q[kQ22] = -0.1;
  Vec7 qd = Vec7::Zero();
  qd[kX] = 0.3;
  PassiveController passive;
  const SimResult r = Simulate(setup, q, qd, &passive);
  ASSERT_GE(r.samples.size(), 100u);
  int slip_stops = 0;
  for (const ContactEvent& e : r.events)
    slip_stops += e.from == ContactMode::kSlide && e.to == ContactMode::kStick;
  EXPECT_GT(slip_stops, 0);  // the balance is exercised
  const double kTolerance = 1e-6 * std::abs(TotalEnergy(r.samples.front()));
  size_t next_event = 0;
  for (size_t i = 1; i < r.samples.size(); ++i) {
    double reanchor = 0.0;
    for (; next_event < r.events.size() && r.events[next_event].t <= r.samples[i].t; ++next_event) {
      const ContactEvent& e = r.events[next_event];
      if (e.from == ContactMode::kSlide && e.to == ContactMode::kStick) {
        reanchor += 0.5 * setup.contact.k_t * (e.x - e.anchor_x) * (e.x - e.anchor_x);
      }
    }
    EXPECT_LE(TotalEnergy(r.samples[i]), TotalEnergy(r.samples[i - 1]) + reanchor + kTolerance)
        << "at t = " << r.samples[i].t;
  }
  EXPECT_LT(TotalEnergy(r.samples.back()), TotalEnergy(r.samples.front()) - 1.0);
}

TEST_P(SimulatorTest, DropSettlesWithinAcceptanceNumbers) {
  // Acceptance: a 2 cm drop settles with maximum penetration under 5 mm and no rebound over 1 mm.
  const Model model{ModelParams{}};
  SimSetup setup = BaseSetup(model, 1.5);
  const Vec7 q = Stance(model, 0.02);
  PdHoldController hold(HoldAt(q));
  const SimResult r = Simulate(setup, q, Vec7::Zero(), &hold);
  ASSERT_EQ(r.outcome, Outcome::kCompleted) << r.reason;
  const auto [deepest, rebound, landed] = MeasureDrop(r);
  const double kMaxPenetration = 0.005, kMaxRebound = 0.001;
  EXPECT_TRUE(landed[0] && landed[1]);
  EXPECT_GT(-deepest, 0.0);
  EXPECT_LT(-deepest, kMaxPenetration);
  EXPECT_LT(rebound, kMaxRebound);
  // Settled: at rest at the end.
  EXPECT_LT(r.samples.back().qd.norm(), 1e-3);
}

TEST_P(SimulatorTest, StandingFeetDoNotSlip) {
  const Model model{ModelParams{}};
  SimSetup setup = BaseSetup(model, 10.0);
  const Vec7 q = Stance(model, 0.0);
  PdHoldController hold(HoldAt(q));
  const SimResult r = Simulate(setup, q, Vec7::Zero(), &hold);
  ASSERT_EQ(r.outcome, Outcome::kCompleted) << r.reason;
  // Acceptance: standing still, feet slip < 1 mm/s. The first 0.5 s are the settling of the
  // contact springs under the robot's weight (a 2 mm sink and the matching elastic spread of the
  // feet), not slip; from then on, sample by sample, and no foot ever enters slide.
  const double kMaxSlip = 1e-3;
  const size_t settled = 500;
  for (const ContactEvent& e : r.events) EXPECT_NE(e.to, ContactMode::kSlide) << "t = " << e.t;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const double drift = r.samples.back().foot_pos[leg].x() - r.samples[settled].foot_pos[leg].x();
    EXPECT_LT(std::abs(drift) / 9.5, kMaxSlip);
    for (size_t i = settled + 1; i < r.samples.size(); ++i) {
      const double v = (r.samples[i].foot_pos[leg].x() - r.samples[i - 1].foot_pos[leg].x()) /
                       setup.options.control_period;
      ASSERT_LT(std::abs(v), kMaxSlip) << "leg " << leg << " at t = " << r.samples[i].t;
    }
    EXPECT_EQ(r.samples.back().foot_mode[leg], ContactMode::kStick);
  }
  EXPECT_NEAR(r.samples.back().q[kQ0], 0.0, 0.01);
}

// The robot as a block on an incline: held rigid by stiff PD (actuator limits off), in a wide
// stance that keeps its centre of mass well between the feet, released on a uniform slope. As a
// whole it needs Ft / Fn = tan(slope): it sticks when tan(slope) < mu_s and slides otherwise. Each
// foot also carries the A-frame's internal thrust (Ft / Fn = 0.37 on flat ground in this stance:
// the contact springs are far stiffer than the joint servos), so the sticking case keeps a margin;
// in the sliding case both feet move down the slope, which thrust alone would not do. (The feet
// start exactly on the ground with zero force, where the slip guard is exactly zero: SUNDIALS
// does not report its first sign change, and the simulator's once-per-period check must.)
SimResult StandOnSlope(IntegratorKind kind, double slope_deg, double mu_s, double lambda_g) {
  ModelParams params;
  params.slope = slope_deg * kDeg;
  const Model model(params);
  SimSetup setup;
  setup.model = &model;
  setup.options.duration = 1.0;
  setup.options.integrator.kind = kind;
  setup.contact.mu_s = mu_s;
  setup.contact.lambda_g = lambda_g;
  setup.actuator.enabled = false;
  const Vec7 q = Stance(model, 0.0, 25.0);
  PdHoldParams hold_params = HoldAt(q);
  hold_params.kp = Vec4::Constant(3000.0);
  hold_params.kd = Vec4::Constant(100.0);
  PdHoldController hold(hold_params);
  return Simulate(setup, q, Vec7::Zero(), &hold);
}

double FootTravel(const SimResult& r, int leg) {
  return r.samples.back().foot_pos[leg].x() - r.samples.front().foot_pos[leg].x();
}

TEST_P(SimulatorTest, FootOnSlopeSticksBelowFrictionAngleAndSlidesAbove) {
  const double kSlopeDeg = 10.0;  // tan = 0.176
  const SimResult sticks = StandOnSlope(GetParam(), kSlopeDeg, 0.6, 0.5);
  ASSERT_EQ(sticks.outcome, Outcome::kCompleted) << sticks.reason;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    // Only the contact springs' deflection (a couple of millimetres at most).
    EXPECT_LT(std::abs(FootTravel(sticks, leg)), 0.002) << "leg " << leg;
    EXPECT_EQ(sticks.samples.back().foot_mode[leg], ContactMode::kStick);
  }
  const SimResult slides = StandOnSlope(GetParam(), kSlopeDeg, 0.15, 0.12);
  ASSERT_EQ(slides.outcome, Outcome::kCompleted) << slides.reason;
  // Sliding down the slope (+x), at about g (sin - lambda_g cos) = 0.55 m/s^2.
  for (int leg = 0; leg < kNumLegs; ++leg) {
    EXPECT_GT(FootTravel(slides, leg), 0.1) << "leg " << leg;
    EXPECT_EQ(slides.samples.back().foot_mode[leg], ContactMode::kSlide);
  }
}

TEST_P(SimulatorTest, TouchdownTimeOfFreeFallIsLocated) {
  // Released at rest, a rigid-posture robot falls without relative motion: the lowest foot
  // reaches the ground at t = sqrt(2 h / g).
  const Model model{ModelParams{}};
  SimSetup setup = BaseSetup(model, 0.2);
  const double h = 0.05;
  const Vec7 q = Stance(model, h);
  PassiveController passive;
  const SimResult r = Simulate(setup, q, Vec7::Zero(), &passive);
  ASSERT_FALSE(r.events.empty());
  const ContactEvent& first = r.events.front();
  EXPECT_EQ(first.from, ContactMode::kAir);
  const double kTimeTolerance = 1e-6;
  EXPECT_NEAR(first.t, std::sqrt(2 * h / 9.81), kTimeTolerance);
  EXPECT_NEAR(first.y, 0.0, 1e-9);
  // The other foot lands at the same instant (symmetric stance).
  ASSERT_GE(r.events.size(), 2u);
  EXPECT_NEAR(r.events[1].t, first.t, kTimeTolerance);
}

TEST_P(SimulatorTest, SaturationIsAppliedAndCounted) {
  // Asking the knees for a large sudden flexion with high gains needs more than 75 N m.
  const Model model{ModelParams{}};
  SimSetup setup = BaseSetup(model, 0.3);
  const Vec7 q = Stance(model, 0.0);
  PdHoldParams p = HoldAt(q);
  p.kp = Vec4::Constant(5000.0);
  p.target[1] = p.target[3] = -0.5;
  PdHoldController hold(p);
  const SimResult r = Simulate(setup, q, Vec7::Zero(), &hold);
  EXPECT_GT(r.saturated_periods[1], 0);
  bool saw_limit = false;
  for (const SimSample& s : r.samples) {
    for (int j = 0; j < kNumJoints; ++j) {
      const double limit = TorqueLimit(setup.actuator, s.qd[3 + j]);
      ASSERT_LE(std::abs(s.tau[j]), limit + 1e-12);
      if (std::abs(s.tau_cmd[j]) > limit) saw_limit = true;
    }
  }
  EXPECT_TRUE(saw_limit);
}

TEST_P(SimulatorTest, FeetLandOnObstacleTop) {
  // Dropped over a wide obstacle, both feet land on its top and stand there.
  const Model model{ModelParams{}};
  SimSetup setup = BaseSetup(model, 1.0);
  const double kHeight = 0.05;
  const Vec7 q = Stance(model, kHeight + 0.02);
  setup.terrain.obstacles.push_back({-0.5, 1.0, kHeight});
  PdHoldController hold(HoldAt(q));
  const SimResult r = Simulate(setup, q, Vec7::Zero(), &hold);
  ASSERT_EQ(r.outcome, Outcome::kCompleted) << r.reason;
  ASSERT_FALSE(r.events.empty());
  EXPECT_NEAR(r.events.front().y, kHeight, 1e-9);  // touchdown located on the top
  for (int leg = 0; leg < kNumLegs; ++leg) {
    EXPECT_NEAR(r.samples.back().foot_pos[leg].y(), kHeight, 0.005);
    EXPECT_NE(r.samples.back().foot_mode[leg], ContactMode::kAir);
  }
}

TEST_P(SimulatorTest, FootSlidingIntoObstacleSideTrips) {
  const Model model{ModelParams{}};
  SimSetup setup = BaseSetup(model, 1.0);
  const Vec7 q = Stance(model, 0.005);
  const double front_x = FootPosition(model, q, 0).x();
  setup.terrain.obstacles.push_back({front_x + 0.03, 0.2, 0.05});
  Vec7 qd = Vec7::Zero();
  qd[kX] = 1.5;
  PdHoldController hold(HoldAt(q));
  const SimResult r = Simulate(setup, q, qd, &hold);
  EXPECT_EQ(r.outcome, Outcome::kTripped);
  EXPECT_NE(r.reason.find("obstacle"), std::string::npos) << r.reason;
}

TEST_P(SimulatorTest, IntegratorFailureEndsRunWithReason) {
  const Model model{ModelParams{}};
  SimSetup setup = BaseSetup(model, 1.0);
  setup.options.integrator.max_steps_per_call = 1;
  setup.options.integrator.rtol = 1e-14;
  setup.options.integrator.atol = 1e-16;
  const Vec7 q = Stance(model, 0.02);
  PassiveController passive;
  SimResult r;
  ASSERT_NO_THROW(r = Simulate(setup, q, Vec7::Zero(), &passive));
  EXPECT_EQ(r.outcome, Outcome::kDiverged);
  EXPECT_NE(r.reason.find("integrator failure"), std::string::npos) << r.reason;
}

TEST_P(SimulatorTest, DeterministicAcrossThreadsSharingOneModel) {
  const Model model{ModelParams{}};
  const SimSetup setup = BaseSetup(model, 1.0);
  Vec7 q = Stance(model, 0.01);
  q[kQ12] = -0.2;
  auto run = [&](SimResult* out) {
    PassiveController passive;
    *out = Simulate(setup, q, Vec7::Zero(), &passive);
  };
  SimResult a, b, c;
  std::thread ta(run, &a), tb(run, &b);
  ta.join();
  tb.join();
  run(&c);
  ASSERT_EQ(a.samples.size(), c.samples.size());
  ASSERT_EQ(b.samples.size(), c.samples.size());
  for (size_t i = 0; i < c.samples.size(); ++i) {
    ASSERT_EQ(a.samples[i].q, c.samples[i].q);
    ASSERT_EQ(b.samples[i].q, c.samples[i].q);
  }
}

INSTANTIATE_TEST_SUITE_P(BothIntegrators, SimulatorTest,
                         ::testing::Values(IntegratorKind::kCvodeBdf, IntegratorKind::kArkodeErk),
                         [](const ::testing::TestParamInfo<IntegratorKind>& param) {
                           return std::string(IntegratorName(param.param));
                         });

TEST_P(SimulatorTest, TrunkPushDeliversItsImpulse) {
  // No gravity, no ground, no torque: the only external force is the push, so the linear momentum
  // after it is the impulse F T (the push acts on 200 control periods exactly), and the centre of
  // mass then moves at constant velocity.
  ModelParams params;
  params.gravity = 0.0;
  const Model model(params);
  SimSetup setup = BaseSetup(model, 0.5);
  setup.options.contact = false;
  setup.pushes = {{0.1, 0.2, Vec2(50.0, 20.0), 0.3}};
  const Vec7 q0 = Stance(model, 0.5);
  PassiveController passive;
  const SimResult r = Simulate(setup, q0, Vec7::Zero(), &passive);
  ASSERT_EQ(r.outcome, Outcome::kCompleted) << r.reason;
  const SimSample& a = r.samples[400];
  const SimSample& b = r.samples[500];
  const Vec2 v = (CenterOfMass(model, b.q) - CenterOfMass(model, a.q)) / (b.t - a.t);
  const Vec2 impulse = Vec2(50.0, 20.0) * 0.2;
  const double kTolerance = 1e-6;
  EXPECT_LT((model.total_mass() * v - impulse).norm(), kTolerance * impulse.norm());
  // Before the push, nothing moves.
  EXPECT_LT((CenterOfMass(model, r.samples[99].q) - CenterOfMass(model, q0)).norm(), 1e-12);
}

TEST_P(SimulatorTest, RunStopsAtItsDistance) {
  const Model model{ModelParams{}};
  SimSetup setup = BaseSetup(model, 5.0);
  setup.options.contact = false;
  setup.options.fall.enabled = false;
  setup.options.stop_distance = 0.25;
  Vec7 qd = Vec7::Zero();
  qd[kX] = 1.0;  // drifting forward at 1 m/s without gravity
  ModelParams params;
  params.gravity = 0.0;
  const Model free(params);
  setup.model = &free;
  PassiveController passive;
  const SimResult r = Simulate(setup, Stance(free, 0.5), qd, &passive);
  EXPECT_EQ(r.outcome, Outcome::kCompleted);
  EXPECT_NEAR(r.t_end, 0.25, 1.5e-3);
  EXPECT_GE(r.samples.back().q[kX], 0.25);
  EXPECT_LT(r.samples[r.samples.size() - 2].q[kX], 0.25);
}

TEST(TrunkPushTest, GeneralizedForceIsTheJacobianTransposeOfTheForce) {
  // Q = J^T F with J the finite-difference Jacobian of the push point hip + h (sin q0, cos q0).
  const double h = 0.3;
  const Vec2 F(40.0, -15.0);
  Vec7 q;
  q << 0.3, 0.8, 0.2, 0.1, -0.2, -0.3, -0.1;
  auto point = [h](const Vec7& x) {
    return Vec2(x[kX] + h * std::sin(x[kQ0]), x[kY] + h * std::cos(x[kQ0]));
  };
  Vec7 expected;
  const double step = 1e-6;
  for (int i = 0; i < kNq; ++i) {
    Vec7 plus = q, minus = q;
    plus[i] += step;
    minus[i] -= step;
    expected[i] = F.dot((point(plus) - point(minus)) / (2 * step));
  }
  const double kTolerance = 1e-8;
  EXPECT_LT((TrunkForceToGeneralized(q, F, h) - expected).cwiseAbs().maxCoeff(), kTolerance);
  std::string error;
  TrunkPush bad{0.0, -1.0, F, h};
  EXPECT_FALSE(bad.IsValid(&error));
}

TEST(SimulatorOptionsTest, InvalidOptionsThrow) {
  const Model model{ModelParams{}};
  SimSetup setup;
  setup.model = &model;
  setup.options.control_period = -1.0;
  PassiveController passive;
  EXPECT_THROW(Simulate(setup, Vec7::Zero(), Vec7::Zero(), &passive), std::invalid_argument);
}

}  // namespace
}  // namespace rabbit
