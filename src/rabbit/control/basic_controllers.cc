#include "rabbit/control/basic_controllers.h"

namespace rabbit {

bool PdHoldParams::IsValid(std::string* error) const {
  if (!target.allFinite() || !kp.allFinite() || !kd.allFinite()) {
    *error = "pd_hold targets and gains must be finite";
    return false;
  }
  if ((kp.array() < 0.0).any() || (kd.array() < 0.0).any()) {
    *error = "pd_hold gains must be >= 0";
    return false;
  }
  return true;
}

Vec4 PdHoldController::Compute(const Observation& obs) {
  const Vec4 q = obs.q.tail<4>();
  const Vec4 qd = obs.qd.tail<4>();
  return params_.kp.cwiseProduct(params_.target - q) - params_.kd.cwiseProduct(qd);
}

}  // namespace rabbit
