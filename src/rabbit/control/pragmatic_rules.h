// The five pragmatic rules of the chapter (section 4.1, eqs. 14-18), used to generate reference
// gaits without reference trajectories (docs/design/gait-pattern.md):
//   swing hip   a torque pulse K_hip_pulse for t1 < t < t2 after the swing phase starts (eq. 14),
//               then passive until the angle between the thighs qr1 = q_sw1 - q_st1 exceeds
//               qr1_dsw, then PD-locked there (eq. 15);
//   stance hip  holds the trunk pitch at q0_d (eq. 16);
//   swing knee  free, then, at the end of its extension (back up to qi2_dsw after flexing past
//               it), PD-locked at qi2_dsw (eq. 17); locked at the latest when the hip locks;
//   stance knee driven to 0 from impact and held there (eq. 18).
// The swing phase starts when the swing leg's partner touches down (support exchange).
#ifndef RABBIT_CONTROL_PRAGMATIC_RULES_H_
#define RABBIT_CONTROL_PRAGMATIC_RULES_H_

#include <string>

#include "rabbit/control/gait_meter.h"
#include "rabbit/sim/controller.h"

namespace rabbit {

struct PragmaticParams {
  // Per-gait parameters of the chapter's Table 2 (rad).
  double qr1_dsw = 0.5236;   // desired angle between the thighs at the end of the swing (30 deg)
  double qi2_dsw = -0.2443;  // swing knee angle locked at the end of its extension (-14 deg)
  double q0_d = 0.0698;      // trunk pitch held by the stance hip (4 deg)
  // Swing-hip pulse (eq. 14): amplitude (N m), start after the swing phase begins, duration (s).
  // Defaults: a walk found by NLopt's CRS2 at 0.6 m/s (bench/README.md, "gait synthesis").
  double pulse_torque = 75.0;
  double pulse_start = 0.0;
  double pulse_duration = 0.25;
  // PD gains (N m/rad, N m s/rad): swing-hip lock (eq. 15), trunk (eq. 16), knees (eqs. 17-18).
  double hip_kp = 770.0, hip_kd = 21.0;
  double trunk_kp = 400.0, trunk_kd = 40.0;
  double knee_kp = 450.0, knee_kd = 25.0;
  bool IsValid(std::string* error) const;
};

class PragmaticController final : public Controller {
 public:
  // stance_leg: the leg in support at t = 0 (0 or 1).
  PragmaticController(const PragmaticParams& params, int stance_leg);
  Vec4 Compute(const Observation& obs) override;
  // Takes over a walk in progress: stance_leg in support, its swing phase begun at swing_start
  // (the swing's rule state follows the measured swing from then on).
  void Restart(double swing_start, int stance_leg);
  const GaitMeter& meter() const { return meter_; }
  int stance_leg() const { return stance_; }

 private:
  PragmaticParams p_;
  GaitMeter meter_;
  int stance_;
  double swing_start_ = 0.0;
  bool hip_locked_ = false;
  bool knee_flexed_ = false;
  bool knee_locked_ = false;
};

// The documented start of a walk: the robot on its straight stance leg, whose thigh is at
// `stance_angle` from the vertical (0: mid-stance, hip above the foot), the swing leg a half step
// behind (thigh at -qr1_dsw/2) with its knee at qi2_dsw, the trunk at q0_d, the stance foot on the
// ground at x = 0, and the whole robot rotating rigidly about the stance foot with forward hip
// speed `speed` (an initial push).
void WalkingStartState(const Model& model, const PragmaticParams& params, double speed,
                       double stance_angle, int stance_leg, Vec7* q, Vec7* qd);

}  // namespace rabbit

#endif  // RABBIT_CONTROL_PRAGMATIC_RULES_H_
