// The simulator on a ground profile (Terrain::ground) in the world frame: a uniform slope as a
// profile against the tilted-gravity slope, standing on a profile incline, energy on a profile
// slope, and sliding across a breakpoint onto flat ground. Each test runs with both integrators.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <string>
#include <thread>

#include "rabbit/control/basic_controllers.h"
#include "rabbit/sim/simulator.h"
#include "sim_fixture.h"

namespace rabbit {
namespace {

using testing::HoldAt;
using testing::kDeg;
using testing::SimulatorTest;
using testing::Stance;

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

// The robot as a block on an incline of the ground profile (see StandOnSlope in simulator_test):
// sum over the feet of the contact forces, in the world frame and in the surface frame, at the end
// of a 2 s stand.
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
// + contact spring energy can only fall, but for the anchor rule's one source
// (docs/design/model.md): when slip stops, the tangential spring is loaded with 0.5 k_t stretch^2,
// the stretch measured along the surface. Sample by sample, within the integrator's error.
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

INSTANTIATE_TEST_SUITE_P(BothIntegrators, SimulatorTest,
                         ::testing::Values(IntegratorKind::kCvodeBdf, IntegratorKind::kArkodeErk),
                         [](const ::testing::TestParamInfo<IntegratorKind>& param) {
                           return std::string(IntegratorName(param.param));
                         });

}  // namespace
}  // namespace rabbit
