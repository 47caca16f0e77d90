// A push on the approach to an obstacle (beyond the chapter; key planner.push_dead,
// docs/design/step-planner.md "The step planner"). The step planner corrects the step-length fuzzy
// system's input by a bias fed from each planned step's length error (step_planner.h): the realised
// step of a blend differs from the gaits' own. A push on the approach makes a step short or long
// for reasons the blend has nothing to do with, and the bias it feeds asks for the opposite error
// of the next steps, once the walk has settled (a backward push's short step asked for long steps
// that landed the last approach foot at the obstacle's edge).
//
// The watch measures the disturbance step to step: d = v_orb - v_ref(s), the pendulum's hip
// speed (push_recovery.h) less its mean at the same phase s of the same leg's last undisturbed
// step (s over the leg's first step's duration, the phase bins of step_phase_bins.h, s in [0.2, 1)
// compared, each bin when complete). A step with |d| > push_dead in a bin is disturbed: it is
// not its leg's reference (unless more than kMaxDisturbed of the leg's steps in a row were: a new
// gait), and the walker keeps it out of the planner's bias. The push response's own reference
// needs three touchdowns with one command on level ground (push_response.h), which the
// approach speed has just changed when an obstacle comes near; here a change of command, or a
// touchdown off level ground, only leaves the kSettleSteps steps from it unjudged, taken as the
// references. push_dead = 0 (the default): off.
#ifndef RABBIT_CONTROL_APPROACH_WATCH_H_
#define RABBIT_CONTROL_APPROACH_WATCH_H_

#include <array>

#include "rabbit/control/step_phase_bins.h"

namespace rabbit {

class ApproachWatch {
 public:
  explicit ApproachWatch(double dead) : dead_(dead) {}

  bool enabled() const { return dead_ > 0.0; }
  // Every control period: v_orb, and whether the steps are the walker's own (false in the
  // warm-up, the step over and the steps after it): a change of it forgets the references.
  void Observe(double t, double v_orb, bool own);
  // At each support exchange (t_step: the finished step's duration, 0 if unknown).
  void OnTouchdown(double t, double t_step);
  // After OnTouchdown, the speed command for the coming step and whether the ground is level:
  // a change of command or of grade moves v_orb as a push does.
  void Command(double v_c, bool level);
  // The step that ended at the last touchdown: disturbed, and its d of largest magnitude.
  bool last_disturbed() const { return last_disturbed_; }
  double last_d() const { return last_d_; }

  static constexpr int kPhaseBins = StepPhaseBins::kBins;
  static constexpr int kFirstBin = 2, kLastBin = 9;
  static constexpr int kMaxDisturbed = 2;
  static constexpr int kSettleSteps = 4;  // two steps of each leg

 private:
  double Phase(double t) const;  // the step's phase on its leg's timebase (-1: none)

  double dead_;
  std::array<std::array<double, kPhaseBins>, 2> ref_{};
  std::array<std::array<bool, kPhaseBins>, 2> has_ref_{};
  std::array<double, 2> t_ref_{};   // the legs' timebases (their first steps' durations; 0: none)
  std::array<int, 2> disturbed_{};  // the leg's disturbed steps in a row
  StepPhaseBins bins_;              // the current step's v_orb
  int leg_ = 0;
  double t_touchdown_ = -1.0;
  bool own_ = false;
  double extreme_ = 0.0;  // this step's d of largest magnitude beyond the dead zone
  bool disturbed_step_ = false;
  bool last_disturbed_ = false;
  double last_d_ = 0.0;
  double v_c_ = -1.0;
  int unjudged_ = 0;  // steps still to take as references unjudged (a change of command)
};

}  // namespace rabbit

#endif  // RABBIT_CONTROL_APPROACH_WATCH_H_
