// The choice between two rule-walked gaits (WalkerParams::rule_gait_choice;
// docs/design/velocity-control.md, "Velocity control").
//
// A gait walked by its pragmatic rules (rule_share 1) swings by its own hip pulse, lock angle and
// knee lock; the Fuzzy-CMAC's blend of two such neighbouring gaits sums their rule torques, each
// with its own lock, and walks neither: on the shipped database the blend of the 0.8 and 0.9 m/s
// gaits walks 0.7-0.8 m/s at the top of the pitch range with strides that swing by 0.3 m/s from
// one step to the next, where each gait alone walks its own speed. With the choice, a velocity
// input of the gait pattern that lies strictly between the speeds of two neighbouring gaits that
// are both rule-walked (share >= 1/2) is moved to the nearer of the two (the upper one at the
// midpoint), so that the pattern walks one of them; the trunk pitch of the velocity control then
// brings the stride to V_d. Between any other neighbours (one tracked gait) the input is left
// unchanged. The choice acts while the command V_c holds (is the same as at the touchdown
// before, or within hold_rate of it): while V_c moves faster (a ramp, or the rate limit after a
// step of V_d) the blend carries the pattern from one gait to the next, as a jump from the 0.9 to
// the 0.8 m/s gait in a ramp down leaves the robot at the faster gait's speed on the slower gait's
// pattern, and the tracked gait that joins next takes a long step. A slow ramp (a few mm/s a
// step) that starts from a level between the two rule-walked gaits is no such move: released
// into the blend there, the walk fell within a few steps; hold_rate keeps the choice through it.
// With mixed_below the choice acts also between a rule-walked
// and a tracked neighbour below that speed (on the shipped database the 0.3 and 0.4 m/s gaits,
// whose blend walks faster than either); the walker then leaves out the gait shift there while
// the command holds. Between such a mixed pair the switch lies at mixed_point of the way from the
// slower gait to the faster (0.5: the midpoint, as between two rule-walked gaits; larger values
// keep the slower gait longer).
#ifndef RABBIT_CONTROL_RULE_GAIT_CHOICE_H_
#define RABBIT_CONTROL_RULE_GAIT_CHOICE_H_

#include <utility>
#include <vector>

namespace rabbit {

// v: the gait pattern's velocity input (m/s); speeds: the reference gaits' speeds (the gait
// pattern's centres, m/s) and rule_share their shares, both in the gait pattern's order (the
// speeds need not be sorted; unequal sizes or an empty share leave v unchanged).
// Below mixed_below (m/s; 0: never) the choice acts also between a rule-walked and a tracked
// neighbour, where the faster of the two is below it; the input then moves to the slower gait
// below lo + mixed_point (hi - lo), to the faster one from there (mixed_point in [0, 1]).
double ChooseRuleGait(double v, const std::vector<double>& speeds,
                      const std::vector<double>& rule_share, double mixed_below = 0.0,
                      double mixed_point = 0.5);

// The walker's choice: ChooseRuleGait while the command holds, the input as it is otherwise.
class RuleGaitChoice {
 public:
  RuleGaitChoice() = default;
  // gait_pitches: the reference gaits' (speed, pitch), rule_share their shares (empty: none), in
  // the gait pattern's order; enabled with a share per gait but not a speed per gait throws
  // std::invalid_argument.
  RuleGaitChoice(bool enabled, const std::vector<std::pair<double, double>>& gait_pitches,
                 std::vector<double> rule_share, double mixed_below = 0.0, double mixed_point = 0.5,
                 double hold_rate = 0.0);
  // At each touchdown: the command V_c of the coming step. It holds when it differs from the
  // previous touchdown's by at most hold_rate (m/s; 0: only an unchanged command).
  void OnCommand(double v_c);
  // The gait pattern's velocity input after the choice.
  double Input(double v) const {
    return enabled_ && holding_
               ? ChooseRuleGait(v, speeds_, rule_share_, mixed_below_, mixed_point_)
               : v;
  }
  bool holding() const { return holding_; }

 private:
  bool enabled_ = false;
  double mixed_below_ = 0.0;
  double mixed_point_ = 0.5;
  double hold_rate_ = 0.0;
  std::vector<double> speeds_, rule_share_;
  bool have_command_ = false, holding_ = false;
  double last_command_ = 0.0;
};

}  // namespace rabbit

#endif  // RABBIT_CONTROL_RULE_GAIT_CHOICE_H_
