#include "rabbit/sim/push_schedule.h"

#include <cmath>
#include <limits>

namespace rabbit {

PushSchedule::PushSchedule(const std::vector<TrunkPush>* pushes) : pushes_(pushes) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const TrunkPush& p : *pushes_) {
    start_.push_back(p.event_timed() ? nan : p.start);
    counted_from_.push_back(std::isnan(p.at_hip_x) ? 0 : -1);
  }
}

void PushSchedule::Update(double t, double hip_x, const std::array<bool, kNumLegs>& contact) {
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const bool now = contact[leg];
    if (!seen_[leg]) {
      seen_[leg] = true;
      contact_[leg] = now;
      if (!now) air_since_[leg] = t;
      continue;
    }
    if (contact_[leg] && !now) air_since_[leg] = t;
    if (!contact_[leg] && now && air_since_[leg] >= 0.0 && t - air_since_[leg] >= kMinAirTime) {
      touchdown_t_.push_back(t);
    }
    contact_[leg] = now;
  }
  const int n = touchdowns();
  for (size_t i = 0; i < start_.size(); ++i) {
    if (!std::isnan(start_[i])) continue;
    const TrunkPush& p = (*pushes_)[i];
    if (counted_from_[i] < 0) {
      if (hip_x < p.at_hip_x) continue;
      counted_from_[i] = n;
      if (p.after_touchdown == 0) {
        start_[i] = t;
        continue;
      }
    }
    const int k = counted_from_[i] + p.after_touchdown;  // the touchdown it waits for, 1-based
    if (n < k) continue;
    const double at = touchdown_t_[k - 1];
    const double before = k >= 2 ? touchdown_t_[k - 2] : 0.0;
    start_[i] = at + p.phase * (at - before);
  }
}

bool PushSchedule::Active(size_t i, double t) const {
  const double start = start_[i];
  if (std::isnan(start)) return false;
  return t >= start - 1e-12 && t < start + (*pushes_)[i].duration - 1e-12;
}

}  // namespace rabbit
