// Push recovery for the Fuzzy-CMAC walker (beyond the chapter). Two reactions, each a
// parameter of RecoveryParams (keys of [controller.recovery]):
//
//   backward step   a swing foot that lands behind the stance foot while the hip moves backward
//                   (xd < backward_step_speed) is a step: support is exchanged. Without it a
//                   backward push that stops the hip before it passes over the stance foot leaves
//                   the robot rolling back onto its swing foot while the walker still drives the
//                   lifted old stance leg as the trunk's support (its hip saturates, the trunk
//                   pitches past 45 deg): the cause of every backward-push fall we analysed.
//   foot placement  the swing thigh's reference is moved by
//                     d_th = placement_gain dz(v_orb - v_nom), clamped to +-placement_max,
//                   (dz: a soft dead zone of placement_dead m/s)
//                   faded in with the swing's progress s = (t - t_touchdown) / t_step_nominal
//                   from placement_start to placement_full (a Raibert-style step-length
//                   correction). v_orb = sqrt(|E|), E = xd^2 - (g / y) (x - x_st)^2, signed as the
//                   way the hip will go (E >= 0: xd's sign; E < 0: the side of the foot the hip is
//                   on), is the hip speed above the stance foot predicted by the linear inverted
//                   pendulum (its
//                   orbital energy), nearly constant over an undisturbed stance, so the reaction
//                   depends less on the phase at which the push comes. The hip is not a point
//                   mass, so v_orb still varies over a step (about 0.45-0.7 m/s at 0.6 m/s, less
//                   around impacts): v_nom(s) is learnt per phase bin (kPhaseBins over s in
//                   [0, 1.5)) as the running mean over the last `nominal_steps` undisturbed steps
//                   (a bin not learnt yet: no placement).
//   trunk lean      the trunk's pitch reference q0_d is moved by
//                     d_q0 = -trunk_gain dz(v_orb - v_nom), clamped to +-trunk_max
//                   at once, within the step (the velocity control of eqs. 19-20 acts only at the
//                   next touchdowns, on a V_M that a hurried short step makes look slow).
//
// With enabled = false nothing changes: AcceptsLandingBehind is false and the offsets are 0.
#ifndef RABBIT_CONTROL_PUSH_RECOVERY_H_
#define RABBIT_CONTROL_PUSH_RECOVERY_H_

#include <array>
#include <string>

#include "rabbit/control/step_phase_bins.h"
#include "rabbit/sim/controller.h"

namespace rabbit {

struct RecoveryParams {
  bool enabled = true;
  // Backward step: hip speed (m/s) below which a landing behind the stance foot is a step.
  double backward_step_speed = 0.0;
  // Foot placement (rad of swing thigh per m/s of v_orb - v_nom; 0: off).
  double placement_gain = 0.0;
  double placement_max = 0.35;   // rad, bound of the offset
  double placement_start = 0.3;  // swing progress where the offset starts fading in
  double placement_full = 0.7;   // ... and where it is fully applied
  double placement_dead = 0.15;  // m/s: |v_orb - v_nom| below this is no disturbance
  // Trunk lean (rad of q0_d per m/s of v_orb - v_nom; 0: off), and its bound (rad).
  double trunk_gain = 0.0;
  double trunk_max = 0.2;
  int nominal_steps = 4;  // undisturbed steps averaged into v_nom
  // The response to a large disturbance (push_response.h): its dead zone on v_orb less its
  // reference (m/s; 0: off), the share of that speed added to the fuzzy system's velocity input
  // and its bound (m/s), the change of it that moves the input again within a step (m/s), the
  // touchdowns at which q0_d is held from the end of a disturbed step (0: none).
  double response_dead = 0.0;
  double response_fis_gain = 0.0;
  double response_fis_max = 0.5;
  double response_fis_step = 0.05;
  int response_fis_steps = 1;  // disturbed steps in a row whose gait pattern follows
  int response_hold_steps = 0;
  // Backward disturbance (m/s, below -response_rules_dead) that hands the walk to the start
  // gait's rules for response_rules_steps steps (0: never).
  double response_rules_dead = 0.6;
  // Swing placement (rad of swing thigh per m/s of the disturbance past the dead zone, and its
  // bound) and trunk lean (rad of q0_d per m/s, signed, and its bound) while disturbed.
  double response_place_gain = 0.0;
  double response_place_max = 0.35;
  double response_place_back = 1.0;  // share of the placement after a backward disturbance
  double response_trunk_gain = 0.0;
  double response_trunk_max = 0.2;
  int response_rules_steps = 0;
  // Backward catch (m; 0: off): in a step disturbed backward, once past response_catch_from of
  // the step the pendulum falls back (v_orb < 0) with the hip moving backward, the swing foot is
  // put down response_catch_back behind the hip's capture point (push_response.h).
  double response_catch_back = 0.0;
  double response_catch_from = 0.7;
  // Forward reach (share in [0, 1]; 0: off): in a step disturbed forward beyond
  // response_reach_dead (m/s), and in the step after it, the swing thigh's reference is raised
  // this share of the way toward a straight leg whose foot is on the hip's capture point
  // (push_response.h).
  double response_reach = 0.0;
  double response_reach_dead = 0.3;
  // m/s (0: every bin): the reach compares only the phase bins where the reference's |v_orb| is
  // at least this. Near the pendulum's apex (E about 0) v_orb = sqrt(|E|) turns a small
  // difference of energy into a large one of speed (push_response.h).
  double response_reach_ref_min = 0.0;
  double gravity = 9.81;  // m/s^2, for the pendulum's omega^2 = g / y_hip
  bool IsValid(std::string* error) const;
};

// The pendulum's predicted hip speed above the stance foot: sqrt(|E|) with
// E = xd^2 - (g / y) dx^2, dx = x_hip - x_stance_foot, signed as xd when E >= 0 (the hip passes
// over the foot) and as dx when E < 0 (it turns back and falls on its side of the foot).
double OrbitalVelocity(double dx, double xd, double y, double gravity);

// The fade of the placement offset at swing progress s: 0 before start, 1 after full, linear in
// between (a step at start when full <= start).
double PlacementFade(double s, double start, double full);

class PushRecovery {
 public:
  explicit PushRecovery(const RecoveryParams& params) : p_(params) {}

  // Every control period, with the walker's stance leg (0 or 1).
  void Observe(const Observation& obs, int stance);
  // At each support exchange (t_step: the finished step's duration, 0 if unknown).
  void OnTouchdown(double t, double t_step);
  // Whether a landing of the swing foot behind the stance foot counts as a step.
  bool AcceptsLandingBehind(const Observation& obs) const;
  // Offset (rad) to add to the swing thigh's (hip's) reference now.
  double SwingOffset(double t) const;
  // Offset (rad) to add to the trunk's pitch reference q0_d now.
  double TrunkOffset(double t) const;

  double v_orb() const { return v_orb_; }
  static constexpr int kPhaseBins = StepPhaseBins::kBins;
  // The learnt nominal v_orb at swing progress s (NaN: not learnt).
  double Nominal(double s) const;

 private:
  RecoveryParams p_;
  // v_orb - v_nom(s) past the soft dead zone (0 within it, or when nothing is learnt).
  double Excess(double t) const;
  double Progress(double t) const;

  double v_orb_ = 0.0;
  std::array<double, kPhaseBins> nominal_{};  // learnt v_orb per phase bin
  std::array<int, kPhaseBins> learnt_{};      // steps averaged into each bin
  StepPhaseBins bins_;                        // the current step's v_orb
  bool disturbed_ = false;  // |v_orb - v_nom| beyond placement_dead in the current step
  double t_touchdown_ = -1.0;
  double t_step_ = 0.0;  // nominal step duration (last undisturbed step)
};

}  // namespace rabbit

#endif  // RABBIT_CONTROL_PUSH_RECOVERY_H_
