#include "rabbit/control/terrain_steps.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace rabbit {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The ground's two levels at breakpoint i (before and beyond its face).
std::pair<double, double> Levels(const GroundProfile& ground, int i) {
  const double x = ground.breaks()[i].x_start;
  return {ground.segment(i).HeightAt(x), ground.segment(i + 1).HeightAt(x)};
}

}  // namespace

bool TerrainStepParams::IsValid(std::string* error) const {
  const std::pair<const char*, double> lengths[] = {{"reach", reach},
                                                    {"clearance", clearance},
                                                    {"lead", lead},
                                                    {"trail", trail},
                                                    {"ramp", ramp},
                                                    {"release", release},
                                                    {"knee_ramp_s", knee_ramp_s},
                                                    {"face_before", face_before},
                                                    {"face_after", face_after},
                                                    {"up_knee_ramp_s", up_knee_ramp_s},
                                                    {"up_speed", up_speed},
                                                    {"down_speed", down_speed}};
  for (const auto& [name, value] : lengths) {
    if (!(std::isfinite(value) && value >= 0.0 && value <= 2.0)) {
      *error = std::string("steps.") + name + " must be in [0, 2]";
      return false;
    }
  }
  if (!(std::isfinite(speed_before) && speed_before >= 0.0 && speed_before <= 5.0)) {
    *error = "steps.speed_before must be in [0, 5] m";
    return false;
  }
  if (!(std::isfinite(up_lean) && std::abs(up_lean) <= 20.0) ||
      !(std::isfinite(down_lean) && std::abs(down_lean) <= 20.0)) {
    *error = "steps.up_lean and steps.down_lean must be in [-20, 20] rad/m";
    return false;
  }
  if (hold_steps < 0 || hold_steps > 100) {
    *error = "steps.hold_steps must be in [0, 100]";
    return false;
  }
  if (lean_steps < 0 || lean_steps > 100) {
    *error = "steps.lean_steps must be in [0, 100]";
    return false;
  }
  if (!(std::isfinite(knee_share) && knee_share >= 0.0 && knee_share <= 1.0) ||
      !(std::isfinite(up_knee_share) && up_knee_share >= 0.0 && up_knee_share <= 1.0)) {
    *error = "steps.knee_share and steps.up_knee_share must be in [0, 1]";
    return false;
  }
  if (!(std::isfinite(up_knee_at) && std::abs(up_knee_at) <= 1.0)) {
    *error = "steps.up_knee_at must be in [-1, 1] m";
    return false;
  }
  if (!(thigh_length > 0.0 && shin_length > 0.0)) {
    *error = "steps: leg lengths must be positive";
    return false;
  }
  return true;
}

double RiseBetween(const GroundProfile& ground, double x_a, double x_b) {
  const int a = ground.SegmentAt(x_a), b = ground.SegmentAt(x_b);
  double rise = 0.0;
  // Segment i > 0 starts at breakpoint i - 1.
  for (int i = std::min(a, b); i < std::max(a, b); ++i) rise += ground.breaks()[i].rise;
  return b >= a ? rise : -rise;
}

StepFace StepIn(const GroundProfile& ground, double x_lo, double x_hi) {
  for (const SlopeBreak& b : ground.breaks()) {
    if (b.rise != 0.0 && b.x_start > x_lo && b.x_start <= x_hi) return {true, b.x_start, b.rise};
  }
  return {};
}

double KneeForShortening(double l1, double l2, double shorten) {
  const double straight = l1 + l2;
  const double length = std::clamp(straight - shorten, std::abs(l1 - l2) + 1e-6, straight);
  const double c = (length * length - l1 * l1 - l2 * l2) / (2.0 * l1 * l2);
  return -std::acos(std::clamp(c, -1.0, 1.0));
}

void TerrainSteps::OnTouchdown(const Terrain& terrain, double t, const Vec2& landing,
                               const Vec2& other) {
  if (!p_.enabled) return;
  const GroundProfile& ground = terrain.ground;
  const double front = landing.x(), back = other.x();
  // The coming swing's landing, predicted from the last step's length.
  const double predicted = front + std::max(front - back, 0.0);
  // The lift: the first step up between the swing foot and the predicted landing + reach.
  lift_face_ = {};
  for (const SlopeBreak& b : ground.breaks()) {
    if (b.rise > 0.0 && b.x_start > std::min(back, front) && b.x_start <= predicted + p_.reach) {
      lift_face_ = {true, b.x_start, b.rise};
      break;
    }
  }
  const StepFace crossed = StepIn(ground, front, predicted + p_.reach);
  // The approach speed: the faces between the back foot and speed_before ahead of the front one.
  approach_speed_ = 0.0;
  for (const SlopeBreak& b : ground.breaks()) {
    if (b.rise != 0.0 && b.x_start > std::min(back, front) &&
        b.x_start <= front + p_.speed_before) {
      approach_speed_ = std::max(approach_speed_, b.rise > 0.0 ? p_.up_speed : p_.down_speed);
    }
  }
  // The hold: the step just taken crossed a face (from its take-off, the other foot's x at the
  // last touchdown, to the landing).
  const double takeoff = std::isnan(takeoff_) ? back : takeoff_;
  takeoff_ = back;
  if (hold_left_ > 0) --hold_left_;
  if (StepIn(ground, std::min(takeoff, front), std::max(takeoff, front)).found) {
    hold_left_ = p_.hold_steps;
  }
  if (lean_left_ > 0) --lean_left_;
  knee_from_ = knee_to_ = 0.0;
  knee_t0_ = t;
  knee_gate_x_ = NAN;
  const double l1 = p_.thigh_length, l2 = p_.shin_length;
  const double climbed = RiseBetween(ground, back, front);
  if (climbed > 0.0 && p_.up_knee_share > 0.0) {
    // Landed on the upper level: the new stance knee extends through the rise.
    knee_from_ = KneeForShortening(l1, l2, climbed * p_.up_knee_share);
    knee_ramp_ = p_.up_knee_ramp_s;
    if (p_.up_knee_by_hip) {
      knee_gate_x_ = front + p_.up_knee_at;
      knee_t0_ = kInf;
    }
  }
  if (crossed.found) {
    lean_ = crossed.rise > 0.0 ? p_.up_lean * crossed.rise : p_.down_lean * -crossed.rise;
    lean_left_ = p_.lean_steps;
    if (crossed.rise < 0.0 && p_.knee_share > 0.0) {
      knee_from_ = 0.0;
      knee_to_ = KneeForShortening(l1, l2, -crossed.rise * p_.knee_share);
      knee_ramp_ = p_.knee_ramp_s;
      knee_gate_x_ = NAN;
      knee_t0_ = t;
    }
  }
}

Vec2 TerrainSteps::LevelledLanding(const Terrain& terrain, const Vec2& landing,
                                   const Vec2& other) const {
  if (!p_.enabled) return landing;
  return {landing.x(), landing.y() - RiseBetween(terrain.ground, other.x(), landing.x())};
}

double TerrainSteps::LiftHeight(const Terrain& terrain, double foot_x) const {
  if (!LiftArmed()) return -kInf;
  const GroundProfile& ground = terrain.ground;
  const int i = ground.SegmentAt(lift_face_.x) - 1;  // the face's breakpoint
  if (i < 0) return -kInf;
  const auto [lower, upper] = Levels(ground, i);
  const double lo = lift_face_.x - p_.lead, hi = lift_face_.x + p_.trail;
  double a = 1.0;
  if (foot_x < lo) a = p_.ramp > 0.0 ? 1.0 - (lo - foot_x) / p_.ramp : 0.0;
  if (foot_x > hi) a = p_.release > 0.0 ? 1.0 - (foot_x - hi) / p_.release : 0.0;
  a = std::clamp(a, 0.0, 1.0);
  return a > 0.0 ? lower + a * (upper - lower + p_.clearance) : -kInf;
}

double TerrainSteps::FaceAhead(const Terrain& terrain, double x, double horizon,
                               double margin_before, double margin_after, double* length) const {
  if (!p_.enabled || !p_.placement) return kInf;
  const StepFace face = StepIn(terrain.ground, x, x + horizon);
  if (!face.found) return kInf;
  const double edge = face.x - p_.face_before + margin_before;
  if (edge < x) return kInf;  // the last foot before the face has landed
  *length = std::max(p_.face_before + p_.face_after - margin_before - margin_after, 0.0);
  return edge - x;
}

void TerrainSteps::Observe(double t, double hip_x) {
  if (!p_.enabled || std::isnan(knee_gate_x_) || hip_x < knee_gate_x_) return;
  knee_t0_ = t;
  knee_gate_x_ = NAN;
}

double TerrainSteps::StanceKnee(double t) const {
  if (!p_.enabled || (knee_from_ == 0.0 && knee_to_ == 0.0)) return 0.0;
  const double s = t < knee_t0_           ? 0.0  // the extension waits for the hip
                   : knee_ramp_ > 0.0 ? std::clamp((t - knee_t0_) / knee_ramp_, 0.0, 1.0)
                                      : 1.0;
  return knee_from_ + s * (knee_to_ - knee_from_);
}

}  // namespace rabbit
