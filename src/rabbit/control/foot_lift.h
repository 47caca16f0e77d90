// The step-over foot lift's settings (beyond the chapter). The reference gaits lift the swing foot
// only 2-4 cm in the front half of the swing, too little for a 5 cm obstacle. The walker arms the
// lift at a touchdown for the coming swing when d_obs < d_obs (the step over) or when an obstacle
// lies between the feet (the trailing leg); then, while the swing foot is in the air, the gait
// pattern's foot point (from its hip and knee references) is raised to at least obstacle height +
// clearance, from `lead` before the near edge to `trail` past the far edge (ramped in over `ramp`
// and out over `release`, in the foot's x), and turned back into hip and knee references by the
// leg's inverse kinematics (FuzzyCmacWalker::ApplyLift). The pattern keeps the foot's forward
// progress (so the fuzzy system still sets the step length); only its height changes.
// Keys: `lift_<member>` in [controller] (docs/formats/scenario.md).
#ifndef RABBIT_CONTROL_FOOT_LIFT_H_
#define RABBIT_CONTROL_FOOT_LIFT_H_

#include <algorithm>

namespace rabbit {

struct FootLiftParams {
  double clearance = 0.06;  // m above the obstacle's top (0 turns the lift off)
  // The clearance grows with the obstacle: max(clearance, height_gain * height) above its top
  // (LiftClearance; 0: clearance alone). A swing foot tracks the raised point with a lag and dips
  // below it by more the higher it was raised, so a clearance low enough for a short step over a
  // low obstacle trips on a high one.
  double height_gain = 0.0;
  double d_obs = 0.25;      // m: armed for the step over when d_obs is below this
  double lead = 0.10, trail = 0.04, ramp = 0.10, release = 0.10;  // m
  // The knee flexes further when the measured thigh, lagging its reference, would leave the foot
  // too low.
  bool feedback = true;
  // With a rule share: false (default) suspends it while the lift is armed, so that the lift,
  // which acts through the PD references, can raise the foot; true keeps it.
  bool keeps_rules = false;
};

// The lift's clearance above an obstacle `height` m high (m).
inline double LiftClearance(const FootLiftParams& p, double height) {
  return p.height_gain > 0.0 ? std::max(p.clearance, p.height_gain * height) : p.clearance;
}

}  // namespace rabbit

#endif  // RABBIT_CONTROL_FOOT_LIFT_H_
