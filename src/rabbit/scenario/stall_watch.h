// The stall watch of walking scenarios (docs/outcomes.md): it wraps the controller of a run and
// ends the run with the outcome `stalled` when the robot stops walking:
//   no touchdown   no foot has touched down (the gait meter's touchdowns: a landing after at least
//                  its min_air_time in the air) for `no_touchdown` seconds, counted from the start
//                  of the run or the last touchdown;
//   no advance     the hip has advanced (signed, forward = +x) less than `min_advance` over the
//                  last `window` seconds (checked once the run is `window` long).
// A setting of 0 turns its check off. Without stalls the watch changes nothing: it passes every
// observation to the wrapped controller and returns its torques.
#ifndef RABBIT_SCENARIO_STALL_WATCH_H_
#define RABBIT_SCENARIO_STALL_WATCH_H_

#include <deque>
#include <string>
#include <utility>

#include "rabbit/control/gait_meter.h"
#include "rabbit/sim/controller.h"

namespace rabbit {

// Keys of a scenario's [criteria] table: stall_no_touchdown_s, stall_window_s,
// stall_min_advance_m.
struct StallCriteria {
  double no_touchdown = 2.0;  // s without a touchdown (0: unchecked)
  double window = 3.0;        // s over which the hip must advance min_advance (0: unchecked)
  double min_advance = 0.1;   // m (0: unchecked)
  bool enabled() const { return no_touchdown > 0.0 || (window > 0.0 && min_advance > 0.0); }
};

class StallWatch final : public Controller {
 public:
  // `inner` must outlive the watch.
  StallWatch(Controller* inner, const StallCriteria& criteria);
  Vec4 Compute(const Observation& obs) override { return inner_->Compute(obs); }
  bool CheckStall(const Observation& obs, std::string* reason) override;

 private:
  Controller* inner_;
  StallCriteria criteria_;
  GaitMeter meter_;
  double last_touchdown_ = 0.0;  // s (the start of the run before the first touchdown)
  bool started_ = false;
  std::deque<std::pair<double, double>> hip_;  // (t, hip x) over the last window
};

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_STALL_WATCH_H_
