#include "rabbit/control/push_recovery.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "rabbit/model/model.h"

namespace rabbit {

bool RecoveryParams::IsValid(std::string* error) const {
  const std::pair<const char*, double> bounded[] = {{"placement_gain", placement_gain},
                                                    {"placement_max", placement_max},
                                                    {"placement_start", placement_start},
                                                    {"placement_full", placement_full},
                                                    {"placement_dead", placement_dead},
                                                    {"trunk_gain", trunk_gain},
                                                    {"trunk_max", trunk_max},
                                                    {"response_dead", response_dead},
                                                    {"response_fis_gain", response_fis_gain},
                                                    {"response_fis_max", response_fis_max},
                                                    {"response_fis_step", response_fis_step},
                                                    {"response_rules_dead", response_rules_dead},
                                                    {"response_place_gain", response_place_gain},
                                                    {"response_place_max", response_place_max},
                                                    {"response_place_back", response_place_back},
                                                    {"response_trunk_max", response_trunk_max},
                                                    {"response_catch_back", response_catch_back},
                                                    {"response_catch_from", response_catch_from}};
  for (const auto& [name, value] : bounded) {
    if (!(std::isfinite(value) && value >= 0.0 && value <= 10.0)) {
      *error = std::string("recovery.") + name + " must be in [0, 10]";
      return false;
    }
  }
  if (!(std::isfinite(backward_step_speed) && std::abs(backward_step_speed) <= 5.0)) {
    *error = "recovery.backward_step_speed must be in [-5, 5] m/s";
    return false;
  }
  if (placement_max > 1.0 || trunk_max > 1.0) {
    *error = "recovery.placement_max and trunk_max must be <= 1 rad";
    return false;
  }
  if (response_dead > 2.0 || response_fis_max > 2.0 || response_fis_step > 2.0 ||
      response_rules_dead > 2.0) {
    *error =
        "recovery.response_dead, response_fis_max, response_fis_step and "
        "response_rules_dead must be <= 2 m/s";
    return false;
  }
  if (response_hold_steps < 0 || response_hold_steps > 100 || response_fis_steps < 0 ||
      response_fis_steps > 100 || response_rules_steps < 0 || response_rules_steps > 100) {
    *error =
        "recovery.response_hold_steps, response_fis_steps and response_rules_steps must be in "
        "[0, 100]";
    return false;
  }
  if (!(std::isfinite(response_trunk_gain) && std::abs(response_trunk_gain) <= 10.0) ||
      response_place_max > 1.0 || response_place_back > 1.0 || response_trunk_max > 1.0) {
    *error =
        "recovery.response_trunk_gain must be in [-10, 10], response_place_max, "
        "response_place_back and response_trunk_max <= 1";
    return false;
  }
  if (response_catch_back > 0.5 || response_catch_from > 1.5) {
    *error = "recovery.response_catch_back must be <= 0.5 m and response_catch_from <= 1.5";
    return false;
  }
  if (!(std::isfinite(response_reach) && response_reach >= 0.0 && response_reach <= 1.0)) {
    *error = "recovery.response_reach must be in [0, 1]";
    return false;
  }
  if (!(std::isfinite(response_reach_dead) && response_reach_dead >= 0.0 &&
        response_reach_dead <= 2.0)) {
    *error = "recovery.response_reach_dead must be in [0, 2] m/s";
    return false;
  }
  if (!(std::isfinite(response_reach_ref_min) && response_reach_ref_min >= 0.0 &&
        response_reach_ref_min <= 2.0)) {
    *error = "recovery.response_reach_ref_min must be in [0, 2] m/s";
    return false;
  }
  if (nominal_steps < 1 || nominal_steps > 100) {
    *error = "recovery.nominal_steps must be in [1, 100]";
    return false;
  }
  if (!(std::isfinite(gravity) && gravity > 0.0 && gravity <= 100.0)) {
    *error = "recovery.gravity must be in (0, 100] m/s^2";
    return false;
  }
  return true;
}

double OrbitalVelocity(double dx, double xd, double y, double gravity) {
  const double e = xd * xd - gravity / std::max(y, 1e-3) * dx * dx;
  // E >= 0: the hip passes over the foot in the direction it moves; E < 0: it turns back before
  // the foot and falls to the side of the foot it is on.
  return e >= 0.0 ? std::copysign(std::sqrt(e), xd) : std::copysign(std::sqrt(-e), dx);
}

double PlacementFade(double s, double start, double full) {
  if (s < start) return 0.0;
  if (full <= start || s >= full) return 1.0;
  return (s - start) / (full - start);
}

double PushRecovery::Progress(double t) const {
  return t_touchdown_ >= 0.0 && t_step_ > 0.0 ? (t - t_touchdown_) / t_step_ : -1.0;
}

double PushRecovery::Nominal(double s) const {
  const int bin = StepPhaseBins::Of(s);
  return bin >= 0 && learnt_[bin] > 0 ? nominal_[bin] : std::nan("");
}

void PushRecovery::Observe(const Observation& obs, int stance) {
  if (!p_.enabled) return;
  v_orb_ = OrbitalVelocity(obs.q[kX] - obs.foot_pos[stance].x(), obs.qd[kX], obs.q[kY], p_.gravity);
  if (!std::isfinite(v_orb_)) v_orb_ = 0.0;
  const double s = Progress(obs.t);
  if (!bins_.Add(s, v_orb_)) return;
  const double nominal = Nominal(s);
  if (std::isfinite(nominal) && std::abs(v_orb_ - nominal) > p_.placement_dead) disturbed_ = true;
}

void PushRecovery::OnTouchdown(double t, double t_step) {
  if (!p_.enabled) return;
  if (!disturbed_ && t_touchdown_ >= 0.0 && t_step > 0.0) {
    for (int b = 0; b < kPhaseBins; ++b) {
      if (!bins_.has(b)) continue;
      const double mean = bins_.mean(b);
      learnt_[b] = std::min(learnt_[b] + 1, p_.nominal_steps);
      nominal_[b] += (mean - nominal_[b]) / learnt_[b];
    }
    t_step_ = t_step;
  }
  if (t_step_ <= 0.0 && t_step > 0.0) t_step_ = t_step;
  bins_.Clear();
  disturbed_ = false;
  t_touchdown_ = t;
}

bool PushRecovery::AcceptsLandingBehind(const Observation& obs) const {
  return p_.enabled && obs.qd[kX] < p_.backward_step_speed;
}

double PushRecovery::Excess(double t) const {
  if (!p_.enabled) return 0.0;
  const double nominal = Nominal(Progress(t));
  if (!std::isfinite(nominal)) return 0.0;
  // A soft dead zone: no reaction within placement_dead, then linear in the excess.
  const double excess = std::abs(v_orb_ - nominal) - p_.placement_dead;
  return excess > 0.0 ? std::copysign(excess, v_orb_ - nominal) : 0.0;
}

double PushRecovery::SwingOffset(double t) const {
  if (!p_.enabled || p_.placement_gain == 0.0) return 0.0;
  const double dv = Excess(t);
  if (dv == 0.0) return 0.0;
  const double fade = PlacementFade(Progress(t), p_.placement_start, p_.placement_full);
  return fade * std::clamp(p_.placement_gain * dv, -p_.placement_max, p_.placement_max);
}

double PushRecovery::TrunkOffset(double t) const {
  if (!p_.enabled || p_.trunk_gain == 0.0) return 0.0;
  return -std::clamp(p_.trunk_gain * Excess(t), -p_.trunk_max, p_.trunk_max);
}

}  // namespace rabbit
