// Multi-step foot placement for stepping over an obstacle (beyond the chapter;
// docs/design/step-planner.md, "The step planner").
//
// At each touchdown with an obstacle's near edge within `horizon` of the front foot (d_obs), the
// planner chooses the number n >= 0 of approach steps still to take before the step over and
// their common length L_a so that the last foot before the obstacle lands `margin_before` short of
// its near edge:
//   n L_a = d_obs - margin_before,  L_a in [l_min, l_max],  n the count whose L_a is nearest
//   l_nominal (the gait's own step) among those that fit;
// then the step over (n = 0) from that foot is L_over = d_obs + length + margin_after, landing
// margin_after past the far edge (clamped to [l_over_min, l_over_max]). When no n fits (d_obs -
// margin_before below l_min but not below zero), the step over is taken at once if it can reach
// past the far edge, else the shortest approach step. The plan is recomputed at every touchdown
// (receding horizon), so a step that fell short or long is corrected by the next ones.
//
// A target step length is realised by a second zero-order TS fuzzy system (StepLengthFis) whose
// input is the desired step length, with N_r triangles centred on the reference gaits' step
// lengths (shoulders at both ends, a Ruspini partition): its rule weights are a linear
// interpolation between the two gaits whose L_step bracket the target. The realised step of a
// blend differs from the gaits' own (momentum, the velocity control's pitch), so the fuzzy
// system's input is corrected by the step-length error fed back from the previous planned steps.
#ifndef RABBIT_CONTROL_STEP_PLANNER_H_
#define RABBIT_CONTROL_STEP_PLANNER_H_

#include <string>
#include <vector>

#include "rabbit/contact/terrain.h"
#include "rabbit/learn/ts_fis.h"

namespace rabbit {

struct StepPlannerParams {
  // false: the walker as the chapter's (Table 3 alone). The scenario key `enabled` defaults to
  // the preset's (walker_presets.cc: on in `adaptive`, off in `chapter`); a WalkerParams built in
  // code starts without it.
  bool enabled = false;
  double horizon = 1.5;  // m: d_obs within which the planner takes over the step length
  // Blend only the gaits the walker tracks (rule share below 1/2; all when there is no rule
  // share). Off by default: on the training families it changed nothing for one obstacle and cost
  // obstacle rows (docs/design/step-planner.md, "The step planner").
  bool tracked_gaits_only = false;
  double margin_before = 0.06;  // m: the last foot's distance short of the near edge
  double margin_after = 0.05;   // m: the step over lands this far past the far edge
  // Steps asked for: the range the walker realises at 0.6 m/s (the vm_0.40 gait's weights give
  // about 0.31 m, vm_0.80's about 0.49 m).
  double l_min = 0.31;       // m: shortest approach step asked for
  double l_max = 0.45;       // m: longest approach step asked for
  double l_nominal = 0.36;   // m: preferred approach step (the 0.6 m/s walk's)
  double l_over_max = 0.50;  // m: longest step over asked for
  // m: shortest step over asked for (0: as short as the obstacle and margins make it). A step over
  // from a foot close to a short obstacle is otherwise asked for at 0.15-0.25 m, shorter than
  // any approach step: the swing foot lands on the obstacle's far side just past its edge, or the
  // trailing foot strikes it. Faces of terrain steps (planned for as obstacles) leave it out.
  double l_over_min = 0.0;
  // Step-length feedback: the fuzzy system's input is
  //   l_nominal + stretch (L_target - l_nominal) - bias,
  // bias starting at bias_initial (the walker's realised step exceeds the database L_step of the
  // same blend by about 6 cm at 0.6 m/s: the vm_0.40 gait's weights give 0.31 m, not 0.24 m) and
  // bias += feedback_gain (L_measured - L_target) after each planned step, within +-bias_max.
  double feedback_gain = 0.5;
  double bias_initial = 0.08;  // m
  double bias_max = 0.15;      // m
  double stretch = 1.0;
  // Steps after the step over that still go through the planner at l_nominal (0: Table 3 at once).
  int recovery_steps = 2;
  // The foot lift while planning: it holds the foot up to over_lift_trail past the far edge and
  // lowers it over over_lift_release (the walker's lift_trail and lift_release without the
  // planner: 0.04 and 0.10 m, which land the step over about 0.15 m past the edge, too far to
  // walk on from). hold_margin: a swing foot still below the obstacle's top and behind its near
  // edge is kept this far behind the edge (its forward progress held) until it has risen, so the
  // trailing foot that starts close to the edge goes up before it goes forward (0: off).
  double over_lift_trail = 0.0;     // m
  double over_lift_release = 0.05;  // m
  double hold_margin = 0.03;        // m
  bool use_length = true;           // perceive the obstacle's length (else assume `assumed_length`)
  double assumed_length = 0.30;     // m
  // Follow the gait (off: the fixed l_nominal, l_min, l_max above, chosen at 0.6 m/s). At the
  // touchdown where an obstacle enters the horizon the planner takes the mean of the walker's
  // last two measured steps as its nominal step L_g and asks for approach steps in
  //   [max(l_min, L_g - follow_shorten), min(l_over_max, L_g + follow_lengthen)],
  // preferring L_g (FollowGait below). The step-length system's input is then
  //   L_db + stretch (L_target - L_g) - bias,
  // L_db the database step length of the gait weights the walker had at that touchdown (the
  // gait it walks), the bias starting at 0 for each obstacle (the offset between realised and
  // database steps is in L_g - L_db already).
  // After the step over: over_feedback false keeps the step over's and the recovery steps' length
  // errors out of the bias (the foot lift, not the blend, sets the step over's length), and the
  // velocity control leaves q0_d as it is at the touchdowns that end the step over and the
  // hold_pitch_steps - 1 steps after it (the long step over's V_M is no measure of the gait's
  // speed: it would lean the trunk back into a short step or a backward one; 0: off).
  bool over_feedback = true;
  int hold_pitch_steps = 0;
  bool follow_gait = false;
  double follow_shorten = 0.06;   // m
  double follow_lengthen = 0.04;  // m
  // Approach speed: while an obstacle is near (its near edge within approach_distance ahead of
  // the front foot, its far edge still ahead of the back foot) the walker's speed command is at
  // least approach_speed, the speed whose steps the lengths above are (0: off; ApproachSpeed).
  double approach_speed = 0.0;     // m/s
  double approach_distance = 2.5;  // m
  // A push on the approach (approach_watch.h): a step whose pendulum speed v_orb leaves the same
  // leg's last undisturbed step's by more than push_dead (m/s) in a phase bin was disturbed, and
  // its length error does not feed the bias above (0: off, every planned step feeds it).
  double push_dead = 0.0;  // m/s
  // The start's warm-up (the start gait's rules, which the planner does not steer) ends at the
  // touchdown, from the walker's warmup_handover_after-th step on, whose landing foot has an
  // obstacle's near edge less than end_warmup_within ahead, and so do the push response's rule
  // steps, so that the planner plans the approach steps rather than taking over an obstacle
  // already close (0: off; the rules walk their number of steps).
  double end_warmup_within = 0.0;  // m
  bool IsValid(std::string* error) const;
};

// The speed command with the approach speed: max(v_d, p.approach_speed) while an obstacle among
// `obstacles` has its near edge within p.approach_distance of front_x and its far edge beyond
// back_x (the feet's x, m); else v_d. v_d itself when p.approach_speed is 0.
double ApproachSpeed(const StepPlannerParams& p, const std::vector<Obstacle>& obstacles,
                     double back_x, double front_x, double v_d);

// The planner's settings for a walker whose recent steps measure l_gait (m): l_nominal = l_gait
// and the approach range of follow_gait (above), l_gait first clamped into [l_min, l_over_max].
// Unchanged unless follow_gait.
StepPlannerParams FollowGait(const StepPlannerParams& p, double l_gait);

struct StepPlan {
  bool active = false;       // an obstacle within the horizon
  int approach_steps = 0;    // n: steps before the step over (0: this step is the step over)
  double step_length = 0.0;  // m: the target of the coming step
};

// The plan for the coming step, given the front foot's d_obs and the obstacle's length (m).
StepPlan PlanStep(const StepPlannerParams& p, double d_obs, double obstacle_length);

// The step-length fuzzy system over the reference gaits' step lengths (any order; throws
// std::invalid_argument unless at least two, finite, positive and distinct): input "L_step",
// one set per gait (sorted: RampDown below the shortest, Triangles, RampUp above the longest),
// one rule per set naming its gait's output term (O1..ON = 1..N in the given order).
TsFis StepLengthFis(const std::vector<double>& gait_l_steps);
// Per-gait weights (summing to 1) of the fuzzy system at step length l.
std::vector<double> StepLengthWeights(const TsFis& fis, double l);

}  // namespace rabbit

#endif  // RABBIT_CONTROL_STEP_PLANNER_H_
