#include "rabbit/control/rule_gait_choice.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace rabbit {

double ChooseRuleGait(double v, const std::vector<double>& speeds,
                      const std::vector<double>& rule_share, double mixed_below,
                      double mixed_point) {
  if (!std::isfinite(v) || speeds.size() != rule_share.size() || speeds.size() < 2) return v;
  std::vector<std::pair<double, bool>> gaits;  // (speed, rule-walked), sorted by speed
  for (size_t k = 0; k < speeds.size(); ++k) gaits.push_back({speeds[k], rule_share[k] >= 0.5});
  std::sort(gaits.begin(), gaits.end());
  for (size_t k = 1; k < gaits.size(); ++k) {
    const auto& [lo, lo_ruled] = gaits[k - 1];
    const auto& [hi, hi_ruled] = gaits[k];
    if (v > lo && v < hi) {
      if (lo_ruled && hi_ruled) return v - lo < hi - v ? lo : hi;
      if ((lo_ruled || hi_ruled) && hi < mixed_below) {
        return v < lo + mixed_point * (hi - lo) ? lo : hi;
      }
      return v;
    }
  }
  return v;
}

RuleGaitChoice::RuleGaitChoice(bool enabled,
                               const std::vector<std::pair<double, double>>& gait_pitches,
                               std::vector<double> rule_share, double mixed_below,
                               double mixed_point, double hold_rate)
    : enabled_(enabled),
      mixed_below_(mixed_below),
      mixed_point_(mixed_point),
      hold_rate_(hold_rate),
      rule_share_(std::move(rule_share)) {
  for (const auto& [v, q0] : gait_pitches) speeds_.push_back(v);
  if (enabled_ && !rule_share_.empty() && speeds_.size() != rule_share_.size()) {
    throw std::invalid_argument("walker: rule_gait_choice needs the speed of each reference gait");
  }
}

void RuleGaitChoice::OnCommand(double v_c) {
  holding_ = have_command_ && std::abs(v_c - last_command_) <= hold_rate_;  // 0: unchanged only
  have_command_ = true;
  last_command_ = v_c;
}

}  // namespace rabbit
