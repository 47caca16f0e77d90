// The controller interface the simulator calls once per control period (zero-order hold).
#ifndef RABBIT_SIM_CONTROLLER_H_
#define RABBIT_SIM_CONTROLLER_H_

#include <array>
#include <string>

#include "rabbit/contact/contact.h"
#include "rabbit/contact/terrain.h"
#include "rabbit/model/model.h"

namespace rabbit {

// What the robot's sensors (and, for perception, the terrain map) tell a controller.
struct Observation {
  double t = 0.0;
  Vec7 q = Vec7::Zero();
  Vec7 qd = Vec7::Zero();
  std::array<bool, kNumLegs> foot_contact{};  // binary contact sensors: Fn > 0
  std::array<Vec2, kNumLegs> foot_pos;
  std::array<FootForce, kNumLegs> foot_force{};
  const Terrain* terrain = nullptr;
};

class Controller {
 public:
  virtual ~Controller() = default;
  // Commanded joint torques [T_hip1, T_knee1, T_hip2, T_knee2] (before actuator saturation).
  virtual Vec4 Compute(const Observation& obs) = 0;
  // Called once per control period, before Compute, with the same observation: true ends the run
  // at this sample with the outcome `stalled` and `reason` (a watch around a walking controller,
  // rabbit/scenario/stall_watch.h). A controller that does not watch for stalls never ends a run.
  virtual bool CheckStall(const Observation& obs, std::string* reason) {
    (void)obs;
    (void)reason;
    return false;
  }
};

}  // namespace rabbit

#endif  // RABBIT_SIM_CONTROLLER_H_
