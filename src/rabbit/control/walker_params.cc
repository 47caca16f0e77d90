// WalkerParams::IsValid (declared in fuzzy_cmac_walker.h): the range of every walker setting, and
// the checks of the mechanisms the walker holds.
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "rabbit/control/fuzzy_cmac_walker.h"

namespace rabbit {

const std::vector<WalkerRange>& RuleGaitChoiceRanges() {
  using P = WalkerParams;
  static const std::vector<WalkerRange> ranges = {
      {"rule_gait_choice_mixed_below", &P::rule_gait_choice_mixed_below, 0.0, 3.0, " m/s"},
      {"rule_gait_choice_mixed_point", &P::rule_gait_choice_mixed_point, 0.0, 1.0, ""},
      {"rule_gait_choice_hold_rate", &P::rule_gait_choice_hold_rate, 0.0, 1.0, " m/s"},
  };
  return ranges;
}

bool WalkerParams::IsValid(std::string* error) const {
  const std::pair<const char*, double> values[] = {
      {"hip_kp", hip_kp},
      {"hip_kd", hip_kd},
      {"knee_kp", knee_kp},
      {"knee_kd", knee_kd},
      {"stance_knee_kp", stance_knee_kp},
      {"stance_knee_kd", stance_knee_kd},
      {"stance_knee_rate", stance_knee_rate},
      {"trunk_kp", trunk_kp},
      {"trunk_kd", trunk_kd},
      {"d_obs_max", d_obs_max},
      {"lift_clearance", lift.clearance},
      {"lift_height_gain", lift.height_gain},
      {"lift_d_obs", lift.d_obs},
      {"lift_lead", lift.lead},
      {"lift_trail", lift.trail},
      {"lift_ramp", lift.ramp},
      {"lift_release", lift.release},
      {"lift_release_rate", lift.release_rate},
      {"lift_trailing_clearance", lift.trailing_clearance},
      {"v_m_noise", v_m_noise},
      {"d_obs_noise", d_obs_noise}};
  for (const auto& [name, value] : values) {
    if (!(std::isfinite(value) && value >= 0.0 && value <= 1e5)) {
      *error = std::string(name) + " must be in [0, 1e5]";
      return false;
    }
  }
  if (!(stance_knee_flexed >= -M_PI && stance_knee_flexed <= 0.0)) {
    *error = "stance_knee_flexed must be in [-180, 0] deg (a flexed knee is negative)";
    return false;
  }
  if (!std::isfinite(k_p) || !std::isfinite(k_v) || std::abs(k_p) > 10 || std::abs(k_v) > 10) {
    *error = "k_p and k_v must be finite, within 10 (rad per m/s)";
    return false;
  }
  if (!(q0_d_min <= q0_d_max && q0_d_min > -M_PI / 4 && q0_d_max < M_PI / 4)) {
    *error = "need -45 deg < q0_d_min <= q0_d_max < 45 deg";
    return false;
  }
  if (!(q0_d_initial >= q0_d_min && q0_d_initial <= q0_d_max)) {
    *error = "q0_d_initial must lie in [q0_d_min, q0_d_max]";
    return false;
  }
  if (!(std::isfinite(v_m_initial) && v_m_initial > 0.0 && v_m_initial < 3.0)) {
    *error = "v_m_initial must be in (0, 3) m/s";
    return false;
  }
  if (!(thigh_length > 0.0 && shin_length > 0.0 && std::isfinite(thigh_length) &&
        std::isfinite(shin_length))) {
    *error = "thigh_length and shin_length must be > 0";
    return false;
  }
  if (d_obs_max <= 0.0) {
    *error = "d_obs_max must be > 0";
    return false;
  }
  for (const WalkerRange& r : RuleGaitChoiceRanges()) {
    const double value = this->*r.field;
    if (!(value >= r.lo && value <= r.hi)) {
      char text[160];
      std::snprintf(text, sizeof text, "%s must be in [%g, %g]%s", r.key, r.lo, r.hi, r.unit);
      *error = text;
      return false;
    }
  }
  if (!(std::isfinite(fis_v_lead) && fis_v_lead >= 0.0 && fis_v_lead <= 2.0)) {
    *error = "fis_v_lead must be in [0, 2]";
    return false;
  }
  for (double r : rule_share) {
    if (!(std::isfinite(r) && r >= 0.0 && r <= 1.0)) {
      *error = "rule_share: every factor must be in [0, 1]";
      return false;
    }
  }
  if (!rule_share.empty()) {
    for (const PragmaticParams& rules : gait_rules) {
      if (!rules.IsValid(error)) {
        *error = "reference gait rules: " + *error;
        return false;
      }
    }
  }
  if (v_m_average_steps < 1 || v_m_average_steps > 100) {
    *error = "v_m_average_steps must be in [1, 100]";
    return false;
  }
  if (warmup_steps < 0 || warmup_steps > 1000) {
    *error = "warmup_steps must be in [0, 1000]";
    return false;
  }
  if (!(warmup_handover_ratio >= 0.0 && warmup_handover_ratio <= 1.0)) {
    *error = "warmup_handover_ratio must be in [0, 1]";
    return false;
  }
  if (warmup_handover_after < 0 || warmup_handover_after > 1000) {
    *error = "warmup_handover_after must be in [0, 1000]";
    return false;
  }
  if (!(std::isfinite(warmup_l_step) && warmup_l_step >= 0.0)) {
    *error = "warmup_l_step must be >= 0";
    return false;
  }
  if (warmup_steps > 0 && !warmup.IsValid(error)) {
    *error = "warm-up rules: " + *error;
    return false;
  }
  if (!recovery.IsValid(error)) return false;
  if (!slope.IsValid(error)) return false;
  if (!velocity_control.IsValid(error)) return false;
  if (!stall_recovery.IsValid(error)) return false;
  if (!steps.IsValid(error)) return false;
  if (log_every < 0) {
    *error = "log_every must be >= 0";
    return false;
  }
  if (planner.enabled && !planner.IsValid(error)) return false;
  return true;
}

}  // namespace rabbit
