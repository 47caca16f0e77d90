// Actuator limits of RABBIT's RS420J motors through a 50:1 gear (chapter section 2), expressed on
// the joint side:   |w| <= w_full:          |tau| <= max_torque         (75 N m at 2000 rpm motor)
//                   w_full < |w| <= w_max:  |tau| <= max_power / |w|    (315 W)
//                   |w| > w_max:            tau = 0                     (beyond 4000 rpm motor)
#ifndef RABBIT_CONTACT_ACTUATOR_H_
#define RABBIT_CONTACT_ACTUATOR_H_

#include <string>

namespace rabbit {

struct ActuatorParams {
  double max_torque = 75.0;          // N m, joint side (1.5 N m x 50)
  double max_power = 315.0;          // W
  double full_torque_speed = 4.189;  // rad/s, joint side (2000 rpm / 50)
  double max_speed = 8.378;          // rad/s, joint side (4000 rpm / 50)
  bool enabled = true;               // false: torques pass unchanged (for tests and studies)
  bool IsValid(std::string* error) const;
};

enum class SaturationRegion { kNone = 0, kTorque = 1, kPower = 2, kSpeed = 3 };

// Largest |tau| the actuator can give at joint speed w.
double TorqueLimit(const ActuatorParams& params, double speed);

// The torque the actuator applies when asked for `tau` at joint speed `speed`; *region tells which
// limit cut it (kNone when tau passed unchanged).
double SaturateTorque(const ActuatorParams& params, double tau, double speed,
                      SaturationRegion* region);

}  // namespace rabbit

#endif  // RABBIT_CONTACT_ACTUATOR_H_
