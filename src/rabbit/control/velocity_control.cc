#include "rabbit/control/velocity_control.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace rabbit {

const std::vector<VelocityControlRange>& VelocityControlRanges() {
  using P = VelocityControlParams;
  static const std::vector<VelocityControlRange> ranges = {
      {"v_d_rate", &P::v_d_rate, 0.0, 3.0, " m/s per step (0: no limit)"},
      {"feedforward_gain", &P::feedforward_gain, 0.0, 2.0, ""},
      {"feedforward_rise_extra", &P::feedforward_rise_extra, 0.0, 2.0, ""},
      {"gait_shift_gain", &P::gait_shift_gain, 0.0, 10.0, " m/s per rad"},
      {"gait_shift_max", &P::gait_shift_max, 0.0, 0.5, " m/s"},
      {"gait_shift_below", &P::gait_shift_below, 0.0, 3.0, " m/s"},
      {"v_d_rate_up", &P::v_d_rate_up, 0.0, 3.0, " m/s per step (0: v_d_rate)"},
      {"v_d_rate_down", &P::v_d_rate_down, 0.0, 3.0, " m/s per step (0: v_d_rate)"},
      {"v_d_rate_down_below", &P::v_d_rate_down_below, 0.0, 3.0, " m/s"},
      {"drop_min", &P::drop_min, 0.0, 3.0, " m/s"},
      {"drop_gap", &P::drop_gap, 0.0, 3.0, " m/s"},
      {"settled_start_clear", &P::settled_start_clear, 0.0, 100.0, " m"},
      {"settled_feedforward_gain", &P::settled_feedforward_gain, 0.0, 2.0, ""},
      {"settled_rise_extra", &P::settled_rise_extra, 0.0, 2.0, ""},
  };
  return ranges;
}

bool VelocityControlParams::IsValid(std::string* error) const {
  for (const VelocityControlRange& r : VelocityControlRanges()) {
    const double value = this->*r.field;
    if (!(std::isfinite(value) && value >= r.lo && value <= r.hi)) {
      char text[160];
      std::snprintf(text, sizeof text, "velocity_control.%s must be in [%g, %g]%s", r.key, r.lo,
                    r.hi, r.unit);
      *error = text;
      return false;
    }
  }
  for (const auto* points : {&pitch_map, &settled_pitch_map}) {
    for (const auto& [v, q] : *points) {
      if (!(std::isfinite(v) && std::isfinite(q) && v >= 0.0 && v < 3.0 &&
            std::abs(q) < M_PI / 4)) {
        *error = std::string("velocity_control.") +
                 (points == &pitch_map ? "pitch_map_deg" : "settled_pitch_map_deg") +
                 ": each point needs V in [0, 3) m/s and |q0_d| < 45 deg";
        return false;
      }
    }
  }
  if (!(drop_no_raise >= 0 && drop_no_raise <= 100)) {
    *error = "velocity_control.drop_no_raise must be in [0, 100] touchdowns";
    return false;
  }
  if (!(drop_floor_steps >= 0 && drop_floor_steps <= 100)) {
    *error = "velocity_control.drop_floor_steps must be in [0, 100] touchdowns";
    return false;
  }
  if (!(std::abs(drop_floor_margin) <= M_PI / 4)) {
    *error = "velocity_control.drop_floor_margin_deg must be in [-45, 45] deg";
    return false;
  }
  return step_map.IsValid(error);
}

std::vector<double> NonDecreasingFit(const std::vector<double>& y) {
  // Blocks of (mean, count), merged while a block's mean is below the one before.
  std::vector<std::pair<double, int>> blocks;
  for (double v : y) {
    blocks.push_back({v, 1});
    while (blocks.size() > 1 && blocks[blocks.size() - 2].first > blocks.back().first) {
      const auto last = blocks.back();
      blocks.pop_back();
      auto& prev = blocks.back();
      prev.first = (prev.first * prev.second + last.first * last.second) /
                   static_cast<double>(prev.second + last.second);
      prev.second += last.second;
    }
  }
  std::vector<double> fit;
  for (const auto& [mean, count] : blocks) fit.insert(fit.end(), count, mean);
  return fit;
}

PitchMap::PitchMap(std::vector<std::pair<double, double>> points) : points_(std::move(points)) {
  for (const auto& [v, q] : points_) {
    if (!std::isfinite(v) || !std::isfinite(q)) {
      throw std::invalid_argument("pitch map: a gait's speed or trunk pitch is not finite");
    }
  }
  std::sort(points_.begin(), points_.end());
  std::vector<double> y;
  for (const auto& point : points_) y.push_back(point.second);
  y = NonDecreasingFit(y);
  for (size_t i = 0; i < points_.size(); ++i) points_[i].second = y[i];
}

double PitchMap::At(double v) const {
  if (points_.empty()) return 0.0;
  if (v <= points_.front().first) return points_.front().second;
  for (size_t i = 1; i < points_.size(); ++i) {
    const auto& [v1, q1] = points_[i];
    if (v < v1) {
      const auto& [v0, q0] = points_[i - 1];
      return v1 > v0 ? q0 + (q1 - q0) * (v - v0) / (v1 - v0) : q1;
    }
  }
  return points_.back().second;
}

VelocityControl::VelocityControl(const VelocityControlParams& params, double k_p, double k_v,
                                 double q0_d_min, double q0_d_max, double q0_d_initial,
                                 PitchMap map)
    : p_(params),
      k_p_(k_p),
      k_v_(k_v),
      q0_d_min_(q0_d_min),
      q0_d_max_(q0_d_max),
      map_(std::move(map)),
      settled_map_(params.settled_pitch_map),
      step_map_(params.step_map),
      q0_d_(q0_d_initial) {
  std::string error;
  if (!p_.IsValid(&error)) throw std::invalid_argument(error);
}

double VelocityControl::Command(double v_d, double v_m, double v_profile) {
  // The command's own profile (v_d when not given): a drop starts only where it steps down.
  const double source = std::isfinite(v_profile) ? v_profile : v_d;
  const bool stepped_down = have_command_ && source < last_source_ - p_.drop_min;
  const bool stepped_up = have_command_ && source > last_source_;
  last_source_ = source;
  last_v_d_ = v_d;
  if (!p_.enabled || !have_command_) {
    v_c_ = v_d;
    have_command_ = true;
    return v_c_;
  }
  // A drop: from a touchdown where the profile stepped down by more than drop_min, with V_d below
  // V_c, until V_c has reached V_d (or V_d is no longer below it).
  if (v_d >= v_c_) {
    dropping_ = false;
  } else if (stepped_down) {
    dropping_ = true;
  }
  // A rise: from a touchdown where the profile stepped up, while V_c is below V_d and V_d is the
  // profile's own (no slope, obstacle or step command); its increases of V_c lean by
  // feedforward_rise_extra more, at v_d_rate_up.
  if (v_d <= v_c_ || v_d != source) {
    rising_ = false;
  } else if (stepped_up) {
    rising_ = true;
  }
  const double down = dropping_ && p_.v_d_rate_down > 0.0 && v_c_ <= p_.v_d_rate_down_below
                          ? p_.v_d_rate_down
                          : p_.v_d_rate;
  double next = v_d;
  const double up = rising_ && p_.v_d_rate_up > 0.0 ? p_.v_d_rate_up : p_.v_d_rate;
  if (p_.v_d_rate > 0.0) next = std::clamp(v_d, v_c_ - down, v_c_ + up);
  // In a drop V_c waits for the measured stride (drop_gap).
  if (dropping_ && next < v_c_ && p_.drop_gap > 0.0 && std::isfinite(v_m)) {
    next = std::min(v_c_, std::max(next, v_m - p_.drop_gap));
  }
  if (since_drop_ >= 0) ++since_drop_;
  if (dropping_ && next < v_c_) {
    since_drop_ = 0;
    drop_v_d_ = v_d;
  }
  const double ff_gain =
      p_.feedforward_gain + (rising_ && next > v_c_ ? p_.feedforward_rise_extra : 0.0);
  if (p_.settled_feedforward_gain > 0.0 && (rising_ || dropping_) &&
      !settled_map_.points().empty()) {
    // The profile's own rise or drop: toward the pitch the walker settles at (settled_pitch_map).
    const double gain =
        p_.settled_feedforward_gain + (rising_ && next > v_c_ ? p_.settled_rise_extra : 0.0);
    pending_ff_ += gain * (settled_map_.At(next) - settled_map_.At(v_c_));
  } else {
    pending_ff_ += ff_gain * (map_.At(next) - map_.At(v_c_));
  }
  v_c_ = next;
  return v_c_;
}

double VelocityControl::Update(double v_m, double t_step, double extra) {
  if (p_.law == VelocityLaw::kStepMap) {
    started_ = true;
    pending_ff_ = 0.0;
    q0_d_ = std::clamp(step_map_.Update(v_m, v_c_, q0_d_, q0_d_min_, q0_d_max_) + extra, q0_d_min_,
                       q0_d_max_);
    return q0_d_;
  }
  const double error = v_c_ - v_m;
  double dq0 = k_p_ * error + pending_ff_ + extra;
  pending_ff_ = 0.0;
  if (p_.enabled && p_.start_at_map && !started_) {
    started_ = true;
    const bool settled = use_start_map_ && !settled_map_.points().empty();
    q0_d_ = std::clamp((settled ? settled_map_ : map_).At(v_c_), q0_d_min_, q0_d_max_);
    last_error_ = error;
    last_v_m_ = v_m;
    have_error_ = true;
    return q0_d_;
  }
  started_ = true;
  // Enabled, the derivative acts on the measured speed only: the feed-forward answers a change of
  // the command, which would otherwise also kick the derivative term.
  if (have_error_) {
    dq0 += k_v_ * (p_.enabled ? last_v_m_ - v_m : error - last_error_) / t_step;
  }
  // After a decrease of V_c, the law may lower q0_d but not raise it (drop_no_raise).
  if (since_drop_ >= 0 && since_drop_ < p_.drop_no_raise) dq0 = std::min(dq0, 0.0);
  if (p_.gait_shift_gain > 0.0) {
    // Split range: the effort below the q0_d floor shifts the gait pattern (FisOffset); an idle
    // shift without windup neither stores nor keeps any.
    const bool idle = shift_idle_ && !p_.idle_shift_windup;
    if (idle) excess_ = 0.0;
    const double reach =
        v_c_ < p_.gait_shift_below && !idle ? p_.gait_shift_max / p_.gait_shift_gain : 0.0;
    const double u = std::clamp(q0_d_ + excess_ + dq0, q0_d_min_ - reach, q0_d_max_);
    q0_d_ = std::clamp(u, q0_d_min_, q0_d_max_);
    excess_ = u - q0_d_;
  } else {
    q0_d_ = std::clamp(q0_d_ + dq0, q0_d_min_, q0_d_max_);
  }
  // The drop's pitch floor: no lean back past the pitch of the speed the drop comes down to (a
  // higher command since, a rise or an obstacle's approach speed, does not raise it).
  if (p_.drop_floor_steps > 0 && since_drop_ >= 0 &&
      (dropping_ || since_drop_ < p_.drop_floor_steps)) {
    const PitchMap& map = settled_map_.points().empty() ? map_ : settled_map_;
    const double v = std::min(last_v_d_, drop_v_d_);
    const double floor = std::min(map.At(v) - p_.drop_floor_margin, q0_d_max_);
    if (!map.points().empty() && q0_d_ < floor) {
      q0_d_ = floor;
      excess_ = 0.0;
    }
  }
  last_error_ = error;
  last_v_m_ = v_m;
  have_error_ = true;
  return q0_d_;
}

}  // namespace rabbit
