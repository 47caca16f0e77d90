#include "rabbit/scenario/stall_watch.h"

#include <cstdio>

namespace rabbit {

StallWatch::StallWatch(Controller* inner, const StallCriteria& criteria)
    : inner_(inner), criteria_(criteria) {}

bool StallWatch::CheckStall(const Observation& obs, std::string* reason) {
  if (inner_->CheckStall(obs, reason)) return true;
  if (!started_) {
    started_ = true;
    last_touchdown_ = obs.t;
  }
  if (meter_.Update(obs)) last_touchdown_ = obs.t;
  char text[128];
  // A small margin keeps a limit that is a whole number of control periods from firing one
  // period early through rounding of t.
  constexpr double kSlack = 1e-9;
  if (criteria_.no_touchdown > 0.0 && obs.t - last_touchdown_ > criteria_.no_touchdown + kSlack) {
    std::snprintf(text, sizeof text, "no touchdown for %.3g s (stall_no_touchdown_s)",
                  criteria_.no_touchdown);
    *reason = text;
    return true;
  }
  if (criteria_.window > 0.0 && criteria_.min_advance > 0.0) {
    hip_.emplace_back(obs.t, obs.q[kX]);
    // Keep the oldest sample at least `window` old: the advance is over the whole window.
    while (hip_.size() >= 2 && obs.t - hip_[1].first >= criteria_.window - kSlack) {
      hip_.pop_front();
    }
    if (obs.t - hip_.front().first >= criteria_.window - kSlack) {
      const double advance = obs.q[kX] - hip_.front().second;
      if (advance < criteria_.min_advance) {
        std::snprintf(text, sizeof text,
                      "hip advanced %.4f m in %.3g s (at least %.3g m: stall_window_s, "
                      "stall_min_advance_m)",
                      advance, criteria_.window, criteria_.min_advance);
        *reason = text;
        return true;
      }
    }
  }
  return false;
}

}  // namespace rabbit
