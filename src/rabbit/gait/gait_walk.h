// Walking with the pragmatic rules: one run from the documented start, its gait metrics, and the
// swing-leg trajectories it produces as functions of e = q_st1 (docs/design/gait-pattern.md).
#ifndef RABBIT_GAIT_GAIT_WALK_H_
#define RABBIT_GAIT_GAIT_WALK_H_

#include <array>
#include <string>
#include <vector>

#include "rabbit/control/pragmatic_rules.h"
#include "rabbit/sim/simulator.h"

namespace rabbit {

// Everything that defines a reference gait: the rule parameters and how the walk starts.
struct GaitSpec {
  PragmaticParams rules;
  double start_speed = 0.6;  // m/s, hip speed of the initial push (WalkingStartState)
  double start_angle = 0.0;  // rad, stance thigh at the start (0: mid-stance)
  bool IsValid(std::string* error) const;
};

// Steady-state figures over the last `window` steps of a walk.
struct GaitMetrics {
  int steps = 0;                 // steps taken before the run ended (or a non-step was seen)
  bool fell = false;             // the run ended early (fall, trip, divergence)
  double walked_time = 0.0;      // s, until the run ended
  std::string reason;            // why it ended early
  double v_m = 0.0;              // mean V_M over the window, m/s
  double l_step = 0.0;           // mean L_step, m
  double t_step = 0.0;           // mean t_step, s
  double l_step_spread = 0.0;    // max - min L_step over the window, m
  double v_m_spread = 0.0;       // max - min V_M over the window, m/s
  double saturation_time = 0.0;  // s, summed over the joints, whole run
};

struct GaitRun {
  SimResult sim;
  std::vector<StepRecord> steps;
  GaitMetrics metrics;
};

// Walks the spec from its start for `duration` seconds on flat ground (setup.terrain and
// setup.options.duration are overridden), and measures the last `window` steps.
GaitRun WalkGait(const SimSetup& setup, const GaitSpec& spec, double duration, int window);

// One sample of a swing-leg trajectory.
struct SwingSample {
  double e = 0.0;               // stance hip angle q_st1, rad
  double q1 = 0.0, q2 = 0.0;    // swing hip and knee, rad
  double qd1 = 0.0, qd2 = 0.0;  // their rates, rad/s
};

// The swing-leg trajectory of the last `window` steps of a run, averaged: each step's swing
// (between two touchdowns) is resampled at `bins` values of e spanning the range all of those
// swings cover, and the steps are averaged. Returned sorted by e (ascending). Needs the run's
// samples at every control period.
std::vector<SwingSample> AverageSwingTrajectory(const GaitRun& run, int window, int bins);

// A swing trajectory as training data: the inputs e and the four outputs q1, q2, qd1, qd2.
void SplitSwing(const std::vector<SwingSample>& swing, std::vector<double>* e,
                std::array<std::vector<double>, 4>* outputs);

}  // namespace rabbit

#endif  // RABBIT_GAIT_GAIT_WALK_H_
