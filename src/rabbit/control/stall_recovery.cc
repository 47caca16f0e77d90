#include "rabbit/control/stall_recovery.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "rabbit/model/model.h"

namespace rabbit {

bool StallRecoveryParams::IsValid(std::string* error) const {
  const std::pair<const char*, double> bounded[] = {
      {"hold_s", hold_s}, {"pulse_s", pulse_s}, {"ramp_s", ramp_s}};
  for (const auto& [name, value] : bounded) {
    if (!(std::isfinite(value) && value >= 0.0 && value <= 10.0)) {
      *error = std::string("stall_recovery.") + name + " must be in [0, 10] s";
      return false;
    }
  }
  if (!(std::isfinite(speed) && std::abs(speed) <= 2.0)) {
    *error = "stall_recovery.speed must be in [-2, 2] m/s";
    return false;
  }
  if (!(std::isfinite(push_off) && std::abs(push_off) <= 1.0) ||
      !(std::isfinite(trunk_lean) && std::abs(trunk_lean) <= 1.0) ||
      !(std::isfinite(knee_dip) && knee_dip >= 0.0 && knee_dip <= 1.0)) {
    *error = "stall_recovery: push_off and trunk_lean in [-1, 1] rad, knee_dip in [0, 1] rad";
    return false;
  }
  if (!(std::isfinite(catch_speed) && catch_speed >= 0.0 && catch_speed <= 2.0) ||
      !(std::isfinite(catch_margin) && std::abs(catch_margin) <= 0.5) ||
      !(std::isfinite(catch_max) && catch_max >= 0.0 && catch_max <= 1.2) ||
      !(std::isfinite(catch_knee) && catch_knee >= 0.0 && catch_knee <= 1.5)) {
    *error =
        "stall_recovery: catch_speed in [0, 2] m/s, catch_margin in [-0.5, 0.5] m, catch_max in "
        "[0, 1.2] rad, catch_knee in [0, 1.5] rad";
    return false;
  }
  if (!(thigh_length > 0.0 && shin_length > 0.0 && gravity > 0.0)) {
    *error = "stall_recovery: leg lengths and gravity must be positive";
    return false;
  }
  if (2.0 * ramp_s > pulse_s) {
    *error = "stall_recovery.ramp_s must be at most half of pulse_s";
    return false;
  }
  return true;
}

void StallRecovery::Observe(const Observation& obs, bool armed) {
  if (!p_.enabled) return;
  armed_ = armed;
  const bool split = obs.foot_contact[0] && obs.foot_contact[1];
  if (!armed || Active(obs.t) || !split || !(obs.qd[kX] < p_.speed)) {
    slow_since_ = -1.0;
    return;
  }
  // The spell counts from the end of the last pulse at the earliest.
  if (slow_since_ < 0.0) slow_since_ = obs.t;
  if (obs.t - slow_since_ >= p_.hold_s) {
    pulse_start_ = obs.t;
    ++pulses_;
    slow_since_ = -1.0;
  }
}

double StallRecovery::Strength(double t) const {
  if (!p_.enabled || pulse_start_ < 0.0) return 0.0;
  const double s = t - pulse_start_;
  if (!(s >= 0.0 && s < p_.pulse_s)) return 0.0;
  if (p_.ramp_s <= 0.0) return 1.0;
  return std::clamp(std::min(s, p_.pulse_s - s) / p_.ramp_s, 0.0, 1.0);
}

bool StallRecovery::Active(double t) const {
  return p_.enabled && pulse_start_ >= 0.0 && t - pulse_start_ >= 0.0 &&
         t - pulse_start_ < p_.pulse_s;
}

double StallRecovery::CatchAngle(double xd, double y) const {
  const double dx = xd * std::sqrt(std::max(y, 1e-3) / p_.gravity) - p_.catch_margin;
  const double s = dx / (p_.thigh_length + p_.shin_length);
  return std::clamp(std::asin(std::clamp(s, -1.0, 1.0)), -p_.catch_max, p_.catch_max);
}

bool StallRecovery::Catching(const Observation& obs, int stance) const {
  return p_.enabled && armed_ && obs.qd[kX] < -p_.catch_speed && !obs.foot_contact[1 - stance];
}

void StallRecovery::Apply(const Observation& obs, int stance, Eigen::Vector4d* ref) const {
  Eigen::Vector4d& r = *ref;
  if (Catching(obs, stance)) {
    // The hip joint's angle is the thigh's absolute angle plus the trunk's pitch.
    // The pendulum's height is the hip's above the local ground (on a step or a ramp too).
    const double ground = obs.terrain != nullptr ? obs.terrain->HeightAt(obs.q[kX]) : 0.0;
    r << CatchAngle(obs.qd[kX], obs.q[kY] - ground) + obs.q[kQ0], -p_.catch_knee, obs.qd[kQ0], 0.0;
    return;
  }
  const double a = Strength(obs.t);
  if (a == 0.0) return;
  r[0] -= a * p_.push_off;
  // The knee's reference moves toward straight (0) with the pulse's strength.
  r[1] *= 1.0 - a;
  r[3] *= 1.0 - a;
}

double StallRecovery::StanceKnee(double t) const { return -Strength(t) * p_.knee_dip; }

double StallRecovery::TrunkOffset(double t) const { return Strength(t) * p_.trunk_lean; }

}  // namespace rabbit
