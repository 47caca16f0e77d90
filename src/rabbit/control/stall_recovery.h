// Stall recovery for the walker (beyond the chapter; keys of [controller.stall_recovery]).
//
// After a hard push the walker can stop making progress: a long step leaves it in a split stance
// with both feet down and the hip at rest between them, where the gait pattern (a function of the
// stance thigh's angle) holds its references still; or the hip moves backward and the pattern
// runs in reverse, flinging the swing foot forward while the robot falls back. Two reactions
// (after the warm-up):
//
// catch step   while the hip moves backward faster than `catch_speed` and the swing foot is in
//              the air, the swing thigh's reference is the absolute angle that puts a leg of
//              length thigh + shin at the capture point of the linear inverted pendulum,
//              x_cp = x_hip + xd sqrt(y / g) (y: the hip's height above the ground under it),
//              `catch_margin` behind it:
//                theta = asin(clamp((xd sqrt(y / g) - catch_margin) / (l1 + l2), +-catch_max)),
//              with the knee flexed by `catch_knee`; the foot lands behind the stance foot (the
//              push recovery's backward step) and stops the backward motion;
// push-off     once the hip's forward speed has stayed below `speed` for `hold_s` with both feet
//              down (a split stance), a pulse of `pulse_s` seconds during which
//   - the swing thigh's reference is moved back by `push_off` rad and the swing knee is held
//     straight: a swing foot on the ground then pushes the hip forward over it (a foot in the air
//     is placed further back, which brakes a backward motion);
//   - the trunk's pitch reference q0_d is moved forward by `trunk_lean` rad;
//   - the stance knee's reference (0, locked) is flexed by `knee_dip` rad: the front leg yields,
//     and the hip, past the top of the rear leg's arc, falls forward; at the pulse's end the knee
//     extends again and lifts the hip over the front foot;
//   - the swing is tracked by the PD (the rule share is suspended).
// Both offsets are faded in and out over `ramp_s` at the pulse's ends. The detection timer
// restarts when a pulse ends, so a robot still stuck gets another pulse after `hold_s`.
// With enabled = false nothing changes: Active is false and the offsets are 0.
#ifndef RABBIT_CONTROL_STALL_RECOVERY_H_
#define RABBIT_CONTROL_STALL_RECOVERY_H_

#include <string>

#include "rabbit/sim/controller.h"

namespace rabbit {

struct StallRecoveryParams {
  bool enabled = false;
  double speed = 0.1;          // m/s: hip forward speed below which the robot makes no progress
  double hold_s = 0.25;        // s below `speed` before a pulse
  double pulse_s = 0.4;        // s: the pulse's length
  double ramp_s = 0.05;        // s: fade in and out at the pulse's ends
  double push_off = 0.3;       // rad: the swing thigh's reference moves back by this
  double trunk_lean = 0.1;     // rad: q0_d moves forward by this
  double knee_dip = 0.0;       // rad: the stance knee's reference flexes by this
  double catch_speed = 0.1;    // m/s: backward hip speed beyond which the swing foot catches
  double catch_margin = 0.05;  // m behind the capture point
  double catch_max = 0.6;      // rad: bound of the catch thigh angle
  double catch_knee = 0.2;     // rad of knee flexion during the catch
  double thigh_length = 0.40, shin_length = 0.47;  // m: the model's (set by the runner, not keys)
  double gravity = 9.81;                           // m/s^2
  bool IsValid(std::string* error) const;
};

class StallRecovery {
 public:
  explicit StallRecovery(const StallRecoveryParams& params) : p_(params) {}

  // Every control period (armed: false during the walker's warm-up, which resets the detection).
  void Observe(const Observation& obs, bool armed);
  // Whether a pulse is on at t.
  bool Active(double t) const;
  // The pulse's strength at t: 0 outside, 1 inside, linear over ramp_s at its ends.
  double Strength(double t) const;
  // Moves the swing references (hip, knee, hip rate, knee rate) of leg 1 - stance: the catch
  // step's, or during a pulse the push-off's.
  void Apply(const Observation& obs, int stance, Eigen::Vector4d* ref) const;
  // The catch step's absolute swing thigh angle (rad, forward positive) for a hip at height y
  // moving at xd.
  double CatchAngle(double xd, double y) const;
  // Whether the catch step drives the swing now.
  bool Catching(const Observation& obs, int stance) const;
  // The stance knee's reference (rad, 0 outside a pulse; flexed is negative).
  double StanceKnee(double t) const;
  // Offset (rad) to add to q0_d at t.
  double TrunkOffset(double t) const;
  int pulses() const { return pulses_; }

 private:
  StallRecoveryParams p_;
  bool armed_ = false;         // after the warm-up
  double slow_since_ = -1.0;   // start of the current spell below `speed` (-1: none)
  double pulse_start_ = -1.0;  // start of the last pulse (-1: none yet)
  int pulses_ = 0;
};

}  // namespace rabbit

#endif  // RABBIT_CONTROL_STALL_RECOVERY_H_
