// Simulator: energy conservation and dissipation, the contact acceptance numbers of docs/design.md
// (drop, standing slip, slope), event location, actuator saturation, obstacles, failures and
// determinism. Most tests run with both integrators.
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

constexpr double kDeg = M_PI / 180.0;

// The A-frame stance of scenarios/standing_pd_hold.toml: legs +-12 deg, knees straight, with the
// lowest foot `clearance` above the ground.
Vec7 Stance(const Model& model, double clearance, double half_angle_deg = 12.0) {
  Vec7 q = Vec7::Zero();
  q[kQ11] = half_angle_deg * kDeg;
  q[kQ21] = -half_angle_deg * kDeg;
  q[kY] = 0.0;
  const double lowest = std::min(FootPosition(model, q, 0).y(), FootPosition(model, q, 1).y());
  q[kY] = clearance - lowest;
  return q;
}

PdHoldParams HoldAt(const Vec7& q) {
  PdHoldParams p;
  p.target = q.tail<4>();
  return p;
}

class SimulatorTest : public ::testing::TestWithParam<IntegratorKind> {
 protected:
  // Not "Setup": that would hide gtest's Setup() misspelling trap (clang: -Woverloaded-virtual).
  SimSetup BaseSetup(const Model& model, double duration) const {
    SimSetup setup;
    setup.model = &model;
    setup.options.duration = duration;
    setup.options.integrator.kind = GetParam();
    return setup;
  }
};

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
  double deepest = 0.0, rebound = 0.0;
  std::array<bool, kNumLegs> landed{};
  for (const SimSample& s : r.samples) {
    for (int leg = 0; leg < kNumLegs; ++leg) {
      const double y = s.foot_pos[leg].y();
      deepest = std::min(deepest, y);
      if (s.foot_mode[leg] != ContactMode::kAir) landed[leg] = true;
      if (landed[leg]) rebound = std::max(rebound, y);
    }
  }
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

// ---------------------------------------------------------------------------------------------
// The slope field: a ground profile (Terrain::ground) in the world frame.

// The frame of a uniform slope a (positive descending toward +x): its tangent and normal in the
// world, t = (cos a, -sin a), n = (sin a, cos a). A state in that frame (the tilted-gravity
// simulation's, ModelParams::slope = a) seen in the world frame: the hip p = x t + y n, the trunk
// pitch (from the vertical) q0 + a, the relative joint angles unchanged; rates alike.
struct SlopeFrame {
  explicit SlopeFrame(double a)
      : slope(a), t(std::cos(a), -std::sin(a)), n(std::sin(a), std::cos(a)) {}
  Vec7 Pose(const Vec7& q) const {
    Vec7 w = q;
    w.head<2>() = q[kX] * t + q[kY] * n;
    w[kQ0] = q[kQ0] + slope;
    return w;
  }
  Vec7 Rates(const Vec7& qd) const {
    Vec7 w = qd;
    w.head<2>() = qd[kX] * t + qd[kY] * n;
    return w;
  }
  double slope;
  Vec2 t, n;
};

// A profile that is one slope over the whole run: the breakpoint 50 m behind, H(0) = 0, so the
// ground is the line through the origin along t.
Terrain UniformSlopeProfile(double slope) {
  Terrain terrain;
  terrain.ground = GroundProfile({{-50.0, slope}});
  return terrain;
}

// (1) Two formulations of the same physics: a uniform slope by tilted gravity in the
// slope-aligned frame, and the same slope as a ground profile in the world frame with the contact
// measured along its normal and tangent. A robot dropped 1 cm onto the incline under stiff PD,
// sticking (mu_s = 0.8) or sliding (mu_s = 0.1 < tan 8 deg): the hip, trunk and joint
// trajectories agree in the world frame at every sample, and the contact events at the same times.
TEST_P(SimulatorTest, SlopeProfileReproducesTheTiltedGravitySlope) {
  const double kSlope = 8.0 * kDeg;
  const SlopeFrame frame(kSlope);
  for (const double mu_s : {0.8, 0.1}) {
    ModelParams tilted_params;
    tilted_params.slope = kSlope;
    const Model tilted_model(tilted_params), world_model{ModelParams{}};
    SimSetup tilted = BaseSetup(tilted_model, 1.0);
    tilted.options.fall.enabled = false;
    tilted.options.integrator.rtol = 1e-9;
    tilted.options.integrator.atol = 1e-11;
    tilted.contact.mu_s = mu_s;
    tilted.contact.lambda_g = std::min(tilted.contact.lambda_g, 0.8 * mu_s);
    tilted.actuator.enabled = false;
    SimSetup world = tilted;
    world.model = &world_model;
    world.terrain = UniformSlopeProfile(kSlope);
    const Vec7 q = Stance(tilted_model, 0.01, 20.0);
    PdHoldParams hold_params = HoldAt(q);
    hold_params.kp = Vec4::Constant(3000.0);
    hold_params.kd = Vec4::Constant(100.0);
    PdHoldController hold_a(hold_params), hold_b(hold_params);
    const SimResult a = Simulate(tilted, q, Vec7::Zero(), &hold_a);
    const SimResult b = Simulate(world, frame.Pose(q), Vec7::Zero(), &hold_b);
    ASSERT_EQ(a.outcome, Outcome::kCompleted) << a.reason;
    ASSERT_EQ(b.outcome, Outcome::kCompleted) << b.reason;
    ASSERT_EQ(a.samples.size(), b.samples.size());
    // Integrator error at rtol 1e-9 through the contact events (seen: 2e-7 m with CVODE, whose
    // BDF restarts at order 1 after each event; 1e-12 m with ARKODE).
    const double kPositionTolerance = 1e-6;  // m
    const double kAngleTolerance = 1e-6;     // rad
    const double kRateTolerance = 1e-4;      // m/s, rad/s
    double worst = 0.0;
    for (size_t i = 0; i < a.samples.size(); ++i) {
      const Vec7 qa = frame.Pose(a.samples[i].q), qb = b.samples[i].q;
      worst = std::max(worst, (qa.head<2>() - qb.head<2>()).norm());
      ASSERT_NEAR((qa.head<2>() - qb.head<2>()).norm(), 0.0, kPositionTolerance)
          << "mu_s " << mu_s << ", t = " << a.samples[i].t;
      ASSERT_LT((qa.tail<5>() - qb.tail<5>()).cwiseAbs().maxCoeff(), kAngleTolerance)
          << "mu_s " << mu_s << ", t = " << a.samples[i].t;
      const Vec7 va = frame.Rates(a.samples[i].qd), vb = b.samples[i].qd;
      ASSERT_LT((va - vb).cwiseAbs().maxCoeff(), kRateTolerance)
          << "mu_s " << mu_s << ", t = " << a.samples[i].t;
      for (int leg = 0; leg < kNumLegs; ++leg) {
        ASSERT_EQ(a.samples[i].foot_mode[leg], b.samples[i].foot_mode[leg]) << a.samples[i].t;
      }
    }
    ASSERT_EQ(a.events.size(), b.events.size()) << "mu_s " << mu_s;
    for (size_t k = 0; k < a.events.size(); ++k) {
      EXPECT_EQ(a.events[k].to, b.events[k].to);
      EXPECT_NEAR(a.events[k].t, b.events[k].t, 1e-6) << "event " << k;
      // The normal and tangential forces after the event, in the surface frame of each: to the
      // rate error times the contact's damping (lambda_n |y| ~ 2e3 N s/m; seen: 0.02 N).
      const double kForceTolerance = 1e-4 * std::max(1.0, std::abs(a.events[k].fn));
      EXPECT_NEAR(a.events[k].fn, b.events[k].fn, kForceTolerance) << "event " << k;
      EXPECT_NEAR(a.events[k].ft, b.events[k].ft, kForceTolerance) << "event " << k;
    }
    EXPECT_GE(a.events.size(), 2u);  // both feet landed
    // The sliding robot went down the slope; the sticking one stayed.
    const double travel = (a.samples.back().q.head<2>() - a.samples.front().q.head<2>()).x();
    if (mu_s < std::tan(kSlope)) {
      EXPECT_GT(travel, 0.05);
    } else {
      EXPECT_LT(std::abs(travel), 0.005);
    }
    char text[32];
    std::snprintf(text, sizeof text, "%.2e", worst);
    RecordProperty(mu_s < 0.5 ? "worst_hip_gap_sliding_m" : "worst_hip_gap_sticking_m", text);
  }
}

// The robot as a block on an incline of the ground profile (see StandOnSlope): sum over the feet
// of the contact forces, in the world frame and in the surface frame, at the end of a 2 s stand.
struct InclineStand {
  SimResult result;
  Vec2 world = Vec2::Zero();  // sum of (fx, fy)
  double fn = 0.0, ft = 0.0;  // sums along the surface's normal and tangent
  double weight = 0.0;        // m g
};

InclineStand StandOnProfileIncline(IntegratorKind kind, double slope, double mu_s,
                                   double lambda_g) {
  const Model model{ModelParams{}};
  const SlopeFrame frame(slope);
  SimSetup setup;
  setup.model = &model;
  setup.options.duration = 2.0;
  setup.options.integrator.kind = kind;
  setup.contact.mu_s = mu_s;
  setup.contact.lambda_g = lambda_g;
  setup.actuator.enabled = false;
  setup.terrain = UniformSlopeProfile(slope);
  // The stance on the incline: built in the slope's frame (feet on y = 0), seen in the world.
  const Vec7 q_slope = Stance(model, 0.0, 25.0);
  PdHoldParams hold_params = HoldAt(q_slope);
  hold_params.kp = Vec4::Constant(3000.0);
  hold_params.kd = Vec4::Constant(100.0);
  PdHoldController hold(hold_params);
  InclineStand out;
  out.result = Simulate(setup, frame.Pose(q_slope), Vec7::Zero(), &hold);
  const SimSample& last = out.result.samples.back();
  for (int leg = 0; leg < kNumLegs; ++leg) {
    out.world += Vec2(last.foot_force[leg].fx, last.foot_force[leg].fy);
    out.fn += last.foot_force[leg].fn;
    out.ft += last.foot_force[leg].ft;
  }
  out.weight = model.total_mass() * 9.81;
  return out;
}

// (2) Standing on an incline of the profile: with tan(slope) < mu_s the feet stick and, at rest,
// the contact forces carry the weight: their sum is (0, m g), its normal part m g cos a and its
// tangential part -m g sin a (friction up the slope). With tan(slope) > mu_s the robot slides down
// the slope, the normal forces still m g cos a (no acceleration off the plane).
TEST_P(SimulatorTest, StandingOnAProfileInclineBalancesGravityOrSlides) {
  const double kSlope = 10.0 * kDeg;  // tan = 0.176
  const InclineStand sticks = StandOnProfileIncline(GetParam(), kSlope, 0.6, 0.5);
  ASSERT_EQ(sticks.result.outcome, Outcome::kCompleted) << sticks.result.reason;
  const SimSample& rest = sticks.result.samples.back();
  EXPECT_LT(rest.qd.cwiseAbs().maxCoeff(), 1e-3);  // at rest
  // At rest the contact forces balance gravity to the residual accelerations (seen: 1e-5 N).
  const double kForceTolerance = 1e-3 * sticks.weight;  // 0.3 N
  EXPECT_NEAR(sticks.world.x(), 0.0, kForceTolerance);
  EXPECT_NEAR(sticks.world.y(), sticks.weight, kForceTolerance);
  EXPECT_NEAR(sticks.fn, sticks.weight * std::cos(kSlope), kForceTolerance);
  EXPECT_NEAR(sticks.ft, -sticks.weight * std::sin(kSlope), kForceTolerance);
  const SlopeFrame incline(kSlope);
  for (int leg = 0; leg < kNumLegs; ++leg) {
    EXPECT_EQ(rest.foot_mode[leg], ContactMode::kStick);
    // Along the slope the feet moved only by the springs' deflection (a couple of millimetres).
    const Vec2 moved = rest.foot_pos[leg] - sticks.result.samples.front().foot_pos[leg];
    EXPECT_LT(std::abs(moved.dot(incline.t)), 0.002) << "leg " << leg;
  }
  // Released with zero normal force, the feet may slip for an instant; once loaded, never.
  for (const ContactEvent& e : sticks.result.events) {
    if (e.t > 0.05) {
      EXPECT_NE(e.to, ContactMode::kSlide) << "t = " << e.t;
    }
  }

  // Rising toward +x this time (negative slope), low friction: it slides down the slope, toward -x.
  const InclineStand slides = StandOnProfileIncline(GetParam(), -kSlope, 0.15, 0.12);
  ASSERT_EQ(slides.result.outcome, Outcome::kCompleted) << slides.result.reason;
  const SlopeFrame frame(-kSlope);
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const Vec2 moved =
        slides.result.samples.back().foot_pos[leg] - slides.result.samples.front().foot_pos[leg];
    EXPECT_LT(moved.dot(frame.t), -0.1) << "leg " << leg;          // down the slope
    EXPECT_NEAR(moved.dot(frame.n), 0.0, 0.005) << "leg " << leg;  // along the surface
    EXPECT_EQ(slides.result.samples.back().foot_mode[leg], ContactMode::kSlide);
  }
  EXPECT_NEAR(slides.fn, slides.weight * std::cos(kSlope), 0.01 * slides.weight);
  EXPECT_GT(slides.ft, 0.0);  // friction acts up the slope (+t here)
}

// (3) Energy on the profile: a passive collapse onto a 10 deg incline with little contact damping
// (touchdowns while moving, sliding, sticking, knees folding). With no torque, kinetic + potential
// + contact spring energy can only fall, but for the anchor rule's one source (docs/design.md):
// when slip stops, the tangential spring is loaded with 0.5 k_t stretch^2, the stretch measured
// along the surface. Sample by sample, within the integrator's error.
TEST_P(SimulatorTest, PassiveMotionOnAProfileSlopeOnlyLosesEnergy) {
  const double kSlope = 10.0 * kDeg;
  const Model model{ModelParams{}};
  SimSetup setup = BaseSetup(model, 2.0);
  setup.options.integrator.rtol = 1e-8;
  setup.options.integrator.atol = 1e-10;
  setup.options.fall.enabled = false;
  setup.contact.lambda_n = 1e4;  // 1 % of the default
  setup.contact.lambda_t = 20.0;
  setup.terrain = UniformSlopeProfile(kSlope);
  const SlopeFrame frame(kSlope);
  Vec7 q = Stance(model, 0.01, 15.0);
  q[kQ12] = q[kQ22] = -0.1;
  Vec7 qd = Vec7::Zero();
  qd[kX] = 0.3;
  PassiveController passive;
  const SimResult r = Simulate(setup, frame.Pose(q), frame.Rates(qd), &passive);
  ASSERT_GE(r.samples.size(), 100u);
  const GroundSegment& ground = setup.terrain.ground.segment(1);
  int slip_stops = 0, slides = 0;
  for (const ContactEvent& e : r.events) {
    slip_stops += e.from == ContactMode::kSlide && e.to == ContactMode::kStick;
    slides += e.to == ContactMode::kSlide;
  }
  EXPECT_GT(slides, 0);  // the balance is exercised
  const double kTolerance = 1e-6 * std::abs(TotalEnergy(r.samples.front()));
  size_t next_event = 0;
  double worst = -1e9;
  for (size_t i = 1; i < r.samples.size(); ++i) {
    double reanchor = 0.0;
    for (; next_event < r.events.size() && r.events[next_event].t <= r.samples[i].t; ++next_event) {
      const ContactEvent& e = r.events[next_event];
      if (e.from == ContactMode::kSlide && e.to == ContactMode::kStick) {
        const double stretch =
            (e.x - e.anchor_x) / ground.cos_slope - (e.y - ground.HeightAt(e.x)) * ground.sin_slope;
        reanchor += 0.5 * setup.contact.k_t * stretch * stretch;
      }
    }
    const double rise = TotalEnergy(r.samples[i]) - TotalEnergy(r.samples[i - 1]) - reanchor;
    worst = std::max(worst, rise);
    EXPECT_LE(rise, kTolerance) << "at t = " << r.samples[i].t;
  }
  EXPECT_LT(TotalEnergy(r.samples.back()), TotalEnergy(r.samples.front()) - 1.0);
  RecordProperty("slip_stops", slip_stops);
  char text[32];
  std::snprintf(text, sizeof text, "%.2e", worst);
  RecordProperty("worst_energy_rise_j", text);
}

// Across breakpoints: a robot sliding down a 20 deg slope (low friction) runs out onto a flat
// part 0.2 m lower and stops there. Each foot's segment changes at the breakpoint (located by root
// finding): at the end both feet rest on the flat part, a couple of millimetres into it, and the
// flat part carries the whole weight vertically.
TEST_P(SimulatorTest, SlidingDownASlopeOntoFlatGroundChangesSegment) {
  const double kSlope = 20.0 * kDeg;
  const Model model{ModelParams{}};
  SimSetup setup = BaseSetup(model, 4.0);
  setup.options.fall.enabled = false;
  setup.actuator.enabled = false;
  setup.contact.mu_s = 0.15;
  setup.contact.lambda_g = 0.12;
  const double run_out = 0.2 / std::tan(kSlope);  // the flat part starts 0.2 m lower
  setup.terrain.ground = GroundProfile({{-50.0, kSlope}, {run_out, 0.0}});
  const SlopeFrame frame(kSlope);
  const Vec7 q_slope = Stance(model, 0.0, 25.0);
  PdHoldParams hold_params = HoldAt(q_slope);
  hold_params.kp = Vec4::Constant(3000.0);
  hold_params.kd = Vec4::Constant(100.0);
  PdHoldController hold(hold_params);
  const SimResult r = Simulate(setup, frame.Pose(q_slope), Vec7::Zero(), &hold);
  ASSERT_EQ(r.outcome, Outcome::kCompleted) << r.reason;
  const SimSample& last = r.samples.back();
  double fy = 0.0, fx = 0.0;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    EXPECT_GT(last.foot_pos[leg].x(), run_out + 0.05) << "leg " << leg;
    EXPECT_NEAR(last.foot_pos[leg].y(), -0.2 - 0.0015, 0.0015) << "leg " << leg;
    EXPECT_NE(last.foot_mode[leg], ContactMode::kAir);
    fx += last.foot_force[leg].fx;
    fy += last.foot_force[leg].fy;
    // On the flat part the normal is vertical.
    EXPECT_DOUBLE_EQ(last.foot_force[leg].fy, last.foot_force[leg].fn);
  }
  EXPECT_LT(last.qd.head<2>().norm(), 0.05);  // stopped (or nearly)
  EXPECT_NEAR(fy, model.total_mass() * 9.81, 0.05 * model.total_mass() * 9.81);
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
