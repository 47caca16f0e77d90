// When the trunk pushes of a run act (rabbit/sim/simulator.h, TrunkPush): at a fixed time, or
// after an event seen at the control samples (a touchdown, the hip passing a point).
#ifndef RABBIT_SIM_PUSH_SCHEDULE_H_
#define RABBIT_SIM_PUSH_SCHEDULE_H_

#include <array>
#include <vector>

#include "rabbit/sim/simulator.h"

namespace rabbit {

class PushSchedule {
 public:
  explicit PushSchedule(const std::vector<TrunkPush>* pushes);
  // Feeds the control sample at time t (samples in increasing time): the hip's x and the binary
  // contact sensors (Fn > 0). Touchdowns count as in the gait meter (GaitMeter: a foot landing
  // after at least kMinAirTime in the air; a foot in the air at the first sample counts when it
  // lands).
  void Update(double t, double hip_x, const std::array<bool, kNumLegs>& contact);
  // Whether push i acts on the sample at t (start <= t < start + duration).
  bool Active(size_t i, double t) const;
  // Push i's start (s), nan while its event has not come.
  double start(size_t i) const { return start_[i]; }
  const std::vector<double>& starts() const { return start_; }
  int touchdowns() const { return static_cast<int>(touchdown_t_.size()); }

  // s: the gait meter's default min_air_time; touchdowns are counted as steps.csv counts them
  // while the meter keeps that default.
  static constexpr double kMinAirTime = 0.05;

 private:
  const std::vector<TrunkPush>* pushes_;
  std::vector<double> start_;
  std::vector<int> counted_from_;  // touchdowns before the hip passed at_hip_x (-1: not yet)
  std::array<bool, kNumLegs> contact_{}, seen_{};
  std::array<double, kNumLegs> air_since_{-1.0, -1.0};
  std::vector<double> touchdown_t_;
};

}  // namespace rabbit

#endif  // RABBIT_SIM_PUSH_SCHEDULE_H_
