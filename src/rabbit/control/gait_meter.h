// Gait measurement from the binary contact sensors: touchdown and take-off of each foot, and per
// step L_step (horizontal distance between the feet at touchdown, signed: the landing foot's x
// minus the other foot's, negative when it lands behind the other), t_step (take-off to landing
// of the same leg) and V_M = L_step / t_step (chapter eq. 1; negative for a step backward).
#ifndef RABBIT_CONTROL_GAIT_METER_H_
#define RABBIT_CONTROL_GAIT_METER_H_

#include <array>
#include <vector>

#include "rabbit/sim/controller.h"

namespace rabbit {

struct StepRecord {
  int index = 0;           // 0, 1, 2, ... in time order
  int leg = 0;             // the leg that landed
  double t_touchdown = 0;  // s
  double l_step = 0;       // m, signed: < 0 when the foot landed behind the other
  double t_step = 0;       // s (0 when that leg's take-off was not seen)
  double v_m = 0;          // m/s, signed as l_step (0 when t_step is 0)
  double x = 0;            // m, where the landing foot touched down
  double y = 0;            // m, its height there (unloaded: the contact has not sunk it yet)
};

class GaitMeter {
 public:
  // Feeds one observation; returns true when a foot touched down at this sample (then
  // last_step() describes it). A touchdown counts only after the foot was off the ground for at
  // least min_air_time (so that contact flicker at lift-off is not a step).
  bool Update(const Observation& obs);
  const std::vector<StepRecord>& steps() const { return steps_; }
  const StepRecord& last_step() const { return steps_.back(); }
  // The latest touchdown of `leg`, or null before its first.
  const StepRecord* LastLanding(int leg) const;
  bool in_contact(int leg) const { return contact_[leg]; }
  double takeoff_time(int leg) const { return takeoff_[leg]; }
  double min_air_time = 0.05;  // s

 private:
  std::array<bool, kNumLegs> contact_{};
  std::array<bool, kNumLegs> seen_{};
  std::array<double, kNumLegs> takeoff_{-1.0, -1.0};    // last take-off seen (-1: none)
  std::array<double, kNumLegs> air_since_{-1.0, -1.0};  // in the air since (first sample too)
  std::vector<StepRecord> steps_;
};

}  // namespace rabbit

#endif  // RABBIT_CONTROL_GAIT_METER_H_
