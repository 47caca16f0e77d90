#include "rabbit/control/step_planner.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <utility>

namespace rabbit {

bool StepPlannerParams::IsValid(std::string* error) const {
  const std::pair<const char*, double> lengths[] = {{"horizon", horizon},
                                                    {"margin_before", margin_before},
                                                    {"margin_after", margin_after},
                                                    {"l_min", l_min},
                                                    {"l_max", l_max},
                                                    {"l_nominal", l_nominal},
                                                    {"l_over_max", l_over_max},
                                                    {"l_over_min", l_over_min},
                                                    {"bias_max", bias_max},
                                                    {"assumed_length", assumed_length},
                                                    {"over_lift_trail", over_lift_trail},
                                                    {"over_lift_release", over_lift_release},
                                                    {"hold_margin", hold_margin},
                                                    {"follow_shorten", follow_shorten},
                                                    {"follow_lengthen", follow_lengthen}};
  for (const auto& [name, value] : lengths) {
    if (!(std::isfinite(value) && value >= 0.0 && value <= 10.0)) {
      *error = std::string("planner.") + name + " must be in [0, 10] m";
      return false;
    }
  }
  if (!(std::isfinite(approach_speed) && approach_speed >= 0.0 && approach_speed <= 2.0)) {
    *error = "planner.approach_speed must be in [0, 2] m/s";
    return false;
  }
  if (!(std::isfinite(push_dead) && push_dead >= 0.0 && push_dead <= 2.0)) {
    *error = "planner.push_dead must be in [0, 2] m/s";
    return false;
  }
  if (!(std::isfinite(approach_distance) && approach_distance >= 0.0 &&
        approach_distance <= 100.0)) {
    *error = "planner.approach_distance must be in [0, 100] m";
    return false;
  }
  if (!(std::isfinite(end_warmup_within) && end_warmup_within >= 0.0 &&
        end_warmup_within <= 100.0)) {
    *error = "planner.end_warmup_within must be in [0, 100] m";
    return false;
  }
  if (!(l_min > 0.0 && l_min < l_max)) {
    *error = "planner: need 0 < l_min < l_max";
    return false;
  }
  if (!(l_nominal >= l_min && l_nominal <= l_max)) {
    *error = "planner.l_nominal must lie in [l_min, l_max]";
    return false;
  }
  if (!(l_over_max >= l_min)) {
    *error = "planner.l_over_max must be >= l_min";
    return false;
  }
  if (!(l_over_min <= l_over_max)) {
    *error = "planner.l_over_min must be <= l_over_max";
    return false;
  }
  if (!(std::isfinite(feedback_gain) && feedback_gain >= 0.0 && feedback_gain <= 1.0)) {
    *error = "planner.feedback_gain must be in [0, 1]";
    return false;
  }
  if (!(std::isfinite(bias_initial) && std::abs(bias_initial) <= bias_max)) {
    *error = "planner.bias_initial must be within +-bias_max";
    return false;
  }
  if (recovery_steps < 0 || recovery_steps > 100) {
    *error = "planner.recovery_steps must be in [0, 100]";
    return false;
  }
  if (hold_pitch_steps < 0 || hold_pitch_steps > 100) {
    *error = "planner.hold_pitch_steps must be in [0, 100]";
    return false;
  }
  if (!(std::isfinite(stretch) && stretch > 0.0 && stretch <= 10.0)) {
    *error = "planner.stretch must be in (0, 10]";
    return false;
  }
  return true;
}

StepPlannerParams FollowGait(const StepPlannerParams& p, double l_gait) {
  if (!p.follow_gait || !std::isfinite(l_gait)) return p;
  StepPlannerParams f = p;
  const double g = std::clamp(l_gait, p.l_min, p.l_over_max);
  f.l_nominal = g;
  f.l_min = std::max(p.l_min, g - p.follow_shorten);
  f.l_max = std::min(p.l_over_max, g + p.follow_lengthen);
  // A zero-width range (both spreads 0, or l_gait at a bound): the plan still needs l_min < l_max.
  if (!(f.l_max > f.l_min)) f.l_max = f.l_min + 1e-6;
  return f;
}

double ApproachSpeed(const StepPlannerParams& p, const std::vector<Obstacle>& obstacles,
                     double back_x, double front_x, double v_d) {
  if (!(p.approach_speed > v_d)) return v_d;
  for (const Obstacle& o : obstacles) {
    if (o.x_start <= front_x + p.approach_distance && o.x_end() > back_x) return p.approach_speed;
  }
  return v_d;
}

StepPlan PlanStep(const StepPlannerParams& p, double d_obs, double obstacle_length) {
  StepPlan plan;
  if (!(d_obs <= p.horizon) || !std::isfinite(d_obs)) return plan;
  plan.active = true;
  const double length = p.use_length ? obstacle_length : p.assumed_length;
  const double over = std::clamp(d_obs + length + p.margin_after,
                                 std::min(p.l_over_min, p.l_over_max), p.l_over_max);
  const double rest = d_obs - p.margin_before;  // to the last foot's target
  if (rest < p.l_min) {
    // No full approach step fits: step over now if it clears the far edge, else creep closer.
    if (rest <= 0.0 || d_obs + length + p.margin_after <= p.l_over_max) {
      plan.approach_steps = 0;
      plan.step_length = over;
    } else {
      plan.approach_steps = 1;
      plan.step_length = rest;
    }
    return plan;
  }
  // The count whose step is nearest [l_min, l_max], then nearest l_nominal.
  const int n_max = static_cast<int>(std::ceil(rest / p.l_min)) + 1;
  double best_violation = INFINITY, best_off = INFINITY;
  for (int n = 1; n <= n_max; ++n) {
    const double l = rest / n;
    const double violation = std::max({p.l_min - l, l - p.l_max, 0.0});
    const double off = std::abs(l - p.l_nominal);
    if (violation < best_violation - 1e-12 ||
        (std::abs(violation - best_violation) <= 1e-12 && off < best_off)) {
      best_violation = violation;
      best_off = off;
      plan.approach_steps = n;
      plan.step_length = l;
    }
  }
  return plan;
}

TsFis StepLengthFis(const std::vector<double>& gait_l_steps) {
  const size_t n = gait_l_steps.size();
  if (n < 2) throw std::invalid_argument("the step-length fuzzy system needs two gaits or more");
  for (double l : gait_l_steps) {
    if (!(std::isfinite(l) && l > 0.0)) {
      throw std::invalid_argument("gait step lengths must be finite and > 0");
    }
  }
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return gait_l_steps[a] < gait_l_steps[b]; });
  std::vector<double> c(n);
  for (size_t i = 0; i < n; ++i) c[i] = gait_l_steps[order[i]];
  for (size_t i = 1; i < n; ++i) {
    if (!(c[i] > c[i - 1])) throw std::invalid_argument("gait step lengths must be distinct");
  }
  TsFis fis;
  fis.name = "step_length";
  FuzzyInput input;
  input.name = "L_step";
  input.min = 0.0;
  input.max = std::max(1.0, 1.5 * c.back());
  for (size_t i = 0; i < n; ++i) {
    FuzzySet set;
    set.name = "L" + std::to_string(i + 1);
    Membership& m = set.membership;
    if (i == 0) {
      m.shape = Membership::Shape::kRampDown;
      m.a = c[0];
      m.b = c[1];
    } else if (i + 1 == n) {
      m.shape = Membership::Shape::kRampUp;
      m.a = c[n - 2];
      m.b = c[n - 1];
    } else {
      m.shape = Membership::Shape::kTriangle;
      m.a = c[i - 1];
      m.b = c[i];
      m.c = c[i + 1];
    }
    input.sets.push_back(set);
  }
  fis.inputs.push_back(std::move(input));
  fis.output_name = "gait";
  for (size_t k = 0; k < n; ++k) {
    fis.output_terms.push_back("O" + std::to_string(k + 1));
    fis.output_values.push_back(static_cast<double>(k + 1));
  }
  fis.output_min = 1.0;
  fis.output_max = static_cast<double>(n);
  fis.default_value = std::nan("");
  for (size_t i = 0; i < n; ++i)
    fis.rules.push_back({{static_cast<int>(i)}, static_cast<int>(order[i])});
  return fis;
}

std::vector<double> StepLengthWeights(const TsFis& fis, double l) {
  TsFis::Result result;
  fis.Evaluate({l}, &result);
  std::vector<double> weights(fis.output_values.size(), 0.0);
  if (!result.fired) return weights;
  for (size_t r = 0; r < fis.rules.size(); ++r) {
    weights[static_cast<size_t>(fis.output_values[fis.rules[r].consequent]) - 1] +=
        result.activation[r];
  }
  return weights;
}

}  // namespace rabbit
