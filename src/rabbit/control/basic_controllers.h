// The simplest controllers: no torque at all, and PD hold of every joint at a fixed target.
#ifndef RABBIT_CONTROL_BASIC_CONTROLLERS_H_
#define RABBIT_CONTROL_BASIC_CONTROLLERS_H_

#include <string>

#include "rabbit/sim/controller.h"

namespace rabbit {

// Zero torque on every joint: the robot moves under gravity and contact only.
class PassiveController final : public Controller {
 public:
  Vec4 Compute(const Observation& /*obs*/) override { return Vec4::Zero(); }
};

// tau_j = kp_j (target_j - q_j) - kd_j qd_j on [hip1, knee1, hip2, knee2].
struct PdHoldParams {
  Vec4 target = Vec4::Zero();       // rad
  Vec4 kp = Vec4::Constant(600.0);  // N m / rad
  Vec4 kd = Vec4::Constant(30.0);   // N m s / rad
  bool IsValid(std::string* error) const;
};

class PdHoldController final : public Controller {
 public:
  explicit PdHoldController(const PdHoldParams& params) : params_(params) {}
  Vec4 Compute(const Observation& obs) override;

 private:
  PdHoldParams params_;
};

}  // namespace rabbit

#endif  // RABBIT_CONTROL_BASIC_CONTROLLERS_H_
