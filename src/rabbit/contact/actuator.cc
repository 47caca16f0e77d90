#include "rabbit/contact/actuator.h"

#include <algorithm>
#include <cmath>

namespace rabbit {

bool ActuatorParams::IsValid(std::string* error) const {
  if (!(std::isfinite(max_torque) && max_torque > 0.0) ||
      !(std::isfinite(max_power) && max_power > 0.0)) {
    *error = "max_torque and max_power must be finite and > 0";
    return false;
  }
  if (!(std::isfinite(full_torque_speed) && full_torque_speed > 0.0) ||
      !(std::isfinite(max_speed) && max_speed >= full_torque_speed)) {
    *error = "need 0 < full_torque_speed <= max_speed, both finite";
    return false;
  }
  return true;
}

double TorqueLimit(const ActuatorParams& params, double speed) {
  const double w = std::abs(speed);
  if (w <= params.full_torque_speed) return params.max_torque;
  if (w <= params.max_speed) return std::min(params.max_torque, params.max_power / w);
  return 0.0;
}

double SaturateTorque(const ActuatorParams& params, double tau, double speed,
                      SaturationRegion* region) {
  *region = SaturationRegion::kNone;
  if (!params.enabled) return tau;
  const double limit = TorqueLimit(params, speed);
  if (std::abs(tau) <= limit) return tau;
  const double w = std::abs(speed);
  *region = w <= params.full_torque_speed ? SaturationRegion::kTorque
            : w <= params.max_speed       ? SaturationRegion::kPower
                                          : SaturationRegion::kSpeed;
  return std::copysign(limit, tau);
}

}  // namespace rabbit
