#include "rabbit/control/pragmatic_rules.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "rabbit/io/error.h"

namespace rabbit {

bool PragmaticParams::IsValid(std::string* error) const {
  const std::vector<std::pair<const char*, double>> values = {{"qr1_dsw", qr1_dsw},
                                                              {"qi2_dsw", qi2_dsw},
                                                              {"q0_d", q0_d},
                                                              {"pulse_torque", pulse_torque},
                                                              {"pulse_start", pulse_start},
                                                              {"pulse_duration", pulse_duration},
                                                              {"hip_kp", hip_kp},
                                                              {"hip_kd", hip_kd},
                                                              {"trunk_kp", trunk_kp},
                                                              {"trunk_kd", trunk_kd},
                                                              {"knee_kp", knee_kp},
                                                              {"knee_kd", knee_kd}};
  for (const auto& [name, value] : values) {
    if (!std::isfinite(value)) {
      *error = std::string(name) + " must be finite";
      return false;
    }
  }
  // Each setting by name, with the value given.
  const std::pair<const char*, double> nonnegative[] = {
      {"pulse_start", pulse_start}, {"pulse_duration", pulse_duration},
      {"hip_kp", hip_kp},           {"hip_kd", hip_kd},
      {"trunk_kp", trunk_kp},       {"trunk_kd", trunk_kd},
      {"knee_kp", knee_kp},         {"knee_kd", knee_kd}};
  for (const auto& [name, value] : nonnegative) {
    if (value < 0.0) {
      *error = std::string(name) + " must be >= 0, got " + FormatLimit(value);
      return false;
    }
  }
  if (!(qi2_dsw <= 0.0 && qi2_dsw > -M_PI / 2)) {
    *error = "qi2_dsw must be in (-90, 0] deg (knees flex to negative angles)";
    return false;
  }
  if (!(qr1_dsw > 0.0 && qr1_dsw < M_PI / 2)) {
    *error = "qr1_dsw must be in (0, 90) deg";
    return false;
  }
  if (!(std::abs(q0_d) < M_PI / 4)) {
    *error = "q0_d must be within 45 deg (the fall limit)";
    return false;
  }
  for (const auto& [name, value] : {std::pair<const char*, double>{"pulse_start", pulse_start},
                                    {"pulse_duration", pulse_duration}}) {
    if (value > 10.0) {
      *error = std::string(name) + " must be <= 10 s, got " + FormatLimit(value);
      return false;
    }
  }
  if (std::abs(pulse_torque) > 1e4) {
    *error = "|pulse_torque| must be <= 1e4 N m, got " + FormatLimit(pulse_torque);
    return false;
  }
  return true;
}

PragmaticController::PragmaticController(const PragmaticParams& params, int stance_leg)
    : p_(params), stance_(stance_leg) {}

void PragmaticController::Restart(double swing_start, int stance_leg) {
  meter_ = GaitMeter();
  stance_ = stance_leg;
  swing_start_ = swing_start;
  hip_locked_ = knee_flexed_ = knee_locked_ = false;
}

Vec4 PragmaticController::Compute(const Observation& obs) {
  const int swing = 1 - stance_;
  if (meter_.Update(obs) && meter_.last_step().leg == swing) {
    // The swing foot landed: support exchange, a new swing phase for the other leg.
    stance_ = swing;
    swing_start_ = obs.t;
    hip_locked_ = knee_flexed_ = knee_locked_ = false;
  }
  const int st = stance_, sw = 1 - stance_;
  const int st_hip = 3 + 2 * st, sw_hip = 3 + 2 * sw;  // q indices of the hips; knees are +1
  Vec4 tau = Vec4::Zero();
  const auto& q = obs.q;
  const auto& qd = obs.qd;

  // Stance hip: the trunk (eq. 16). Stance knee: locked straight (eq. 18).
  tau[2 * st] = p_.trunk_kp * (p_.q0_d - q[kQ0]) - p_.trunk_kd * qd[kQ0];
  tau[2 * st + 1] = p_.knee_kp * (0.0 - q[st_hip + 1]) - p_.knee_kd * qd[st_hip + 1];

  // Swing hip: pulse, passive, then locked at qr1_dsw (eqs. 14-15).
  const double qr1 = q[sw_hip] - q[st_hip];
  const double qr1_rate = qd[sw_hip] - qd[st_hip];
  const double phase = obs.t - swing_start_;
  if (!hip_locked_ && qr1 > p_.qr1_dsw) hip_locked_ = true;
  if (hip_locked_) {
    tau[2 * sw] = p_.hip_kp * (p_.qr1_dsw - qr1) - p_.hip_kd * qr1_rate;
  } else if (phase > p_.pulse_start && phase < p_.pulse_start + p_.pulse_duration) {
    tau[2 * sw] = p_.pulse_torque;
  }

  // Swing knee: free, then locked at the end of its extension (eq. 17).
  const double knee = q[sw_hip + 1];
  if (knee < p_.qi2_dsw) knee_flexed_ = true;
  if (!knee_locked_ && ((knee_flexed_ && knee >= p_.qi2_dsw) || hip_locked_)) knee_locked_ = true;
  if (knee_locked_) {
    tau[2 * sw + 1] = p_.knee_kp * (p_.qi2_dsw - knee) - p_.knee_kd * qd[sw_hip + 1];
  }
  return tau;
}

void WalkingStartState(const Model& model, const PragmaticParams& params, double speed,
                       double stance_angle, int stance_leg, Vec7* q, Vec7* qd) {
  const int st_hip = 3 + 2 * stance_leg, sw_hip = 3 + 2 * (1 - stance_leg);
  Vec7& x = *q;
  x.setZero();
  x[kQ0] = params.q0_d;
  x[st_hip] = stance_angle + params.q0_d;  // thigh angle th = q_i1 - q0
  x[sw_hip] = -0.5 * params.qr1_dsw + params.q0_d;
  x[sw_hip + 1] = params.qi2_dsw;
  const Vec2 foot = FootPosition(model, x, stance_leg);  // hip at the origin
  x[kX] = -foot.x();
  x[kY] = -foot.y();
  // Rigid rotation at rate w (counter-clockwise) about the stance foot, now at the origin:
  // hip velocity w x (hip - foot) = w (-y, x); forward speed `speed` needs w = -speed / y.
  const double w = -speed / x[kY];
  qd->setZero();
  (*qd)[kX] = -w * x[kY];
  (*qd)[kY] = w * x[kX];
  (*qd)[kQ0] = -w;  // the trunk's counter-clockwise angle is -q0
}

}  // namespace rabbit
