#include "rabbit/sim/simulator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "rabbit/sim/push_schedule.h"

namespace rabbit {

const char* OutcomeName(Outcome outcome) {
  switch (outcome) {
    case Outcome::kCompleted:
      return "completed";
    case Outcome::kFell:
      return "fell";
    case Outcome::kTripped:
      return "tripped";
    case Outcome::kStalled:
      return "stalled";
    case Outcome::kDiverged:
      return "diverged";
    case Outcome::kTimedOut:
      return "timeout";
  }
  return "?";
}

bool ParseOutcome(const std::string& name, Outcome* outcome) {
  for (Outcome o : kAllOutcomes) {
    if (name == OutcomeName(o)) {
      *outcome = o;
      return true;
    }
  }
  return false;
}

bool SimOptions::IsValid(std::string* error) const {
  if (!(std::isfinite(duration) && duration >= 0.0)) {
    *error = "duration must be finite and >= 0";
    return false;
  }
  if (!(std::isfinite(control_period) && control_period >= 1e-5 && control_period <= 1.0)) {
    *error = "control period must be in [1e-5, 1] s";
    return false;
  }
  if (duration / control_period > 1e8) {
    *error = "more than 1e8 control periods in one run";
    return false;
  }
  if (!(max_wall > 0.0)) {
    *error = "max wall time must be > 0 s";
    return false;
  }
  if (max_events_per_period <= 0 || record_every < 0) {
    *error = "max_events_per_period must be > 0 and record_every >= 0";
    return false;
  }
  if (!(std::isfinite(fall.min_hip_height) && std::isfinite(fall.max_trunk_pitch) &&
        fall.max_trunk_pitch > 0.0)) {
    *error = "fall criteria must be finite, with max trunk pitch > 0";
    return false;
  }
  return integrator.IsValid(error);
}

bool TrunkPush::IsValid(std::string* error) const {
  if (!(std::isfinite(start) && std::isfinite(duration) && force.allFinite() &&
        std::isfinite(height))) {
    *error = "push values must be finite";
    return false;
  }
  if (start < 0.0 || duration <= 0.0) {
    *error = "push start must be >= 0 and duration > 0";
    return false;
  }
  if (force.norm() > 1e4 || std::abs(height) > 2.0) {
    *error = "push beyond sensible bounds (|force| <= 1e4 N, |height| <= 2 m)";
    return false;
  }
  if (after_touchdown < 0 || after_touchdown > 100000 || !(phase >= 0.0 && phase <= 1.0) ||
      std::isinf(at_hip_x) || std::abs(at_hip_x) > 1e4) {
    *error = "push event: after_touchdown in [0, 100000], phase in [0, 1], |at_hip_x| <= 1e4 m";
    return false;
  }
  if (event_timed() && start != 0.0) {
    *error = "a push timed by an event (after_touchdown, at_hip_x) has no start time";
    return false;
  }
  return true;
}

Vec7 TrunkForceToGeneralized(const Vec7& q, const Vec2& force, double height) {
  Vec7 Q = Vec7::Zero();
  Q[kX] = force.x();
  Q[kY] = force.y();
  Q[kQ0] = height * (force.x() * std::cos(q[kQ0]) - force.y() * std::sin(q[kQ0]));
  return Q;
}

namespace {

constexpr int kStateSize = 2 * kNq;
// Guards per foot: touch, slip, resume; then one per foot and obstacle (span); then, when the
// ground profile has breakpoints, one per foot for its ground segment.
constexpr int kFootGuards = 3;
// Foot penetration into an obstacle's top that does not count as a link entering it (m).
constexpr double kObstacleTopMargin = 0.01;

struct RunContext {
  const SimSetup* setup = nullptr;
  Data data;
  std::array<FootContactState, kNumLegs> feet{};
  Vec4 tau = Vec4::Zero();
  std::vector<const TrunkPush*> pushes;  // trunk pushes held over the period
  int num_obstacles = 0;
  bool segment_guards = false;  // the ground has more than one segment
  int SegmentGuardIndex(int leg) const {
    return kFootGuards * kNumLegs + kNumLegs * num_obstacles + leg;
  }
};

// Does not depend on t (the torques and pushes are held over the period): the fixed step's
// Butcher tables rely on it (integrator.cc, AvoidFalseFsal).
int Rhs(double /*t*/, const double* y, double* ydot, void* user) {
  auto* c = static_cast<RunContext*>(user);
  const Model& model = *c->setup->model;
  const Vec7 q = Eigen::Map<const Vec7>(y);
  const Vec7 qd = Eigen::Map<const Vec7>(y + kNq);
  ComputeAbsoluteDynamics(model, q, qd, &c->data);
  Vec7 Q = JointTorqueToGeneralized(c->tau);
  for (const TrunkPush* push : c->pushes) {
    Q += TrunkForceToGeneralized(q, push->force, push->height);
  }
  if (c->setup->options.contact) {
    ComputeFootKinematics(model, q, qd, &c->data);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      if (c->feet[leg].mode == ContactMode::kAir) continue;
      const FootForce f = ComputeFootForce(c->setup->contact, c->setup->terrain, c->feet[leg],
                                           c->data.foot_pos[leg], c->data.foot_vel[leg]);
      AddFootForce(model, c->data, leg, Vec2(f.fx, f.fy), &Q);
    }
  }
  if (!SolveForAcceleration(model, Q, &c->data)) return 1;
  Eigen::Map<Vec7> ydot_q(ydot), ydot_qd(ydot + kNq);
  ydot_q = qd;
  ydot_qd = c->data.qdd;
  return c->data.qdd.allFinite() ? 0 : 1;
}

int Roots(double /*t*/, const double* y, double* g, void* user) {
  auto* c = static_cast<RunContext*>(user);
  const Model& model = *c->setup->model;
  const Vec7 q = Eigen::Map<const Vec7>(y);
  const Vec7 qd = Eigen::Map<const Vec7>(y + kNq);
  ComputeLinkAngles(model, q, qd, &c->data);
  ComputeFootKinematics(model, q, qd, &c->data);
  const Terrain& terrain = c->setup->terrain;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const Vec2& pos = c->data.foot_pos[leg];
    const Vec2& vel = c->data.foot_vel[leg];
    const ContactParams& contact = c->setup->contact;
    g[kFootGuards * leg] = TouchGuard(terrain, c->feet[leg], pos);
    g[kFootGuards * leg + 1] = SlipGuard(contact, terrain, c->feet[leg], pos, vel);
    g[kFootGuards * leg + 2] = ResumeGuard(contact, terrain, c->feet[leg], pos, vel);
    for (int j = 0; j < c->num_obstacles; ++j) {
      g[kFootGuards * kNumLegs + leg * c->num_obstacles + j] =
          SpanGuard(terrain, c->feet[leg], pos, j);
    }
    if (c->segment_guards) g[c->SegmentGuardIndex(leg)] = SegmentGuard(terrain, c->feet[leg], pos);
  }
  return 0;
}

std::string Describe(const char* what, double t) {
  std::ostringstream out;
  out << what << " at t = " << t << " s";
  return out.str();
}

// Ends the run when the state is not finite, the robot fell, or a link entered an obstacle.
bool CheckState(const SimSetup& setup, const SimSample& s, const Pose& pose, SimResult* result) {
  if (!s.q.allFinite() || !s.qd.allFinite()) {
    result->outcome = Outcome::kDiverged;
    result->reason = Describe("state became non-finite", s.t);
    return false;
  }
  const Terrain& terrain = setup.terrain;
  if (setup.options.contact) {
    for (int leg = 0; leg < kNumLegs; ++leg) {
      if (terrain.SegmentHitsObstacle(pose.knee[leg], pose.foot[leg], kObstacleTopMargin) >= 0 ||
          terrain.SegmentHitsObstacle(pose.hip, pose.knee[leg], kObstacleTopMargin) >= 0 ||
          terrain.SegmentHitsObstacle(pose.hip, pose.trunk_top, 0.0) >= 0) {
        result->outcome = Outcome::kTripped;
        result->reason =
            Describe(leg == 0 ? "leg 1 hit an obstacle" : "leg 2 hit an obstacle", s.t);
        return false;
      }
      if (terrain.SegmentHitsStepFace(pose.knee[leg], pose.foot[leg], kObstacleTopMargin) >= 0 ||
          terrain.SegmentHitsStepFace(pose.hip, pose.knee[leg], kObstacleTopMargin) >= 0) {
        result->outcome = Outcome::kTripped;
        result->reason =
            Describe(leg == 0 ? "leg 1 hit a step's face" : "leg 2 hit a step's face", s.t);
        return false;
      }
    }
  }
  const FallCriteria& fall = setup.options.fall;
  if (!fall.enabled) return true;
  const char* why = nullptr;
  // Hip height over the ground under it.
  if (s.q[kY] - terrain.GroundHeight(s.q[kX]) < fall.min_hip_height) {
    why = "hip below the fall height";
  }
  if (std::abs(s.q[kQ0]) > fall.max_trunk_pitch) why = "trunk pitch beyond the fall limit";
  if (setup.options.contact) {
    for (int leg = 0; leg < kNumLegs; ++leg) {
      if (pose.knee[leg].y() <= terrain.HeightAt(pose.knee[leg].x())) why = "a knee touched ground";
    }
  }
  if (why == nullptr) return true;
  result->outcome = Outcome::kFell;
  result->reason = Describe(why, s.t);
  return false;
}

// Transitions a foot is due, from the guards that fired or from guards found violated.
struct FootTriggers {
  bool touch = false;
  bool friction = false;
  bool span = false;
  bool any() const { return touch || friction || span; }
};

// Applies one foot's due transitions at time t, where it is at pos with velocity vel, and records
// every mode change. Returns false when the foot entered an obstacle through its side.
bool ApplyTransitions(const SimSetup& setup, int leg, const FootTriggers& due, double t,
                      const Vec2& pos, const Vec2& vel, RunContext* ctx, SimResult* result) {
  FootContactState& foot = ctx->feet[leg];
  const ContactMode before = foot.mode;  // a foot leaving an edge goes to the air: recorded too
  if (due.span && !UpdateFootSurface(setup.terrain, pos, &foot)) {
    result->outcome = Outcome::kTripped;
    const bool step = setup.terrain.SurfaceAt(pos.x()) == kGround;  // else an obstacle's side
    const char* what = step ? "a step's face" : "an obstacle's side";
    result->reason =
        Describe((std::string(leg == 0 ? "foot 1 hit " : "foot 2 hit ") + what).c_str(), t);
    return false;
  }
  if (due.touch) OnTouchEvent(setup.terrain, pos, vel, &foot);
  if (due.friction) OnFrictionEvent(setup.contact, setup.terrain, pos, vel, &foot);
  if (foot.mode != before) {
    const FootForce f = ComputeFootForce(setup.contact, setup.terrain, foot, pos, vel);
    result->events.push_back(
        {t, leg, before, foot.mode, pos.x(), pos.y(), f.fn, f.ft, foot.anchor_x});
  }
  return true;
}

// Guards that are negative although no event fired. SUNDIALS reports only sign changes, and a
// guard that is exactly zero where the integration (re)starts is switched off until it leaves
// zero, so a foot placed exactly at the cone's edge, or released exactly on the ground, could
// miss its first transition. Checked once per control period: a missed event is caught within
// one period. (The resume guard starts negative by design and is not checked.)
FootTriggers ViolatedGuards(const SimSetup& setup, const FootContactState& foot, const Vec2& pos,
                            const Vec2& vel) {
  FootTriggers due;
  due.span = setup.terrain.SurfaceAt(pos.x()) != foot.surface ||
             setup.terrain.ground.SegmentAt(pos.x()) != foot.segment;
  due.touch = TouchGuard(setup.terrain, foot, pos) < 0.0;
  due.friction = !due.touch && foot.mode != ContactMode::kAir &&
                 SlipGuard(setup.contact, setup.terrain, foot, pos, vel) < 0.0;
  return due;
}

}  // namespace

SimResult Simulate(const SimSetup& setup, const Vec7& q0, const Vec7& qd0, Controller* controller) {
  std::string error;
  if (setup.model == nullptr) throw std::invalid_argument("SimSetup has no model");
  if (!setup.options.IsValid(&error) || !setup.contact.IsValid(&error) ||
      !setup.actuator.IsValid(&error) || !setup.terrain.IsValid(&error)) {
    throw std::invalid_argument(error);
  }
  for (const TrunkPush& push : setup.pushes) {
    if (!push.IsValid(&error)) throw std::invalid_argument(error);
  }
  const Model& model = *setup.model;
  const SimOptions& opt = setup.options;
  const Terrain& terrain = setup.terrain;
  const auto wall_start = std::chrono::steady_clock::now();
  const bool wall_limited = std::isfinite(opt.max_wall);

  RunContext ctx;
  ctx.setup = &setup;
  ctx.num_obstacles = static_cast<int>(terrain.obstacles.size());
  ctx.segment_guards = opt.contact && terrain.ground.num_segments() > 1;
  ctx.pushes.reserve(setup.pushes.size());
  PushSchedule schedule(&setup.pushes);
  if (opt.contact) {
    for (int leg = 0; leg < kNumLegs; ++leg) {
      ctx.feet[leg] = InitialFootState(terrain, FootPosition(model, q0, leg));
    }
  }
  double y[kStateSize];
  Eigen::Map<Vec7> y_q(y), y_qd(y + kNq);
  y_q = q0;
  y_qd = qd0;
  const int num_roots =
      opt.contact ? kNumLegs * (kFootGuards + ctx.num_obstacles + (ctx.segment_guards ? 1 : 0)) : 0;
  std::unique_ptr<OdeIntegrator> integrator =
      OdeIntegrator::Create(opt.integrator, kStateSize, num_roots, Rhs, Roots, &ctx, 0.0, y);

  SimResult result;
  // The run ends at the last sample at or before `duration`.
  const long num_periods = std::lround(std::floor(opt.duration / opt.control_period + 1e-9));
  std::vector<int> fired;
  // Reserve for a short run only: a long one grows as it goes, so that a run that ends early (a
  // fall) never holds memory for the samples it did not record.
  constexpr long kReservedSamples = 1 << 16;
  if (opt.record_every > 0) {
    result.samples.reserve(std::min(num_periods / opt.record_every + 1, kReservedSamples));
  }
  Data& sample_data = ctx.data;  // shared with the integrator's callbacks: same q, cached sines
  for (long k = 0;; ++k) {
    SimSample s;
    s.t = static_cast<double>(k) * opt.control_period;
    s.q = Eigen::Map<const Vec7>(y);
    s.qd = Eigen::Map<const Vec7>(y + kNq);
    Observation obs;
    obs.t = s.t;
    obs.q = s.q;
    obs.qd = s.qd;
    obs.terrain = &terrain;
    // The link angles for the feet and the pose; the mass matrix only for a recorded sample's
    // kinetic energy (the right-hand side forms its own).
    ComputeLinkAngles(model, s.q, s.qd, &sample_data);
    ComputeFootKinematics(model, s.q, s.qd, &sample_data);
    bool alive = true;
    if (k > 0 && opt.contact) {
      // Catch a transition the root finding could not see (see ViolatedGuards).
      bool changed = false;
      for (int leg = 0; leg < kNumLegs && alive; ++leg) {
        const Vec2& pos = sample_data.foot_pos[leg];
        const Vec2& vel = sample_data.foot_vel[leg];
        const FootTriggers due = ViolatedGuards(setup, ctx.feet[leg], pos, vel);
        if (!due.any()) continue;
        changed = true;
        alive = ApplyTransitions(setup, leg, due, s.t, pos, vel, &ctx, &result);
      }
      if (alive && changed) integrator->Reinit(s.t, y);
    }
    for (int leg = 0; leg < kNumLegs; ++leg) {
      const Vec2& pos = sample_data.foot_pos[leg];
      s.foot_pos[leg] = obs.foot_pos[leg] = pos;
      s.foot_mode[leg] = ctx.feet[leg].mode;
      if (opt.contact) {
        s.foot_force[leg] =
            ComputeFootForce(setup.contact, terrain, ctx.feet[leg], pos, sample_data.foot_vel[leg]);
      }
      obs.foot_force[leg] = s.foot_force[leg];
      obs.foot_contact[leg] = s.foot_force[leg].fn > 0.0;
    }
    alive = alive && CheckState(setup, s, ComputePose(model, s.q, sample_data), &result);
    if (alive && controller != nullptr) {
      std::string stall;
      if (controller->CheckStall(obs, &stall)) {
        result.outcome = Outcome::kStalled;
        result.reason = Describe(stall.c_str(), s.t);
        alive = false;
      }
    }
    if (alive && wall_limited && k > 0 && k % kWallCheckPeriods == 0) {
      const double wall =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
      if (wall > opt.max_wall) {
        char text[96];
        std::snprintf(text, sizeof text, "wall time %.3g s over the %.3g s limit (max_wall_s)",
                      wall, opt.max_wall);
        result.outcome = Outcome::kTimedOut;
        result.reason = Describe(text, s.t);
        alive = false;
      }
    }
    const bool reached = alive && s.q[kX] - q0[kX] >= opt.stop_distance;
    // Energies only for the samples kept (a run that records nothing, like a synthesis
    // candidate, skips them).
    const bool record = opt.record_every > 0 &&
                        (k % opt.record_every == 0 || !alive || reached || k == num_periods);
    if (record) {
      ComputeAbsoluteDynamics(model, s.q, s.qd, &sample_data);
      s.kinetic = KineticEnergy(model, s.qd, sample_data);
      s.potential = PotentialEnergy(model, s.q, sample_data);
      s.elastic = 0.0;
      for (int leg = 0; leg < kNumLegs && opt.contact; ++leg) {
        s.elastic += ContactElasticEnergy(setup.contact, terrain, ctx.feet[leg], s.foot_pos[leg]);
      }
    }
    if (alive && controller != nullptr) s.tau_cmd = controller->Compute(obs);
    for (int j = 0; j < kNumJoints; ++j) {
      SaturationRegion region;
      s.tau[j] = SaturateTorque(setup.actuator, s.tau_cmd[j], s.qd[3 + j], &region);
      if (region != SaturationRegion::kNone) ++result.saturated_periods[j];
      if (alive && !reached && k < num_periods) {  // only when a period follows this sample
        result.positive_work += std::max(0.0, s.tau[j] * s.qd[3 + j]) * opt.control_period;
      }
    }
    // New torques are a jump in the right-hand side: restart the integrator there (see
    // SimOptions::restart_at_samples). Unchanged torques (e.g. a passive robot) need nothing.
    // Pushes held over this period (capacity reserved: no allocation here).
    // Event-timed pushes wait for their event, seen at the samples.
    schedule.Update(s.t, s.q[kX], obs.foot_contact);
    bool push_changed = false;
    size_t active = 0;
    for (size_t i = 0; i < setup.pushes.size(); ++i) {
      if (schedule.Active(i, s.t)) {
        push_changed |= active >= ctx.pushes.size() || ctx.pushes[active] != &setup.pushes[i];
        ++active;
      }
    }
    push_changed |= active != ctx.pushes.size();
    if (push_changed) {
      ctx.pushes.clear();
      for (size_t i = 0; i < setup.pushes.size(); ++i) {
        if (schedule.Active(i, s.t)) ctx.pushes.push_back(&setup.pushes[i]);
      }
    }
    if (opt.restart_at_samples && k > 0 && (s.tau != ctx.tau || push_changed)) {
      integrator->Restart(s.t, y);
    }
    ctx.tau = s.tau;
    result.t_end = s.t;
    if (record) result.samples.push_back(s);
    if (!alive || reached || k == num_periods) {
      result.last = s;
      break;
    }
    result.num_periods = k + 1;

    // Integrate over the control period, stopping at every event.
    const double t_next = static_cast<double>(k + 1) * opt.control_period;
    double t = s.t;
    int events = 0;
    bool ok = true;
    while (ok) {
      const OdeIntegrator::Status status = integrator->Advance(t_next, &t, y);
      if (status == OdeIntegrator::Status::kReachedStop) break;
      if (status == OdeIntegrator::Status::kFailure) {
        result.outcome = Outcome::kDiverged;
        result.reason = Describe("integrator failure", t) + ": " + integrator->error();
        ok = false;
        break;
      }
      ++result.num_events;
      if (++events > opt.max_events_per_period) {
        result.outcome = Outcome::kDiverged;
        result.reason = Describe("contact events chattering", t);
        ok = false;
        break;
      }
      integrator->RootsFound(&fired);
      const Vec7 q = Eigen::Map<const Vec7>(y);
      const Vec7 qd = Eigen::Map<const Vec7>(y + kNq);
      ComputeLinkAngles(model, q, qd, &ctx.data);
      ComputeFootKinematics(model, q, qd, &ctx.data);
      for (int leg = 0; leg < kNumLegs && ok; ++leg) {
        FootTriggers due;
        due.touch = fired[kFootGuards * leg] != 0;
        due.friction = fired[kFootGuards * leg + 1] != 0 || fired[kFootGuards * leg + 2] != 0;
        for (int j = 0; j < ctx.num_obstacles; ++j) {
          due.span |= fired[kFootGuards * kNumLegs + leg * ctx.num_obstacles + j] != 0;
        }
        if (ctx.segment_guards) due.span |= fired[ctx.SegmentGuardIndex(leg)] != 0;
        ok = ApplyTransitions(setup, leg, due, t, ctx.data.foot_pos[leg], ctx.data.foot_vel[leg],
                              &ctx, &result);
      }
      if (ok) integrator->Reinit(t, y);
    }
    if (!ok) {
      result.t_end = t;
      result.last = s;
      break;
    }
  }
  result.integrator = integrator->Stats();
  result.push_starts = schedule.starts();
  return result;
}

}  // namespace rabbit
