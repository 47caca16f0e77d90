#include "rabbit/scenario/scenario.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <limits>
#include <map>
#include <mutex>
#include <utility>

#include "rabbit/control/walker_presets.h"
#include "rabbit/gait/gait_database.h"
#include "rabbit/gait/walker_settings.h"
#include "rabbit/io/bounded_read.h"
#include "rabbit/io/error.h"
#include "rabbit/io/toml_reader.h"
#include "rabbit/learn/fll.h"
#include "rabbit/scenario/params.h"
#include "rabbit/scenario/slope_keys.h"
#include "rabbit/scenario/stall_recovery_keys.h"

namespace rabbit {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kMaxControlRate = 1e5;  // Hz
constexpr double kMaxPeriods = 1e8;      // control periods in one run
// A foot may start at most this deep in its surface (a computed pose on the ground sinks ~2 mm
// under load; deeper is a mistake in the scenario).
constexpr double kMaxInitialPenetration = 0.005;  // m
constexpr double kMaxInitialSpeed = 20.0;         // m/s or rad/s, any coordinate
// A run given by distance only stops at the latest after this time.
constexpr double kDefaultDistanceTimeLimit = 600.0;  // s

// The initial state must be physically sensible: finite, bounded rates, feet not deep in the
// ground, no link inside an obstacle.
void ValidateInitialState(const TomlReader& t, const Model& model, const Scenario& s) {
  if (!s.q0.allFinite() || !s.qd0.allFinite()) t.Fail("", "initial state is not finite");
  if (s.q0.tail<5>().cwiseAbs().maxCoeff() > 2 * M_PI) t.Fail("", "angles beyond +-360 deg");
  if (s.qd0.cwiseAbs().maxCoeff() > kMaxInitialSpeed) {
    t.Fail("", "initial rates beyond 20 m/s or rad/s");
  }
  if (std::abs(s.q0[kX]) > 1e3 || s.q0[kY] > 1e3) t.Fail("", "hip position beyond 1 km");
  const Pose pose = ComputePose(model, s.q0);
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const Vec2& foot = pose.foot[leg];
    const double depth = s.terrain.HeightAt(foot.x()) - foot.y();
    if (depth > kMaxInitialPenetration) {
      t.Fail("", "foot " + std::to_string(leg + 1) + " starts " +
                     std::to_string(static_cast<int>(std::lround(depth * 1000))) +
                     " mm below its surface (at most 5 mm)");
    }
    for (const auto& [a, b] : {std::pair<Vec2, Vec2>{pose.hip, pose.knee[leg]},
                               std::pair<Vec2, Vec2>{pose.knee[leg], pose.foot[leg]},
                               std::pair<Vec2, Vec2>{pose.hip, pose.trunk_top}}) {
      const int hit = s.terrain.SegmentHitsObstacle(a, b, 0.01);
      if (hit >= 0) {
        t.Fail("", "the robot starts inside obstacle " + std::to_string(hit + 1));
      }
    }
  }
}

void ReadModelFields(TomlReader* t, ModelParams* p) {
  p->trunk_mass = t->Double("trunk_mass", p->trunk_mass);
  p->trunk_com = t->Double("trunk_com", p->trunk_com);
  p->trunk_inertia = t->Double("trunk_inertia", p->trunk_inertia);
  p->trunk_length = t->Double("trunk_length", p->trunk_length);
  p->thigh_mass = t->Double("thigh_mass", p->thigh_mass);
  p->thigh_length = t->Double("thigh_length", p->thigh_length);
  p->thigh_com = t->Double("thigh_com", p->thigh_com);
  p->thigh_inertia = t->Double("thigh_inertia", p->thigh_inertia);
  p->shin_mass = t->Double("shin_mass", p->shin_mass);
  p->shin_length = t->Double("shin_length", p->shin_length);
  p->shin_com = t->Double("shin_com", p->shin_com);
  p->shin_inertia = t->Double("shin_inertia", p->shin_inertia);
  p->rotor_inertia = t->Double("rotor_inertia", p->rotor_inertia);
  p->gear_ratio = t->Double("gear_ratio", p->gear_ratio);
  p->gravity = t->Double("gravity", p->gravity);
}

template <typename Params>
void Validate(const TomlReader& t, const Params& params) {
  std::string error;
  if (!params.IsValid(&error)) t.Fail("", error);
}

ContactParams ReadContact(TomlReader t) {
  ContactParams p;
  p.k_n = t.Double("k_n", p.k_n);
  p.lambda_n = t.Double("lambda_n", p.lambda_n);
  p.k_t = t.Double("k_t", p.k_t);
  p.lambda_t = t.Double("lambda_t", p.lambda_t);
  p.mu_s = t.Double("mu_s", p.mu_s);
  p.lambda_g = t.Double("lambda_g", p.lambda_g);
  p.mu_g = t.Double("mu_g", p.mu_g);
  p.resume_fraction = t.Double("resume_fraction", p.resume_fraction);
  t.Finish();
  Validate(t, p);
  return p;
}

ActuatorParams ReadActuator(TomlReader t) {
  ActuatorParams p;
  p.enabled = t.Bool("enabled", p.enabled);
  p.max_torque = t.Double("max_torque", p.max_torque);
  p.max_power = t.Double("max_power", p.max_power);
  p.full_torque_speed = t.Double("full_torque_speed", p.full_torque_speed);
  p.max_speed = t.Double("max_speed", p.max_speed);
  t.Finish();
  Validate(t, p);
  return p;
}

// [terrain]: a uniform slope (slope_deg, the tilted-gravity frame) or a ground profile
// (slopes = [{x_start, slope_deg}, ...]), not both; vertical steps (steps = [{x_start, rise}, ...])
// on the profile; obstacles on flat ground.
Terrain ReadTerrain(TomlReader t, ModelParams* model) {
  Terrain terrain;
  model->slope = t.Double("slope_deg", model->slope / kDeg) * kDeg;
  Validate(t, *model);
  std::vector<SlopeBreak> breaks;
  std::vector<TomlReader> rows = t.TableArray("slopes");
  for (size_t i = 0; i < rows.size(); ++i) {
    TomlReader& b = rows[i];
    SlopeBreak brk;
    brk.x_start = b.RequiredDouble("x_start");
    const double slope_deg = b.RequiredDouble("slope_deg");
    b.Finish();
    if (std::abs(brk.x_start) > GroundProfile::kMaxAbsX) b.Fail("x_start", "beyond +-1e4 m");
    if (!(std::abs(slope_deg * kDeg) < GroundProfile::kMaxSlope)) {
      b.Fail("slope_deg", "must be below 30 deg in magnitude");
    }
    if (i > 0 && !(brk.x_start > breaks.back().x_start)) {
      char message[120];
      std::snprintf(message, sizeof message,
                    "breakpoints must be in increasing x_start (the previous one is at %g m)",
                    breaks.back().x_start);
      b.Fail("x_start", message);
    }
    brk.slope = slope_deg * kDeg;
    breaks.push_back(brk);
  }
  if (!breaks.empty() && model->slope != 0.0) {
    t.Fail("slopes",
           "a ground profile does not combine with a uniform slope_deg (the tilted-gravity frame): "
           "give one of them (a profile with one breakpoint before the walk is a uniform slope)");
  }
  // Vertical steps: breakpoints with a rise, on whatever slope the profile has there (one at a
  // slope breakpoint's x_start joins it).
  std::vector<TomlReader> steps = t.TableArray("steps");
  double previous_step = -std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < steps.size(); ++i) {
    TomlReader& st = steps[i];
    const double x = st.RequiredDouble("x_start");
    const double rise = st.RequiredDouble("rise");
    st.Finish();
    if (std::abs(x) > GroundProfile::kMaxAbsX) st.Fail("x_start", "beyond +-1e4 m");
    if (!(x > previous_step)) {
      char message[120];
      std::snprintf(message, sizeof message,
                    "steps must be in increasing x_start (the previous one is at %g m)",
                    previous_step);
      st.Fail("x_start", message);
    }
    previous_step = x;
    if (rise == 0.0 || std::abs(rise) > GroundProfile::kMaxRise) {
      st.Fail("rise", "a step's rise is nonzero and within +-1 m (+ up, - down)");
    }
    if (model->slope != 0.0) {
      st.Fail("x_start",
              "steps do not combine with a uniform slope_deg (the tilted-gravity frame): give the "
              "slope as a ground profile ([[terrain.slopes]])");
    }
    auto at = std::lower_bound(breaks.begin(), breaks.end(), x,
                               [](const SlopeBreak& b, double v) { return b.x_start < v; });
    if (at != breaks.end() && at->x_start == x) {
      at->rise = rise;
    } else {
      SlopeBreak brk;
      brk.x_start = x;
      brk.slope = at == breaks.begin() ? 0.0 : std::prev(at)->slope;
      brk.rise = rise;
      breaks.insert(at, brk);
    }
  }
  if (!breaks.empty()) terrain.ground = GroundProfile(std::move(breaks));
  std::vector<TomlReader> obstacles = t.TableArray("obstacles");
  for (size_t i = 0; i < obstacles.size(); ++i) {
    TomlReader& o = obstacles[i];
    Obstacle obstacle;
    obstacle.x_start = o.RequiredDouble("x_start");
    obstacle.length = o.RequiredDouble("length");
    obstacle.height = o.RequiredDouble("height");
    o.Finish();
    if (obstacle.length <= 0.0) o.Fail("length", "must be > 0");
    if (obstacle.height <= 0.0) o.Fail("height", "must be > 0");
    const GroundProfile& ground = terrain.ground;
    const GroundSegment& under = ground.segment(ground.SegmentAt(obstacle.x_start));
    if (under.slope != 0.0 || obstacle.x_end() > under.x_end) {
      o.Fail("x_start",
             "the obstacle stands on sloped ground (its span must lie on one flat part of "
             "[terrain] slopes; its base is the ground's height there)");
    }
    terrain.obstacles.push_back(obstacle);
  }
  t.Finish();
  Validate(t, terrain);
  return terrain;
}

void ReadSimulation(TomlReader t, Scenario* s) {
  SimOptions& o = s->options;
  if (t.Has("distance")) {
    o.stop_distance = t.Double("distance", 0.0);
    if (!(o.stop_distance > 0.0 && o.stop_distance <= 1e4)) {
      t.Fail("distance", "must be in (0, 1e4] m");
    }
    o.duration = t.Double("duration", kDefaultDistanceTimeLimit);
  } else {
    o.duration = t.RequiredDouble("duration");
  }
  if (!(o.duration >= 0.0 && o.duration <= kMaxDurationS)) {
    t.Fail("duration",
           "must be in [0, " + FormatLimit(kMaxDurationS) + "] s, got " + FormatLimit(o.duration));
  }
  const double rate = t.Double("control_rate_hz", 1.0 / o.control_period);
  if (!(rate >= 1.0 && rate <= kMaxControlRate)) {
    t.Fail("control_rate_hz",
           "must be in [1, " + std::to_string(static_cast<long>(kMaxControlRate)) + "] Hz");
  }
  o.control_period = 1.0 / rate;
  const std::string integrator = t.String("integrator", IntegratorName(o.integrator.kind));
  if (!ParseIntegratorName(integrator, &o.integrator.kind)) {
    t.Fail("integrator",
           "expected \"cvode\", \"cvode-adams\" or \"arkode\", got \"" + integrator + "\"");
  }
  o.integrator.rtol = t.Double("rtol", o.integrator.rtol);
  o.integrator.atol = t.Double("atol", o.integrator.atol);
  o.integrator.max_step = t.Double("max_step", o.integrator.max_step);
  o.integrator.order = static_cast<int>(t.Integer("order", o.integrator.order, 0, 12));
  o.contact = t.Bool("contact", o.contact);
  o.restart_at_samples = t.Bool("restart_at_samples", o.restart_at_samples);
  // 0 (record nothing) is for internal runs only: distance, speed and cost of transport come from
  // the samples.
  o.record_every = static_cast<int>(t.Integer("record_every", o.record_every, 1, 1000000));
  if (t.Has("max_wall_s")) {
    o.max_wall = t.Double("max_wall_s", 0.0);
    if (!(o.max_wall > 0.0)) t.Fail("max_wall_s", "must be > 0 s");
  }
  if (!t.Bool("gravity", true)) s->model.gravity = 0.0;
  t.Finish();
  if (o.duration / o.control_period > kMaxPeriods) {
    t.Fail("duration", "too long for the control rate (more than 1e8 control periods)");
  }
  if (o.duration / o.control_period / o.record_every > kMaxRecordedSamples) {
    t.Fail("record_every", "the run would record more than " + FormatLimit(kMaxRecordedSamples) +
                               " samples (duration / control period / record_every): raise "
                               "record_every or shorten the run");
  }
  std::string error;
  if (!o.IsValid(&error)) t.Fail("", error);
}

void ReadFall(TomlReader t, FallCriteria* f) {
  f->enabled = t.Bool("enabled", f->enabled);
  f->min_hip_height = t.Double("min_hip_height", f->min_hip_height);
  f->max_trunk_pitch = t.Double("max_trunk_pitch_deg", f->max_trunk_pitch / kDeg) * kDeg;
  if (f->max_trunk_pitch <= 0.0) t.Fail("max_trunk_pitch_deg", "must be > 0");
  t.Finish();
}

void ReadInitial(TomlReader t, const Model& model, Scenario* s) {
  Vec7& q = s->q0;
  Vec7& qd = s->qd0;
  q[kX] = t.Double("x", 0.0);
  q[kQ0] = t.Double("q0_deg", 0.0) * kDeg;
  q[kQ11] = t.Double("q11_deg", 0.0) * kDeg;
  q[kQ12] = t.Double("q12_deg", 0.0) * kDeg;
  q[kQ21] = t.Double("q21_deg", 0.0) * kDeg;
  q[kQ22] = t.Double("q22_deg", 0.0) * kDeg;
  qd[kX] = t.Double("xd", 0.0);
  qd[kY] = t.Double("yd", 0.0);
  qd[kQ0] = t.Double("q0d_deg_s", 0.0) * kDeg;
  qd[kQ11] = t.Double("q11d_deg_s", 0.0) * kDeg;
  qd[kQ12] = t.Double("q12d_deg_s", 0.0) * kDeg;
  qd[kQ21] = t.Double("q21d_deg_s", 0.0) * kDeg;
  qd[kQ22] = t.Double("q22d_deg_s", 0.0) * kDeg;
  const bool has_y = t.Has("y"), has_clearance = t.Has("foot_clearance");
  if (has_y == has_clearance) {
    t.Fail("",
           "give exactly one of 'y' (hip height, m) or 'foot_clearance' (lowest foot "
           "above the ground, m)");
  }
  if (has_y) {
    q[kY] = t.Double("y", 0.0);
  } else {
    // Hip height that puts the lowest foot at the requested clearance above its surface.
    const double clearance = t.Double("foot_clearance", 0.0);
    double y = -1e9;
    for (int leg = 0; leg < kNumLegs; ++leg) {
      Vec7 at_zero = q;
      at_zero[kY] = 0.0;
      const Vec2 foot = FootPosition(model, at_zero, leg);
      y = std::max(y, s->terrain.HeightAt(foot.x()) + clearance - foot.y());
    }
    q[kY] = y;
  }
  t.Finish();
}

const char* ControllerName(ControllerKind kind) {
  switch (kind) {
    case ControllerKind::kPdHold:
      return "pd_hold";
    case ControllerKind::kPragmatic:
      return "pragmatic";
    case ControllerKind::kFuzzyCmac:
      return "fuzzy_cmac";
    case ControllerKind::kPassive:
      break;
  }
  return "passive";
}

// passive or pd_hold (ReadScenario has checked the type).
void ReadController(TomlReader t, Scenario* s) {
  const std::string type = t.String("type", "passive");
  if (type == "passive") {
    s->controller = ControllerKind::kPassive;
  } else if (type == "pd_hold") {
    s->controller = ControllerKind::kPdHold;
    PdHoldParams& p = s->pd_hold;
    // Gains: one number for all four joints, or four [hip1, knee1, hip2, knee2].
    for (const char* key : {"kp", "kd"}) {
      Vec4* out = std::string(key) == "kp" ? &p.kp : &p.kd;
      if (t.IsArray(key)) {
        const std::vector<double> v = t.Doubles(key, {}, 4);
        *out = Vec4(v[0], v[1], v[2], v[3]);
      } else {
        *out = Vec4::Constant(t.Double(key, (*out)[0]));
      }
    }
    const std::vector<double> target = t.Doubles(
        "target_deg",
        {s->q0[kQ11] / kDeg, s->q0[kQ12] / kDeg, s->q0[kQ21] / kDeg, s->q0[kQ22] / kDeg}, 4);
    p.target = Vec4(target[0], target[1], target[2], target[3]) * kDeg;
    Validate(t, p);
  }
  t.Finish();
}

// type = "pragmatic": the five rules, from a gait file (`gait`, relative to the scenario) and/or
// single keys; the walk starts from WalkingStartState.
void ReadPragmatic(TomlReader* t, Scenario* s) {
  s->controller = ControllerKind::kPragmatic;
  GaitSpec& spec = s->walking;
  const std::string gait = t->String("gait", "");
  if (!gait.empty()) {
    spec = ReadGaitFile((std::filesystem::path(t->Directory()) / gait).string()).spec;
  }
  PragmaticParams& r = spec.rules;
  r.qr1_dsw = t->Double("qr1_dsw_deg", r.qr1_dsw / kDeg) * kDeg;
  r.qi2_dsw = t->Double("qi2_dsw_deg", r.qi2_dsw / kDeg) * kDeg;
  r.q0_d = t->Double("q0_d_deg", r.q0_d / kDeg) * kDeg;
  r.pulse_torque = t->Double("pulse_torque", r.pulse_torque);
  r.pulse_start = t->Double("pulse_start", r.pulse_start);
  r.pulse_duration = t->Double("pulse_duration", r.pulse_duration);
  r.hip_kp = t->Double("hip_kp", r.hip_kp);
  r.hip_kd = t->Double("hip_kd", r.hip_kd);
  r.trunk_kp = t->Double("trunk_kp", r.trunk_kp);
  r.trunk_kd = t->Double("trunk_kd", r.trunk_kd);
  r.knee_kp = t->Double("knee_kp", r.knee_kp);
  r.knee_kd = t->Double("knee_kd", r.knee_kd);
  spec.start_speed = t->Double("start_speed", spec.start_speed);
  spec.start_angle = t->Double("start_angle_deg", spec.start_angle / kDeg) * kDeg;
  t->Finish();
  Validate(*t, spec);
}

std::string ResolvePath(const TomlReader& t, const std::string& path) {
  const std::filesystem::path p(path);
  return p.is_absolute() ? path : (std::filesystem::path(t.Directory()) / p).string();
}

// [velocity]: profile = "constant" (value = V_d) | "ramp" | "steps" (points = [[t_s, v_m_s], ...]).
VelocityProfile ReadVelocity(TomlReader t) {
  VelocityProfile v;
  const std::string kind = t.String("profile", "constant");
  if (kind == "constant") {
    v.kind = VelocityProfile::Kind::kConstant;
  } else if (kind == "ramp") {
    v.kind = VelocityProfile::Kind::kRamp;
  } else if (kind == "steps") {
    v.kind = VelocityProfile::Kind::kSteps;
  } else {
    t.Fail("profile", "expected \"constant\", \"ramp\" or \"steps\", got \"" + kind + "\"");
  }
  v.points.clear();
  if (v.kind == VelocityProfile::Kind::kConstant && t.Has("value")) {
    if (t.Has("points")) t.Fail("points", "a constant profile takes value or points, not both");
    v.points.push_back({0.0, t.Double("value", 0.0)});
  }
  for (const std::vector<double>& row : t.DoubleRows("points", 2)) {
    v.points.push_back({row[0], row[1]});
  }
  t.Finish();
  if (v.points.empty()) {
    t.Fail(v.kind == VelocityProfile::Kind::kConstant ? "value" : "points",
           "the velocity profile has no points (give value = V_d, or points = [[t_s, V_d], ...])");
  }
  std::string error;
  if (!v.IsValid(&error)) t.Fail("points", error);
  return v;
}

std::vector<TrunkPush> ReadPushes(TomlReader* root) {
  std::vector<TrunkPush> pushes;
  for (TomlReader& t : root->TableArray("push")) {
    TrunkPush p;
    // When: a start time, or an event (a touchdown, the hip passing a point, or both).
    const bool on_event = t.Has("after_touchdown") || t.Has("at_hip_x");
    if (on_event && t.Has("start")) {
      t.Fail("start",
             "a push starts at `start` or on an event (after_touchdown, at_hip_x), "
             "not both");
    }
    if (!on_event) p.start = t.RequiredDouble("start");
    constexpr long kMaxTouchdown = 100000;
    p.after_touchdown = static_cast<int>(t.Integer("after_touchdown", 0, 1, kMaxTouchdown));
    if (t.Has("phase") && p.after_touchdown == 0) {
      t.Fail("phase", "phase times a push after a touchdown: give after_touchdown = k too");
    }
    p.phase = t.Double("phase", 0.0);
    if (!(p.phase >= 0.0 && p.phase <= 1.0)) t.Fail("phase", "a fraction of the step in [0, 1]");
    if (t.Has("at_hip_x")) {
      p.at_hip_x = t.Double("at_hip_x", 0.0);
      if (std::abs(p.at_hip_x) > 1e4) t.Fail("at_hip_x", "beyond +-1e4 m");
    }
    p.duration = t.Double("duration", p.duration);
    if (!(p.duration > 0.0)) t.Fail("duration", "must be > 0 s");
    // How much: a force, or an impulse over the duration (force_x = impulse_n_s / duration).
    if (t.Has("impulse_n_s")) {
      if (t.Has("force_x")) t.Fail("impulse_n_s", "give force_x or impulse_n_s, not both");
      p.force.x() = t.Double("impulse_n_s", 0.0) / p.duration;
    } else {
      p.force.x() = t.Double("force_x", 0.0);
    }
    p.force.y() = t.Double("force_y", 0.0);
    p.height = t.Double("height", p.height);
    t.Finish();
    std::string error;
    if (!p.IsValid(&error)) t.Fail("", error);
    pushes.push_back(p);
  }
  return pushes;
}

PassCriteria ReadCriteria(TomlReader t) {
  PassCriteria c;
  constexpr long kMaxSteps = 1000000;
  c.min_steps = static_cast<int>(t.Integer("min_steps", c.min_steps, 0, kMaxSteps));
  c.min_distance = t.Double("min_distance_m", c.min_distance);
  c.max_l_step_spread = t.Double("max_l_step_spread_m", c.max_l_step_spread);
  c.spread_steps = static_cast<int>(t.Integer("spread_steps", c.spread_steps, 1, kMaxSteps));
  c.min_l_step = t.Double("min_l_step_m", c.min_l_step);
  c.speed_tolerance = t.Double("speed_tolerance_m_s", c.speed_tolerance);
  c.settle_steps = static_cast<int>(t.Integer("settle_steps", c.settle_steps, 0, kMaxSteps));
  c.track_up_to = t.Double("track_up_to_m_s", c.track_up_to);
  c.min_steps_after_obstacles = static_cast<int>(
      t.Integer("min_steps_after_obstacles", c.min_steps_after_obstacles, 0, kMaxSteps));
  c.allow_obstacle_contact = t.Bool("allow_obstacle_contact", c.allow_obstacle_contact);
  c.min_travel_ratio = t.Double("min_travel_ratio", c.min_travel_ratio);
  c.stall.no_touchdown = t.Double("stall_no_touchdown_s", c.stall.no_touchdown);
  c.stall.window = t.Double("stall_window_s", c.stall.window);
  c.stall.min_advance = t.Double("stall_min_advance_m", c.stall.min_advance);
  t.Finish();
  for (const auto& [key, value] : {std::pair<const char*, double>{"min_distance_m", c.min_distance},
                                   {"max_l_step_spread_m", c.max_l_step_spread},
                                   {"min_l_step_m", c.min_l_step},
                                   {"speed_tolerance_m_s", c.speed_tolerance},
                                   {"track_up_to_m_s", c.track_up_to},
                                   {"min_travel_ratio", c.min_travel_ratio},
                                   {"stall_no_touchdown_s", c.stall.no_touchdown},
                                   {"stall_window_s", c.stall.window},
                                   {"stall_min_advance_m", c.stall.min_advance}}) {
    if (value < 0.0) t.Fail(key, "must be >= 0");
  }
  return c;
}

// The FLL file's fuzzy system, parsed once per file (and again when the file changes).
std::shared_ptr<const TsFis> CachedFll(const std::string& path) {
  static std::mutex mutex;
  static std::map<std::string,
                  std::pair<std::filesystem::file_time_type, std::shared_ptr<const TsFis>>>
      cache;
  std::error_code error;
  const auto time = std::filesystem::last_write_time(path, error);
  std::lock_guard<std::mutex> lock(mutex);
  auto found = cache.find(path);
  if (found != cache.end() && !error && found->second.first == time) return found->second.second;
  auto fis = std::make_shared<const TsFis>(LoadFll(path));
  cache[path] = {time, fis};
  return fis;
}

// A membership function's parameters in the FLL's order (Triangle a b c, Trapezoid a b c d,
// Ramp start end, Gaussian mean sd), and back.
std::vector<double> FllParameters(const Membership& m) {
  switch (m.shape) {
    case Membership::Shape::kTriangle:
      return {m.a, m.b, m.c};
    case Membership::Shape::kTrapezoid:
      return {m.a, m.b, m.c, m.d};
    case Membership::Shape::kRampDown:
      return {m.b, m.a};
    case Membership::Shape::kRampUp:
    case Membership::Shape::kGaussian:
      break;
  }
  return {m.a, m.b};
}

Membership FromFllParameters(Membership m, const std::vector<double>& v) {
  if (m.shape == Membership::Shape::kRampUp || m.shape == Membership::Shape::kRampDown) {
    const bool falling = v[0] > v[1];  // Ramp start end
    m.shape = falling ? Membership::Shape::kRampDown : Membership::Shape::kRampUp;
    m.a = falling ? v[1] : v[0];
    m.b = falling ? v[0] : v[1];
    return m;
  }
  m.a = v[0];
  m.b = v[1];
  if (v.size() > 2) m.c = v[2];
  if (v.size() > 3) m.d = v[3];
  return m;
}

// [controller.sets]: <input>.<set> = [parameters in the FLL's order], replacing the FLL file's
// membership functions (every set is readable, so a parameter overlay may tune any breakpoint).
void ReadMembershipSets(TomlReader sets, const TsFis& fll, Scenario* s) {
  TsFis fis = fll;
  bool changed = false;
  for (FuzzyInput& input : fis.inputs) {
    TomlReader table = sets.Table(input.name);
    for (FuzzySet& set : input.sets) {
      const std::vector<double> base = FllParameters(set.membership);
      const std::vector<double> v = table.Doubles(set.name, base, base.size());
      if (v == base) continue;
      set.membership = FromFllParameters(set.membership, v);
      changed = true;
      std::string error;
      if (!set.membership.IsValid(&error)) table.Fail(set.name, error);
    }
    table.Finish();
  }
  sets.Finish();
  if (!changed) return;
  std::string error;
  if (!fis.IsValid(&error)) sets.Fail("", error);
  s->fis = std::move(fis);
}

// [controller.multi_cmac]: the multi_cmac baseline's settings (MultiCmacPatternOptions; angles in
// degrees here).
MultiCmacPatternOptions ReadMultiCmac(TomlReader t) {
  MultiCmacPatternOptions o;
  constexpr long kMaxWidth = 1 << 20;
  o.layers = static_cast<int>(t.Integer("layers", o.layers, 1, kMaxCmacLayers));
  o.e_quantum = t.Double("e_quantum_deg", o.e_quantum / kDeg) * kDeg;
  o.e_width = static_cast<int>(t.Integer("e_width", o.e_width, 1, kMaxWidth));
  o.v_m_quantum = t.Double("v_m_quantum", o.v_m_quantum);
  o.v_m_width = static_cast<int>(t.Integer("v_m_width", o.v_m_width, 1, kMaxWidth));
  o.d_obs_quantum = t.Double("d_obs_quantum", o.d_obs_quantum);
  o.d_obs_width = static_cast<int>(t.Integer("d_obs_width", o.d_obs_width, 1, kMaxWidth));
  o.hash_table_size =
      static_cast<int>(t.Integer("hash_table_size", o.hash_table_size, 1, kMaxMultiCmacTable));
  o.hash_seed = static_cast<std::uint64_t>(
      t.Integer("hash_seed", static_cast<long>(o.hash_seed), 0, std::numeric_limits<long>::max()));
  o.v_m_margin = t.Double("v_m_margin", o.v_m_margin);
  o.grid_e_step = t.Double("grid_e_step_deg", o.grid_e_step / kDeg) * kDeg;
  o.grid_v_m_step = t.Double("grid_v_m_step", o.grid_v_m_step);
  o.grid_d_obs_step = t.Double("grid_d_obs_step", o.grid_d_obs_step);
  o.ridge = t.Double("ridge", o.ridge);
  o.tolerance = t.Double("tolerance", o.tolerance);
  o.max_iterations = static_cast<int>(t.Integer("max_iterations", o.max_iterations, 1, 100000));
  t.Finish();
  for (const auto& [key, value] : {std::pair<const char*, double>{"e_quantum_deg", o.e_quantum},
                                   {"v_m_quantum", o.v_m_quantum},
                                   {"d_obs_quantum", o.d_obs_quantum},
                                   {"grid_e_step_deg", o.grid_e_step},
                                   {"grid_v_m_step", o.grid_v_m_step},
                                   {"grid_d_obs_step", o.grid_d_obs_step},
                                   {"ridge", o.ridge}}) {
    if (!(value > 0.0)) t.Fail(key, "must be > 0");
  }
  if (!(o.tolerance > 0.0 && o.tolerance < 1.0)) t.Fail("tolerance", "must be in (0, 1)");
  if (o.v_m_margin < 0.0) t.Fail("v_m_margin", "must be >= 0");
  for (const auto& [key, width] : {std::pair<const char*, int>{"e_width", o.e_width},
                                   {"v_m_width", o.v_m_width},
                                   {"d_obs_width", o.d_obs_width}}) {
    if (width < o.layers) {
      t.Fail(key, "must be >= layers (" + std::to_string(o.layers) + "): offsets would repeat");
    }
  }
  Validate(t, o);
  return o;
}

// [controller.recovery]: the walker's push recovery (push_recovery.h). Each key is checked here,
// so that an error names its line and key.
void ReadRecovery(TomlReader r, RecoveryParams* p) {
  p->enabled = r.Bool("enabled", p->enabled);
  p->backward_step_speed = r.Double("backward_step_speed", p->backward_step_speed);
  if (std::abs(p->backward_step_speed) > 5.0) {
    r.Fail("backward_step_speed", "must be in [-5, 5] m/s");
  }
  const auto nonnegative = [&r](const char* key, double value, double max, const char* range) {
    const double v = r.Double(key, value);
    if (!(v >= 0.0 && v <= max)) r.Fail(key, std::string("must be in ") + range);
    return v;
  };
  p->placement_gain = nonnegative("placement_gain", p->placement_gain, 10.0, "[0, 10] rad s/m");
  p->placement_max = nonnegative("placement_max", p->placement_max, 1.0, "[0, 1] rad");
  p->placement_start = nonnegative("placement_start", p->placement_start, 10.0, "[0, 10]");
  p->placement_full = nonnegative("placement_full", p->placement_full, 10.0, "[0, 10]");
  p->placement_dead = nonnegative("placement_dead", p->placement_dead, 10.0, "[0, 10] m/s");
  p->trunk_gain = nonnegative("trunk_gain", p->trunk_gain, 10.0, "[0, 10] rad s/m");
  p->trunk_max = nonnegative("trunk_max", p->trunk_max, 1.0, "[0, 1] rad");
  p->nominal_steps = static_cast<int>(r.Integer("nominal_steps", p->nominal_steps, 1, 100));
  p->gravity = r.Double("gravity", p->gravity);
  if (!(p->gravity > 0.0 && p->gravity <= 100.0)) r.Fail("gravity", "must be in (0, 100] m/s^2");
  r.Finish();
  std::string error;
  if (!p->IsValid(&error)) r.Fail("", error);
}

// [controller.velocity_control]: the walker's speed transitions (velocity_control.h).
void ReadVelocityControl(TomlReader r, VelocityControlParams* p) {
  p->enabled = r.Bool("enabled", p->enabled);
  p->v_d_rate = r.Double("v_d_rate", p->v_d_rate);
  if (!(p->v_d_rate >= 0.0 && p->v_d_rate <= 3.0)) r.Fail("v_d_rate", "must be in [0, 3] m/s");
  p->feedforward_gain = r.Double("feedforward_gain", p->feedforward_gain);
  if (!(p->feedforward_gain >= 0.0 && p->feedforward_gain <= 2.0)) {
    r.Fail("feedforward_gain", "must be in [0, 2]");
  }
  p->start_at_map = r.Bool("start_at_map", p->start_at_map);
  // Absent or empty: the reference gaits' map.
  const std::vector<std::vector<double>> map = r.DoubleRows("pitch_map_deg", 2);
  if (!map.empty()) p->pitch_map.clear();
  for (const std::vector<double>& row : map) {
    if (!(row[0] >= 0.0 && row[0] < 3.0 && std::abs(row[1]) < 45.0)) {
      r.Fail("pitch_map_deg", "each point [V_m_s, q0_d_deg] needs V in [0, 3) and |q0_d| < 45");
    }
    p->pitch_map.push_back({row[0], row[1] * kDeg});
  }
  r.Finish();
}

// The walker's own keys of [controller], read over *w (a preset's settings, with the start gait's
// warm-up rules, trunk pitch and V_M).
void ReadWalkerKeys(TomlReader* t, const ModelParams& model, WalkerParams* walker) {
  WalkerParams& w = *walker;
  w.warmup_steps = static_cast<int>(t->Integer("warmup_steps", w.warmup_steps, 0, 1000));
  w.hip_kp = t->Double("hip_kp", w.hip_kp);
  w.hip_kd = t->Double("hip_kd", w.hip_kd);
  w.knee_kp = t->Double("knee_kp", w.knee_kp);
  w.knee_kd = t->Double("knee_kd", w.knee_kd);
  w.stance_knee_kp = t->Double("stance_knee_kp", w.stance_knee_kp);
  w.stance_knee_kd = t->Double("stance_knee_kd", w.stance_knee_kd);
  w.trunk_kp = t->Double("trunk_kp", w.trunk_kp);
  w.trunk_kd = t->Double("trunk_kd", w.trunk_kd);
  w.k_p = t->Double("k_p", w.k_p);
  w.k_v = t->Double("k_v", w.k_v);
  w.q0_d_min = t->Double("q0_d_min_deg", w.q0_d_min / kDeg) * kDeg;
  w.q0_d_max = t->Double("q0_d_max_deg", w.q0_d_max / kDeg) * kDeg;
  w.q0_d_initial = t->Double("q0_d_initial_deg", w.q0_d_initial / kDeg) * kDeg;
  w.v_m_initial = t->Double("v_m_initial", w.v_m_initial);
  w.v_m_average_steps =
      static_cast<int>(t->Integer("v_m_average_steps", w.v_m_average_steps, 1, 100));
  w.fis_v_lead = t->Double("fis_v_lead", w.fis_v_lead);
  w.d_obs_max = t->Double("d_obs_max", w.d_obs_max);
  w.thigh_frame = t->Bool("thigh_frame", w.thigh_frame);
  w.lift_clearance = t->Double("lift_clearance", w.lift_clearance);
  w.lift_d_obs = t->Double("lift_d_obs", w.lift_d_obs);
  w.lift_lead = t->Double("lift_lead", w.lift_lead);
  w.lift_trail = t->Double("lift_trail", w.lift_trail);
  w.lift_ramp = t->Double("lift_ramp", w.lift_ramp);
  w.lift_release = t->Double("lift_release", w.lift_release);
  w.lift_feedback = t->Bool("lift_feedback", w.lift_feedback);
  w.lift_keeps_rules = t->Bool("lift_keeps_rules", w.lift_keeps_rules);
  ReadRecovery(t->Table("recovery"), &w.recovery);
  ReadSlopeKeys(t->Table("slope"), &w.slope);
  ReadVelocityControl(t->Table("velocity_control"), &w.velocity_control);
  ReadStallRecovery(t->Table("stall_recovery"), &w.stall_recovery);
  w.stall_recovery.thigh_length = model.thigh_length;
  w.stall_recovery.shin_length = model.shin_length;
  w.thigh_length = model.thigh_length;
  w.shin_length = model.shin_length;
  {
    // [controller.planner]: the multi-step foot placement over obstacles (step_planner.h).
    TomlReader pt = t->Table("planner");
    StepPlannerParams& pp = w.planner;
    pp.tracked_gaits_only = pt.Bool("tracked_gaits_only", pp.tracked_gaits_only);
    pp.enabled =
        pt.Bool("enabled", pp.enabled);  // the preset's (docs/design.md, "The step planner")
    pp.horizon = pt.Double("horizon", pp.horizon);
    pp.margin_before = pt.Double("margin_before", pp.margin_before);
    pp.margin_after = pt.Double("margin_after", pp.margin_after);
    pp.l_min = pt.Double("l_min", pp.l_min);
    pp.l_max = pt.Double("l_max", pp.l_max);
    pp.l_nominal = pt.Double("l_nominal", pp.l_nominal);
    pp.l_over_max = pt.Double("l_over_max", pp.l_over_max);
    pp.feedback_gain = pt.Double("feedback_gain", pp.feedback_gain);
    pp.bias_initial = pt.Double("bias_initial", pp.bias_initial);
    pp.bias_max = pt.Double("bias_max", pp.bias_max);
    pp.recovery_steps = static_cast<int>(pt.Integer("recovery_steps", pp.recovery_steps, 0, 100));
    pp.stretch = pt.Double("stretch", pp.stretch);
    pp.over_lift_trail = pt.Double("over_lift_trail", pp.over_lift_trail);
    pp.over_lift_release = pt.Double("over_lift_release", pp.over_lift_release);
    pp.hold_margin = pt.Double("hold_margin", pp.hold_margin);
    pp.use_length = pt.Bool("use_length", pp.use_length);
    pp.assumed_length = pt.Double("assumed_length", pp.assumed_length);
    pt.Finish();
    std::string planner_error;
    if (!pp.IsValid(&planner_error)) {
      // Name the key the message starts with ("planner.l_min ..." or "planner: need ...").
      std::string key;
      const std::string head = "planner.";
      if (planner_error.rfind(head, 0) == 0) {
        key = planner_error.substr(head.size(), planner_error.find(' ') - head.size());
      } else if (planner_error.find("l_min") != std::string::npos) {
        key = "l_min";
      }
      pt.Fail(key, planner_error);
    }
  }
  std::string error;
  // The start gait's pitch (the default q0_d_initial) is clamped into the range; a given one must
  // lie in it.
  if (!(w.q0_d_min <= w.q0_d_max)) t->Fail("q0_d_min_deg", "must be <= q0_d_max_deg");
  if (t->Has("q0_d_initial_deg") &&
      !(w.q0_d_initial >= w.q0_d_min && w.q0_d_initial <= w.q0_d_max)) {
    t->Fail("q0_d_initial_deg", "must lie in [q0_d_min_deg, q0_d_max_deg]");
  }
  w.q0_d_initial = std::clamp(w.q0_d_initial, w.q0_d_min, w.q0_d_max);  // the start gait's pitch
  if (!w.IsValid(&error)) t->Fail("", error);
}

// type = "fuzzy_cmac": the chapter's walker (see FuzzyCmacWalker). Reads the gait database to
// choose the start gait; the walk starts from its documented walking start.
// The gait database (`database`, default the shipped one beside the scenario folder) gives the
// gait pattern's files and the per-gait walker settings; `fll`, `networks` and `gaits` may name
// other files for one part. A database override (`rabbit run --gaits DIR`) replaces all of them.
void ReadFuzzyCmac(TomlReader* t, Scenario* s, const std::string& database_override) {
  namespace fs = std::filesystem;
  s->controller = ControllerKind::kFuzzyCmac;
  GaitPatternFiles& f = s->pattern;
  // A path key given as "" is a mistake (it names nothing); left out, it follows `database`.
  auto path_key = [t](const std::string& key) {
    const std::string path = t->String(key, "");
    if (t->Has(key) && path.empty()) {
      t->Fail(key, "an empty path (name a file or folder, or leave the key out)");
    }
    return path;
  };
  const std::string database_key = t->String("database", "../gaits");
  if (database_key.empty()) t->Fail("database", "an empty path (name the gait database's folder)");
  const std::string database = ResolvePath(*t, database_key);
  const std::string fll = path_key("fll");
  const std::string networks = path_key("networks");
  const std::string gaits = path_key("gaits");
  if (!database_override.empty()) {
    f.database = database_override;
    f.fll = (fs::path(f.database) / "gait_pattern.fll").string();
    f.networks = (fs::path(f.database) / "networks").string();
    f.gaits = (fs::path(f.database) / "reference").string();
  } else {
    f.database = database;
    f.fll = fll.empty() ? (fs::path(database) / "gait_pattern.fll").string() : ResolvePath(*t, fll);
    f.networks =
        networks.empty() ? (fs::path(database) / "networks").string() : ResolvePath(*t, networks);
    f.gaits = gaits.empty() ? (fs::path(database) / "reference").string() : ResolvePath(*t, gaits);
  }
  ReadMembershipSets(t->Table("sets"), *CachedFll(f.fll), s);
  const std::vector<GaitIndexEntry> index =
      ReadGaitIndex((std::filesystem::path(f.gaits) / "index.csv").string());
  if (GaitsOfRole(index, GaitRole::kSpeed).empty()) {
    t->Fail("gaits", "the gait database " + f.gaits + " lists no speed gait");
  }
  s->start_gait = t->String("start_gait", "");
  const GaitIndexEntry* start = nullptr;
  if (s->start_gait.empty()) {
    const double v0 = s->velocity.At(0.0);
    for (const GaitIndexEntry& e : index) {
      if (e.role != GaitRole::kSpeed) continue;  // the walker starts from a speed gait
      if (start == nullptr || std::abs(e.measured_v_m - v0) < std::abs(start->measured_v_m - v0)) {
        start = &e;
      }
    }
    s->start_gait = start->name;
  } else {
    for (const GaitIndexEntry& e : index) {
      if (e.name == s->start_gait) start = &e;
    }
    if (start == nullptr) t->Fail("start_gait", "no gait \"" + s->start_gait + "\" in " + f.gaits);
  }
  const GaitRecord gait = ReadGaitFile((std::filesystem::path(f.gaits) / start->file).string());
  s->walking = gait.spec;
  // The preset the keys are read over (walker_presets.h); a baseline "chapter" is the chapter's
  // preset read with the same keys.
  const std::string preset_name = t->String("preset", "adaptive");
  WalkerPreset preset = WalkerPreset::kAdaptive;
  if (!ParseWalkerPreset(preset_name, &preset)) {
    t->Fail("preset",
            "unknown preset \"" + preset_name + "\" (expected " + WalkerPresetNames() + ")");
  }
  s->preset = preset;
  const auto preset_walker = [&](WalkerPreset which) {
    WalkerParams w = PresetWalkerParams(which);
    // The scenario's perception noise and seed ([noise], read before the controller).
    w.v_m_noise = s->walker.v_m_noise;
    w.d_obs_noise = s->walker.d_obs_noise;
    w.seed = s->walker.seed;
    w.warmup = gait.spec.rules;
    w.q0_d_initial = gait.spec.rules.q0_d;
    w.v_m_initial = gait.measured.v_m;
    return w;
  };
  s->walker = preset_walker(preset);
  ReadWalkerKeys(t, s->model, &s->walker);
  if (t->Has("rule_share")) {
    t->Fail("rule_share",
            "per-gait settings are no longer given in a scenario: the rule share of each gait "
            "is the rule_share column of the gait database's walker.csv (" +
                (fs::path(f.database) / kWalkerSettingsFile).string() +
                "; docs/gait-database.md); remove this key");
  }
  // Per-gait settings by name, checked here so that a bad file fails the load (exit 2).
  // gait_rules = false: the chapter's walker (PD tracking of the pattern only), whatever the
  // database's rule shares.
  const bool gait_rules = t->Bool("gait_rules", true);
  s->gait_settings = ReadDatabaseWalkerSettings(f.database);
  for (const auto& entry : s->gait_settings) {
    const std::string& name = entry.first;  // (a structured binding cannot be captured in C++17)
    const bool listed = std::any_of(index.begin(), index.end(),
                                    [&](const GaitIndexEntry& e) { return e.name == name; });
    if (!listed) {
      throw InputError((fs::path(f.database) / kWalkerSettingsFile).string(), 0, name,
                       "walker settings for gait \"" + name + "\", which " + f.gaits +
                           "/index.csv does not list");
    }
  }
  if (!gait_rules) s->gait_settings.clear();
  s->baselines = t->Strings("baselines", {});
  for (size_t i = 0; i < s->baselines.size(); ++i) {
    const std::string& b = s->baselines[i];
    if (b != "pragmatic" && b != "nearest_gait" && b != "multi_cmac" && b != "chapter") {
      t->Fail("baselines", "unknown baseline \"" + b +
                               "\" (expected \"chapter\", \"pragmatic\", \"nearest_gait\" or "
                               "\"multi_cmac\")");
    }
    for (size_t j = 0; j < i; ++j) {
      if (s->baselines[j] == b) t->Fail("baselines", "\"" + b + "\" listed twice");
    }
  }
  if (std::find(s->baselines.begin(), s->baselines.end(), "chapter") != s->baselines.end()) {
    if (preset == WalkerPreset::kChapter) {
      t->Fail("baselines", "\"chapter\" is the main walker here (preset = \"chapter\")");
    }
    s->chapter_walker = preset_walker(WalkerPreset::kChapter);
    // Without the observer: the settings a tuning job sees are the main walker's.
    TomlReader unobserved = t->WithObserver(nullptr);
    ReadWalkerKeys(&unobserved, s->model, &s->chapter_walker);
  }
  s->multi_cmac = ReadMultiCmac(t->Table("multi_cmac"));
  t->Finish();
}

// [controller], merged over the layers (a suite's scenario over its defaults) unless a layer names
// a different `type` than a lower one: then it is read from the layers above that lower one only,
// since the lower layers' keys belong to another controller.
TomlReader ControllerTable(TomlReader* root) {
  const std::vector<const toml::table*>& layers = root->layers();
  std::string type;
  for (size_t i = 0; i < layers.size(); ++i) {
    const toml::node* table = layers[i]->get("controller");
    const toml::node* node =
        table != nullptr && table->is_table() ? table->as_table()->get("type") : nullptr;
    if (node == nullptr || !node->is_string()) continue;
    const std::string here = node->as_string()->get();
    if (type.empty()) {
      type = here;
    } else if (here != type) {
      return root->TableFromLayers("controller", i);
    }
  }
  return root->Table("controller");
}

}  // namespace

std::string SafeNameRule(const std::string& name) {
  std::string rule = "use 1 to " + std::to_string(kMaxNameChars) +
                     " letters, digits, '.', '_' and '-' (no \"..\")";
  if (name.size() > kMaxNameChars) rule += ", got " + std::to_string(name.size()) + " characters";
  return rule;
}

bool IsSafeName(const std::string& name) {
  if (name.empty() || name.size() > kMaxNameChars || name == "." ||
      name.find("..") != std::string::npos) {
    return false;
  }
  for (char c : name) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-')) {
      return false;
    }
  }
  return true;
}

ModelParams ReadModelParams(TomlReader* t, std::string* file) {
  ModelParams p;
  const std::string base = t->String("file", "");
  if (!base.empty()) {
    const std::filesystem::path path = std::filesystem::path(t->Directory()) / base;
    if (!std::filesystem::is_regular_file(path)) {
      t->Fail("file", "no model file " + path.string());
    }
    p = LoadModelFile(path.string());
    if (file != nullptr) *file = path.string();
  }
  ReadModelFields(t, &p);
  t->Finish();
  Validate(*t, p);
  return p;
}

ModelParams LoadModelFile(const std::string& path) {
  TomlReader root = TomlReader::ParseFile(path);
  TomlReader model = root.Table("model");
  ModelParams p;
  ReadModelFields(&model, &p);
  model.Finish();
  root.Finish();
  Validate(model, p);
  return p;
}

Scenario LoadScenario(const std::string& path, const ParamOverlay* overlay) {
  return ReadScenario(TomlReader::ParseFile(path), std::filesystem::path(path).stem().string(),
                      overlay);
}

Scenario ReadScenario(TomlReader root, const std::string& default_name, const ParamOverlay* overlay,
                      std::map<std::string, double>* settings) {
  if (settings != nullptr) {
    auto observed = std::make_shared<std::map<std::string, double>>();
    Scenario s = ReadScenario(root.WithObserver(observed), default_name, overlay, nullptr);
    *settings = std::move(*observed);
    return s;
  }
  const std::string database_override = overlay != nullptr ? overlay->gait_database : "";
  if (overlay != nullptr && !overlay->empty()) {
    TomlReader patched = root.WithPatches(overlay->Patches());
    ParamOverlay database_only;
    database_only.gait_database = database_override;
    Scenario s = ReadScenario(patched, default_name, &database_only);
    const std::vector<std::string> unused = patched.UnusedPatches();
    if (!unused.empty()) {
      overlay->Fail(unused.front(), "names no numeric setting of scenario \"" + s.name + "\" (" +
                                        s.file + ", controller " + ControllerName(s.controller) +
                                        "): see docs/formats/overlay.md");
    }
    return s;
  }
  Scenario s;
  s.file = root.file();
  s.name = root.String("name", default_name);
  if (s.name.empty()) root.Fail("name", "missing: every scenario of a suite needs a name");
  if (!IsSafeName(s.name)) {
    root.Fail("name", SafeNameRule(s.name) + " (it names the output folder)");
  }
  // "shards" is where a sharded run's parts wait for their merge (rabbit/report/shards.h).
  if (s.name == "summary.csv" || s.name == "comparison.csv" || s.name == "targets.csv" ||
      s.name == "members.csv" || s.name == "index.html" || s.name == "shards" || s.name[0] == '.') {
    root.Fail("name", "\"" + s.name + "\" is taken by the report's own files");
  }
  s.description = root.String("description", "");
  s.expected_outcome = root.String("expect_outcome", "");
  Outcome expected;
  if (!s.expected_outcome.empty() && !ParseOutcome(s.expected_outcome, &expected)) {
    std::string names;
    for (Outcome o : kAllOutcomes) {
      names += std::string(names.empty() ? "" : ", ") + "\"" + OutcomeName(o) + "\"";
    }
    root.Fail("expect_outcome", "expected one of " + names);
  }
  s.required = root.Bool("required", s.required);
  s.seed = static_cast<std::uint64_t>(root.Integer("seed", 1, 0, std::numeric_limits<long>::max()));
  TomlReader model_table = root.Table("model");
  s.model = ReadModelParams(&model_table, &s.model_file);
  ReadSimulation(root.Table("simulation"), &s);  // may switch gravity off in s.model
  s.contact = ReadContact(root.Table("contact"));
  s.actuator = ReadActuator(root.Table("actuator"));
  s.terrain = ReadTerrain(root.Table("terrain"), &s.model);
  ReadFall(root.Table("fall"), &s.options.fall);
  s.pushes = ReadPushes(&root);
  s.criteria = ReadCriteria(root.Table("criteria"));
  s.has_velocity = root.Has("velocity");
  if (s.has_velocity) s.velocity = ReadVelocity(root.WholeTable("velocity"));
  TomlReader noise = root.Table("noise");
  s.walker.v_m_noise = noise.Double("v_m_std", 0.0);
  s.walker.d_obs_noise = noise.Double("d_obs_std", 0.0);
  noise.Finish();
  if (s.walker.v_m_noise < 0.0) noise.Fail("v_m_std", "must be >= 0");
  if (s.walker.d_obs_noise < 0.0) noise.Fail("d_obs_std", "must be >= 0");
  s.walker.seed = s.seed;
  TomlReader controller = ControllerTable(&root);
  const std::string type = controller.String("type", "passive");
  if (type != "passive" && type != "pd_hold" && type != "pragmatic" && type != "fuzzy_cmac") {
    controller.Fail("type", "unknown controller \"" + type +
                                "\" (expected \"passive\", \"pd_hold\", \"pragmatic\" or "
                                "\"fuzzy_cmac\")");
  }
  if (type == "pragmatic" || type == "fuzzy_cmac") {
    if (type == "pragmatic") {
      ReadPragmatic(&controller, &s);
    } else {
      if (!root.Has("velocity")) {
        root.Fail("velocity", "the fuzzy_cmac controller needs a [velocity] profile");
      }
      ReadFuzzyCmac(&controller, &s, database_override);
    }
    // The walk starts from the documented walking start: [initial] takes no keys.
    TomlReader initial = root.Table("initial");
    initial.Finish();
    WalkingStartState(Model(s.model), s.walking.rules, s.walking.start_speed, s.walking.start_angle,
                      0, &s.q0, &s.qd0);
    ValidateInitialState(initial, Model(s.model), s);
  } else {
    const TomlReader initial = root.Table("initial");
    ReadInitial(initial, Model(s.model), &s);
    ValidateInitialState(initial, Model(s.model), s);
    ReadController(controller, &s);
  }
  root.Finish();
  return s;
}

std::unique_ptr<Controller> MakeController(const Scenario& scenario) {
  switch (scenario.controller) {
    case ControllerKind::kPdHold:
      return std::make_unique<PdHoldController>(scenario.pd_hold);
    case ControllerKind::kPragmatic:
      return std::make_unique<PragmaticController>(scenario.walking.rules, 0);
    case ControllerKind::kFuzzyCmac:
      throw std::invalid_argument(
          "fuzzy_cmac scenarios need their gait pattern: run them with RunScenario (run.h)");
    case ControllerKind::kPassive:
      break;
  }
  return std::make_unique<PassiveController>();
}

SimSetup MakeSimSetup(const Scenario& scenario, const Model* model) {
  SimSetup setup;
  setup.model = model;
  setup.contact = scenario.contact;
  setup.actuator = scenario.actuator;
  setup.terrain = scenario.terrain;
  setup.pushes = scenario.pushes;
  setup.options = scenario.options;
  return setup;
}

}  // namespace rabbit
