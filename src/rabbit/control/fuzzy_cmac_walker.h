// The closed-loop walker of the chapter (section 5, figure 9):
//   gait pattern   the Fuzzy-CMAC: every control period the swing leg's references
//                  [q_i1_d, q_i2_d, qd_i1_d, qd_i2_d] = Y(e) with e = q_st1, the stance hip angle
//                  (eq. 13); the fuzzy system is evaluated once per step, at touchdown, at
//                  X = [V_M, d_obs] and held during the step. Any SwingPattern
//                  (rabbit/learn/swing_pattern.h) may take its place: the baselines
//                  nearest-gait switching and the multi-input CMACs;
//   velocity       once per step q0_d(n+1) = q0_d(n) + K_P (V_d - V_M) + K_V d/dt (V_d - V_M)
//                  (eqs. 19-20; the derivative is the change of the error over the last step
//                  divided by t_step), clamped to [q0_d_min, q0_d_max];
//   PD             swing hip and knee track the gait pattern (eqs. 21-22), stance knee locked at 0
//                  (eq. 23), stance hip holds the trunk at q0_d (eq. 24).
// Perception: V_M is the gait meter's last complete step (eq. 1; signed: a step that lands behind
// the stance foot, a recovery step, leaves V_M and q0_d as they were, see OnTouchdown); d_obs the
// horizontal distance from the front (new stance) foot to the near edge of the next obstacle
// ahead, saturated at d_obs_max. Both may carry Gaussian noise from a seeded generator
// (deterministic for a seed).
//
// Support exchange: when the swing foot lands (after at least the gait meter's min_air_time in the
// air) ahead of the stance foot, legs swap roles. A swing foot that scuffs the ground behind the
// stance foot and lifts again is not a step.
#ifndef RABBIT_CONTROL_FUZZY_CMAC_WALKER_H_
#define RABBIT_CONTROL_FUZZY_CMAC_WALKER_H_

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "rabbit/control/approach_watch.h"
#include "rabbit/control/foot_lift.h"
#include "rabbit/control/gait_meter.h"
#include "rabbit/control/pragmatic_rules.h"
#include "rabbit/control/push_recovery.h"
#include "rabbit/control/push_response.h"
#include "rabbit/control/rule_gait_choice.h"
#include "rabbit/control/slope_adaptation.h"
#include "rabbit/control/stall_recovery.h"
#include "rabbit/control/step_planner.h"
#include "rabbit/control/terrain_steps.h"
#include "rabbit/control/velocity_control.h"
#include "rabbit/control/velocity_profile.h"
#include "rabbit/learn/fuzzy_cmac.h"
#include "rabbit/learn/swing_pattern.h"
#include "rabbit/sim/controller.h"

namespace rabbit {

struct WalkerParams {
  // PD gains (N m/rad, N m s/rad): swing hip (eq. 21), swing knee (eq. 22), stance knee (eq. 23),
  // trunk through the stance hip (eq. 24).
  // Defaults: chosen by a sweep of the paper suite's ramp (docs/design/walker.md, "The walker").
  double hip_kp = 350.0, hip_kd = 25.0;
  double knee_kp = 350.0, knee_kd = 20.0;
  double stance_knee_kp = 900.0, stance_knee_kd = 35.0;
  // The stance knee's landing (beyond the chapter; 0 = off, eq. 23 as it is): after the touchdown
  // of a lifted swing (the step over or the trailing leg's step) with the knee flexed below
  // stance_knee_flexed (rad, negative), the stance knee's reference rises from the landing angle
  // at stance_knee_rate (rad/s) up to its target, instead of stepping to it. A leg landing from a
  // step over flexed by 0.7 rad was otherwise snapped straight at the knee's full torque: the
  // robot took off, the knee passed straight at 13 rad/s (where the actuator gives no torque)
  // and the next landing fell (docs/design/walker.md, "The walker").
  double stance_knee_rate = 0.0;
  double stance_knee_flexed = 0.0;
  double trunk_kp = 400.0, trunk_kd = 40.0;
  // Velocity control (eqs. 19-20): K_P in rad per m/s, K_V in rad per m/s^2 (it multiplies the
  // error's change over a step divided by t_step).
  double k_p = 0.2, k_v = 0.1;
  double q0_d_min = -0.10, q0_d_max = 0.45;  // rad (-5.73, 25.78 deg): the range of q0_d
  double q0_d_initial = 0.07;                // rad: q0_d before the first step
  double v_m_initial = 0.6;                  // m/s: V_M assumed before the first measured step
  // V_M given to the FIS and the velocity control: the mean of the last `v_m_average_steps`
  // measured steps (1: the chapter's per-step value; 2: one step of each leg, a stride). The legs'
  // steps alternate by a few cm/s, which would otherwise drive the fuzzy blend step by step.
  int v_m_average_steps = 2;
  // Velocity given to the FIS: V_M + fis_v_lead (V_d - V_M) (0: the chapter's V_M; 1: V_d; with
  // velocity_control enabled its rate-limited command V_c takes the place of V_d). With
  // a lead the gait pattern moves toward the gait of the desired velocity before the trunk pitch
  // has brought V_M there (the fast gaits' longer steps are what makes the robot fast).
  double fis_v_lead = 0.0;
  // Rule share (beyond the chapter; empty or all 0: the chapter's walker): one factor r_k in
  // [0, 1] per reference gait, in the gait pattern's order. Gait k's part of the swing and of the
  // stance knee is walked by (1 - r_k) the PD tracking above and r_k the gait's own pragmatic
  // rules (gait_rules; eqs. 14-15, 17-18: hip pulse, passive swing and lock, knee free then
  // locked, stance knee at the gait's gains). With the fuzzy weights w_k:
  //   tau_swing = (1 - sum_k w_k r_k) PD + sum_k w_k r_k tau_rules_k,
  //   stance knee gains = sum_k w_k ((1 - r_k) stance_knee_kp + r_k knee_kp_k) (kd alike).
  // The fast gaits use the motors' whole torque and speed range on a compliant stance knee, which
  // PD tracking cannot reproduce (docs/design/walker.md, "The walker"): they are walked by their
  // rules.
  std::vector<double> rule_share;
  // Between two neighbouring rule-walked gaits (share >= 1/2) the gait pattern's velocity input
  // moves to the nearer one's speed, the speeds being gait_pitches' (rule_gait_choice.h; false:
  // the input as it is, the blend of both).
  bool rule_gait_choice = false;
  // With rule_gait_choice, the choice acts also between a rule-walked and a tracked neighbour
  // whose faster gait is below this speed (m/s in [0, 3]; 0: off).
  double rule_gait_choice_mixed_below = 0.0;
  // Where between such a mixed pair the input moves from the slower gait to the faster: at this
  // share of the way between their speeds (in [0, 1]; 0.5: the midpoint).
  double rule_gait_choice_mixed_point = 0.5;
  // The command holds for the choice while it changes by at most this much from one touchdown to
  // the next (m/s in [0, 1]; 0: only an unchanged command holds).
  double rule_gait_choice_hold_rate = 0.0;
  // Per reference gait, in the gait pattern's order (filled from the gait database, not a key).
  std::vector<PragmaticParams> gait_rules;
  // Perception.
  double d_obs_max = 1.0;    // m: d_obs saturates here (>= 0.5 m means no obstacle to the FIS)
  double v_m_noise = 0.0;    // m/s, standard deviation of the noise on V_M
  double d_obs_noise = 0.0;  // m, standard deviation of the noise on d_obs
  std::uint64_t seed = 1;    // of the noise
  // Frame of the gait pattern: true (default) the thigh frame (FuzzyCmac::QueryThigh: stance
  // thigh's absolute angle in, swing thigh's out, each gait at its own trunk pitch; needs
  // SetTrunkPitches); false the chapter's e = q_st1 and q_sw1 relative to the trunk.
  bool thigh_frame = true;
  // Step-over foot lift (foot_lift.h; keys lift_*).
  FootLiftParams lift;
  double thigh_length = 0.40, shin_length = 0.47;  // m: the model's, for the inverse kinematics
  // Multi-step foot placement over obstacles ([controller.planner], step_planner.h). When enabled,
  // a step with an obstacle within planner.horizon takes its gait weights from the step-length
  // fuzzy system instead of Table 3, and the foot lift is armed for the planned step over (and
  // the trailing leg) only. gait_l_steps: the reference gaits' L_step in network order (the gait
  // database's l_step_m; set by the scenario runner, not a key).
  StepPlannerParams planner;
  std::vector<double> gait_l_steps;
  // Start: the first `warmup_steps` steps walk with the pragmatic rules `warmup` (the start
  // gait's), and the Fuzzy-CMAC takes over at the touchdown that ends them (0: from t = 0).
  int warmup_steps = 6;
  PragmaticParams warmup;
  // Early hand-over: a warm-up step, from the `warmup_handover_after`-th on (0-based; the first
  // step from the walking start is short on any robot), shorter than `warmup_handover_ratio`
  // times the start gait's step length `warmup_l_step` ends the warm-up at its touchdown (ratio 0:
  // off). The start gait's rules have no feedback on speed, so on a robot unlike the one they were
  // found on (heavier legs) their steps shrink until it falls; the Fuzzy-CMAC's velocity control
  // can catch it. warmup_l_step is the database's L_step of the start gait (set from it, not a
  // key).
  double warmup_handover_ratio = 0.0;
  int warmup_handover_after = 1;
  double warmup_l_step = 0.0;
  // Push recovery (push_recovery.h; keys of [controller.recovery]).
  RecoveryParams recovery;
  // Slope adaptation (slope_adaptation.h; keys of [controller.slope]).
  SlopeParams slope;
  // Velocity control beyond the chapter's law (velocity_control.h; keys of
  // [controller.velocity_control]). gait_pitches: the reference gaits' (measured V_M, q0_d) for
  // its pitch map (set by the scenario runner from the gait database, not a key).
  VelocityControlParams velocity_control;
  std::vector<std::pair<double, double>> gait_pitches;
  // Stall recovery (stall_recovery.h; keys of [controller.stall_recovery]).
  StallRecoveryParams stall_recovery;
  // Terrain-step handling (terrain_steps.h; keys of [controller.steps]).
  TerrainStepParams steps;
  // Keep the tracking log (references and measurements) every n-th control period (0: none).
  int log_every = 1;
  bool IsValid(std::string* error) const;
};

// The ranges of the walker's rule_gait_choice_* numbers, one table for WalkerParams::IsValid and
// the scenario keys of the same names (the unit follows the bounds in the message).
struct WalkerRange {
  const char* key;
  double WalkerParams::*field;
  double lo, hi;
  const char* unit;
};
const std::vector<WalkerRange>& RuleGaitChoiceRanges();

// One step as the walker saw it, at the touchdown that ended it.
struct WalkerStep {
  StepRecord step;              // gait meter's record (index, leg, t, L_step, t_step, V_M)
  double v_d = 0.0;             // desired velocity at the touchdown, m/s
  double v_m_used = 0.0;        // V_M given to the FIS and the velocity control (with noise)
  double d_obs = 0.0;           // perceived d_obs for the next step (with noise), m
  int planned_steps = -1;       // planner: approach steps before the step over (-1: not planning)
  double planned_l_step = 0.0;  // planner: target of the next step, m
  double q0_d = 0.0;            // desired trunk pitch for the next step, rad
  std::vector<double> weights;  // per reference gait, summing to 1 (empty: the pattern has none)
  std::vector<double> activation;  // per rule (normalised; empty: the pattern has no rules)
  bool warmup = false;             // walked by the warm-up's pragmatic rules (weights not used)
};

// One line of the tracking log.
struct WalkerTrack {
  double t = 0.0;
  int stance = 0;
  double e = 0.0;
  double hip_ref = 0.0, hip = 0.0, knee_ref = 0.0, knee = 0.0;  // swing leg, rad
  double q0_d = 0.0, q0 = 0.0;
};

class FuzzyCmacWalker final : public Controller {
 public:
  // Any gait pattern (owned: its context is per-walker state), e.g. FuzzyCmacSwingPattern with
  // nearest-gait switching for that baseline. It must support the walker's frame
  // (params.thigh_frame). stance_leg: in support at t = 0. Throws std::invalid_argument.
  FuzzyCmacWalker(const WalkerParams& params, std::unique_ptr<SwingPattern> gait_pattern,
                  VelocityProfile velocity, int stance_leg);
  // The chapter's walker: the Fuzzy-CMAC, copied (its fuzzy context is per-walker state).
  FuzzyCmacWalker(const WalkerParams& params, FuzzyCmac gait_pattern, VelocityProfile velocity,
                  int stance_leg);
  Vec4 Compute(const Observation& obs) override;

  const std::vector<WalkerStep>& steps() const { return steps_; }
  const std::vector<WalkerTrack>& tracking() const { return tracking_; }
  const GaitMeter& meter() const { return meter_; }
  const SwingPattern& gait_pattern() const { return *pattern_; }
  const SlopeAdaptation& slope() const { return slope_; }
  double q0_d() const { return q0_d_; }
  bool warming_up() const { return warming_up_; }

 private:
  void OnTouchdown(const Observation& obs);
  void SetContext(double v_m, double d_obs);
  // The step planner's hook at a touchdown (front foot at x = front, perceived d_obs): sets the
  // gait weights for the coming step when an obstacle is within the horizon.
  StepPlan PlanNextStep(const Observation& obs, const StepRecord& step, double front, double d_obs);
  // planner.follow_gait: measures the walker's step and its gait's database step (planner_l_*).
  void FreezeGait();
  double Gaussian();
  // d_obs seen from x (no terrain: no obstacle), before noise.
  double ObstacleAhead(const Observation& obs, double x) const;
  // At a touchdown while the rules walk (the start's warm-up, or the push response's rule steps),
  // `taken` steps so far, the landing foot at front_x: whether the Fuzzy-CMAC takes over from
  // this touchdown on.
  bool WarmupEnds(const Observation& obs, int taken, double front_x) const;
  // The foot lift's target height (absolute y) at foot abscissa x: the highest over the obstacles
  // of base + a (height + lift_clearance), a the ramp (0..1); -infinity when none needs a lift.
  double LiftHeight(const Terrain& terrain, double foot_x) const;
  // Adds the foot lift to the swing references ref (hip, knee, rates).
  void ApplyLift(const Observation& obs, int sw_hip, Eigen::Vector4d* ref);
  // sum_k w_k r_k tau_rules_k for the swing (hip, knee), and sum_k w_k r_k (rule_share).
  Eigen::Vector2d RuleTorques(const Observation& obs, double* share);

  WalkerParams p_;
  std::unique_ptr<SwingPattern> pattern_;
  VelocityProfile velocity_;
  GaitMeter meter_;
  PragmaticController warmup_;
  PushRecovery recovery_;
  PushResponse response_;  // its response to a large disturbance (push_response.h)
  ApproachWatch watch_;    // a push while the step planner plans (approach_watch.h)
  double fis_v_ = 0.0, fis_d_obs_ = 0.0;  // the fuzzy system's inputs at the last touchdown
  bool planned_ = false;                  // the planner set the coming step's weights
  int rules_until_ = -1;  // the response's rules walk until this many steps (-1: not theirs)
  SlopeAdaptation slope_;
  StallRecovery stall_;
  TerrainSteps terrain_steps_;
  bool warming_up_;
  int stance_;
  double q0_d_;
  double v_m_;                    // V_M in use (noisy)
  std::vector<double> measured_;  // measured per-step V_M (noisy), for the running mean
  VelocityControl speed_;         // the q0_d update (eqs. 19-20, velocity_control.h)
  RuleGaitChoice choice_;         // between two rule-walked gaits (rule_gait_choice.h)
  std::uint64_t rng_;
  long periods_ = 0;
  bool lift_armed_ = false;                               // set at each touchdown
  bool lift_trailing_ = false;  // ... for the trailing leg (an obstacle between the feet)
  Eigen::Vector2d lift_delta_ = Eigen::Vector2d::Zero();  // last lift (hip, knee), rad
  double lift_t_ = -1.0;                                  // its time (-1: none)
  Eigen::Vector2d lift_ref_ = Eigen::Vector2d::Zero();    // last lifted (hip, knee) references
  bool lift_raised_ = false;  // the obstacle lift has raised this swing (lift_release_rate)
  // Rule share: the swing phase's start and each gait's rule state in it.
  struct RuleState {
    bool hip_locked = false, knee_flexed = false, knee_locked = false;
  };
  double swing_start_ = 0.0;
  double stance_knee_landing_ = 0.0;  // the stance knee's angle at a lifted swing's touchdown
  std::vector<RuleState> rule_states_;
  TsFis step_fis_;                     // planner: the step-length fuzzy system (when enabled)
  std::vector<size_t> planner_gaits_;  // planner: the gaits step_fis_ blends, in gait order
  double planner_bias_ = 0.0;          // planner: realised minus asked step length, fed back (m)
  double planner_target_ = -1.0;       // planner: the last planned step's target (-1: none)
  int recovery_left_ = 0;              // planner: nominal steps still to take after a step over
  bool planner_after_over_ = false;    // planner: the coming step is the step over or after it
  bool planner_face_ = false;  // the last plan was for a step's face, not an obstacle
  int pitch_hold_left_ = 0;            // planner: touchdowns still to leave q0_d unchanged
  double planner_l_gait_ = -1.0;       // planner.follow_gait: the measured step (-1: none), m
  double planner_l_db_ = 0.0;          // planner.follow_gait: its gait's database step, m
  std::vector<WalkerStep> steps_;
  std::vector<WalkerTrack> tracking_;
};

// Perceived distance from x (the front foot) to the near edge of the next obstacle ahead,
// saturated at d_max (docs/design/walker.md).
double ObstacleDistance(const Terrain& terrain, double x, double d_max);

}  // namespace rabbit

#endif  // RABBIT_CONTROL_FUZZY_CMAC_WALKER_H_
