#include "rabbit/control/gait_meter.h"

namespace rabbit {

bool GaitMeter::Update(const Observation& obs) {
  bool landed = false;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const bool now = obs.foot_contact[leg];
    if (!seen_[leg]) {
      // A foot already in the air at the first sample: its take-off was not seen, but its
      // landing is still a step (with t_step = 0).
      seen_[leg] = true;
      contact_[leg] = now;
      if (!now) air_since_[leg] = obs.t;
      continue;
    }
    if (contact_[leg] && !now) takeoff_[leg] = air_since_[leg] = obs.t;
    if (!contact_[leg] && now && air_since_[leg] >= 0.0 &&
        obs.t - air_since_[leg] >= min_air_time) {
      StepRecord step;
      step.index = static_cast<int>(steps_.size());
      step.leg = leg;
      step.t_touchdown = obs.t;
      step.x = obs.foot_pos[leg].x();
      step.y = obs.foot_pos[leg].y();
      step.l_step = obs.foot_pos[leg].x() - obs.foot_pos[1 - leg].x();  // < 0: landed behind
      step.t_step = takeoff_[leg] >= 0.0 ? obs.t - takeoff_[leg] : 0.0;
      step.v_m = step.t_step > 0.0 ? step.l_step / step.t_step : 0.0;
      steps_.push_back(step);
      landed = true;
    }
    contact_[leg] = now;
  }
  return landed;
}

const StepRecord* GaitMeter::LastLanding(int leg) const {
  for (auto it = steps_.rbegin(); it != steps_.rend(); ++it) {
    if (it->leg == leg) return &*it;
  }
  return nullptr;
}

}  // namespace rabbit
