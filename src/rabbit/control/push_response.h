// The walker's response to a large disturbance (beyond the chapter; keys response_* of
// [controller.recovery], push_recovery.h). The gait pattern's step length follows the fuzzy
// system's velocity input, which the walker gives the speed command V_c (fis_v_lead = 1), and the
// velocity control reads a push's hurried or long steps as a gait that is too slow or too fast.
// After a push both are wrong: the hip runs ahead of feet that keep the command's step, or the
// trunk leans back after one long step until the robot walks backward. The response measures the
// disturbance and, while it lasts:
//
//   disturbance   d = v_orb - v_ref(s): the pendulum's predicted hip speed (push_recovery.h) less
//                 its value at the same phase s of the same leg's reference step (kPhaseBins over
//                 s in [0, 1.5) of the leg's first step duration, one timebase for learning and
//                 comparing). The reference is the leg's last step that agreed with the leg's
//                 step before it, bin by bin, within response_dead: a settled walk at whatever
//                 speed. d is evaluated as each bin of the step is complete (its mean), from
//                 s = 0.2 to 1 (around the impacts v_orb depends too much on the step's timing),
//                 and |d| > response_dead disturbs the step. The response is armed in plain
//                 walking only: not in the warm-up, nor while the step planner or the foot lift
//                 is at work (a step over is no push), nor until three touchdowns in a row have
//                 had one speed command on level ground (Command: a change of command or of grade
//                 moves v_orb as a push does); the reference is learnt afresh after;
//   pitch         the velocity control leaves q0_d as it is at the response_hold_steps touchdowns
//                 from the one that ends a disturbed step (the push's steps are no measure of the
//                 gait's speed: it leaned the trunk back after one long step until the robot
//                 walked backward, or forward after hurried short ones);
//   placement     the swing thigh's reference moves by response_place_gain (|d| - response_dead)
//                 sign(d), within +-response_place_max, faded in over the swing as the push
//                 recovery's placement (placement_start, placement_full), times
//                 response_place_back when d < 0 (Raibert: a faster hip, a longer step);
//   rules         a step whose d fell below -response_rules_dead hands the walk, from the
//                 touchdown that ends it, to the start gait's pragmatic rules (the warm-up's,
//                 their swing starting there) for response_rules_steps steps: the rules'
//                 fixed lock angle between the thighs walks out of a backward push that leaves
//                 the gait pattern, a function of the stance thigh's angle, running in reverse;
//   catch         in a step disturbed backward, once past response_catch_from of the step the
//                 pendulum falls back (v_orb < 0) with the hip moving backward, the swing foot is
//                 put down response_catch_back behind the hip's capture point (a straight leg,
//                 the knee flexed kCatchKnee), and its landing behind the stance foot is a step:
//                 the gait pattern, running in reverse, held the swing foot up until the hip ran
//                 back past it;
//   reach         in a step disturbed forward (d > response_reach_dead, d here from the current
//                 bin's running mean too, from s = 0.2 on and past s = 1 in a long step, so that
//                 it acts within the step) and in the step after it, the swing thigh's reference
//                 is raised (never lowered) response_reach of the way toward the angle of a
//                 straight leg whose foot is on the hip's capture point x + xd sqrt(y / g): a
//                 Raibert / capture-point step; without it the hip ran ahead of feet that kept the
//                 command's step, one long step, then a split stance or a fall. Only the bins
//                 where the reference's |v_orb| is at least response_reach_ref_min are compared:
//                 near the pendulum's apex v_orb = sqrt(|E|) is steep in E, and the uneven
//                 strides of a walk that has just settled read there as forward pushes;
//   trunk         q0_d moves by response_trunk_gain (|d| - response_dead) sign(d) (within
//                 +-response_trunk_max; measured, not used by the presets);
//   gait pattern  the fuzzy system's velocity input moves by response_fis_gain d (within
//                 +-response_fis_max): mid-step, as soon as |d| exceeds the dead zone and again
//                 whenever d has moved by response_fis_step since, and at the touchdown after a
//                 disturbed step by the gain times the mean d over its disturbed bins, in the
//                 first response_fis_steps disturbed steps (measured, not used by the presets:
//                 the faster gaits' rules add speed, and the offset feeds itself).
//
// With response_dead = 0 (the default) nothing changes.
#ifndef RABBIT_CONTROL_PUSH_RESPONSE_H_
#define RABBIT_CONTROL_PUSH_RESPONSE_H_

#include <array>

#include <Eigen/Core>

#include "rabbit/control/push_recovery.h"
#include "rabbit/sim/controller.h"

namespace rabbit {

class PushResponse {
 public:
  explicit PushResponse(const RecoveryParams& params) : p_(params) {}

  bool enabled() const { return p_.enabled && p_.response_dead > 0.0; }
  // Every control period with the pendulum's hip speed v_orb (plain: the walker walks on its
  // own, not in the warm-up, nor with the planner or the foot lift at work). Returns true when
  // the fuzzy system's input should be moved now (FisOffset() has changed within the step).
  // xd: the hip's forward speed (m/s), for the backward catch.
  bool Observe(double t, double v_orb, bool plain, double xd = 0.0);
  // At each touchdown, the speed command the walker acts on for the coming step and whether the
  // ground is level (no grade measured or known ahead): the response is armed only after
  // kSteadySteps touchdowns in a row with one command on level ground (a commanded change of
  // speed or a change of grade changes v_orb as much as a push).
  void Command(double v_c, bool level);
  // At each support exchange, before the walker's own touchdown work (t_step: the finished
  // step's duration, 0 if unknown).
  void OnTouchdown(double t, double t_step);
  // True once, at the touchdown that ends a step whose d fell below -response_rules_dead
  // (response_rules_steps > 0): the walker hands the next steps to the start gait's rules.
  bool TakesRules() {
    const bool take = rules_pending_;
    rules_pending_ = false;
    return take;
  }
  // Offset (rad) of the swing thigh's reference: response_place_gain times d past the dead zone,
  // faded in over the swing as the push recovery's placement (placement_start, placement_full).
  double SwingOffset(double t) const;
  // The backward catch (response_catch_back > 0): true from the moment in a step of plain walking
  // disturbed backward (d < -response_dead), past response_catch_from of the leg's reference
  // step duration, at which v_orb < 0 (the pendulum falls back) and the hip moves backward, until
  // the touchdown (Observe latches it). The walker then tracks CatchReference with the PD and
  // counts the landing behind the stance foot as a step.
  bool Catching() const { return catching_; }
  // The catch's swing references (hip joint angle, knee angle and their rates): the swing
  // thigh's absolute angle that puts a straight leg of length leg (m) response_catch_back behind
  // the hip's capture point x + min(xd, 0) sqrt(y / g) (y: the hip's height above the ground
  // under it), the knee flexed by kCatchKnee.
  void CatchReference(const Observation& obs, double leg, Eigen::Vector4d* ref) const;
  // The catch's references replace *ref while catching with the swing foot in the air.
  void ApplyCatch(const Observation& obs, int swing, double leg, Eigen::Vector4d* ref) const {
    if (catching_ && !obs.foot_contact[swing]) CatchReference(obs, leg, ref);
  }
  // The forward reach (response_reach > 0): true in a step of plain walking disturbed forward
  // (d > response_reach_dead, from the current bin's running mean too, s >= 0.2) from the moment
  // it is seen, and in the whole step after it.
  bool Reaching() const { return reach_step_ || reach_next_; }
  // The swing thigh's reference (the hip joint's angle) of a straight leg of length leg (m) whose
  // foot is on the hip's capture point x + max(xd, 0) sqrt(y / g) (y: the hip's height above the
  // ground under it).
  double ReachReference(const Observation& obs, double leg) const;
  // While reaching with the swing foot in the air, (*ref)[0] moves response_reach of the way up
  // to ReachReference (not when it is already beyond it); the knee's reference and the rates are
  // left as they are.
  void ApplyReach(const Observation& obs, int swing, double leg, Eigen::Vector4d* ref) const;
  // Offset (rad) of q0_d: response_trunk_gain times d past the dead zone (positive: the trunk
  // pitches back after a backward push, whose hip torque drives the hip forward at once).
  double TrunkOffset() const;
  // Whether the velocity control leaves q0_d unchanged at this touchdown.
  bool HoldsPitch() const { return hold_; }
  // m/s to add to the fuzzy system's velocity input now.
  double FisOffset() const { return fis_offset_; }
  // The disturbance d of the last complete bin of this step (0: none yet, or off).
  double disturbance() const { return d_; }
  bool step_disturbed() const { return step_disturbed_; }

  static constexpr int kPhaseBins = PushRecovery::kPhaseBins;
  // The bins compared (s in [0.2, 1.0)): v_orb around the impacts depends too much on the
  // step's timing.
  static constexpr int kFirstBin = 2, kLastBin = 9;
  static constexpr int kSteadySteps = 3;
  static constexpr double kCatchKnee = 0.2;  // rad of knee flexion during the catch

 private:
  double Phase(double t) const;  // the step's phase on its leg's reference (-1: none)
  // The hip joint's angle of a straight leg of length leg (m) whose foot lies offset (m) ahead of
  // the capture point x + xd sqrt(y / g) (y: the hip's height above the ground under it): the
  // catch's and the reach's swing reference.
  double StraightLegAngle(const Observation& obs, double xd, double offset, double leg) const;
  double Excess() const;         // d past the dead zone (0 within it)
  double Clamp(double v) const;
  void CatchCheck(double t, double v_orb, double xd);
  void ReachCheck(double t);  // the forward reach's trigger, on the current bin's running mean

  RecoveryParams p_;
  // Per leg (the steps of the two legs differ by more than the dead zone in some gaits):
  template <typename T>
  using PerLeg = std::array<std::array<T, kPhaseBins>, 2>;
  PerLeg<double> ref_{};     // v_orb per phase bin of the reference step
  PerLeg<bool> has_ref_{};   // ... and whether the bin was sampled
  PerLeg<double> prev_{};    // v_orb per phase bin of the leg's last step ...
  PerLeg<bool> has_prev_{};  // ... and whether the bin was sampled
  int leg_ = 0;              // the current step's leg (alternating at each touchdown)
  StepPhaseBins bins_;       // the current step's v_orb
  double t_touchdown_ = -1.0;
  std::array<double, 2> t_ref_step_{};  // the reference steps' durations
  double d_ = 0.0;
  bool step_disturbed_ = false;
  double dev_sum_ = 0.0;   // the current step's disturbed samples' d ...
  int dev_n_ = 0;          // ... and their count
  int disturbed_run_ = 0;  // disturbed steps since the reference
  int hold_left_ = 0;
  bool hold_ = false;
  double fis_offset_ = 0.0;
  bool armed_ = false;  // plain walking (Observe)
  double v_c_ = -1.0;   // the last command (Command)
  int steady_ = 0;      // touchdowns in a row with that command on level ground
  bool rules_pending_ = false;
  double min_d_ = 0.0;  // the current step's most negative d
  bool catching_ = false;
  bool reach_step_ = false;  // the reach: this step is disturbed forward ...
  bool reach_next_ = false;  // ... or the step before it was
};

}  // namespace rabbit

#endif  // RABBIT_CONTROL_PUSH_RESPONSE_H_
