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

#include <Eigen/Core>

#include "rabbit/contact/terrain.h"

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
  // The lift's pace (0: off), in a swing the obstacle lift has raised. A joint past the
  // actuator's max_speed (8.378 rad/s) gets no torque at all, not even to brake, and a lift let go
  // of at once (the foot past the far edge: the knee's reference extends by 0.5-0.7 rad within a
  // few ms) runs the swing knee past it: the shin is flung forward and the step over lands
  // 0.2-0.3 m past the edge. So each joint's lift offset shrinks toward zero by at most
  // release_rate (rad/s), and while the lift offsets the references their rates are the lifted
  // references' own time derivative: the pattern's rates alone (plus the offset's) tell the knee
  // to extend at the pattern's pace while the lift holds it flexed, and it falls through the lift
  // onto the obstacle's near side (LimitLiftRelease; FuzzyCmacWalker::ApplyLift).
  double release_rate = 0.0;  // rad/s
  // Added to the clearance in the trailing leg's swing (an obstacle between the feet at its
  // touchdown; m, 0: the same clearance as the step over). The trailing foot starts low and close
  // behind the obstacle, lags the raised point, and without it came down on the obstacle's top.
  double trailing_clearance = 0.0;
};

// The lift's clearance above an obstacle `height` m high (m), in the trailing leg's swing or not.
inline double LiftClearance(const FootLiftParams& p, double height, bool trailing = false) {
  const double c =
      p.height_gain > 0.0 ? std::max(p.clearance, p.height_gain * height) : p.clearance;
  return trailing ? c + p.trailing_clearance : c;
}

// The lift's ramp (0..1) over obstacle o at swing foot abscissa x: in over p.ramp before
// x_start - p.lead, full to `trail` past the far edge, out over `release` (m).
inline double LiftRamp(const FootLiftParams& p, const Obstacle& o, double trail, double release,
                       double x) {
  const double lo = o.x_start - p.lead, hi = o.x_end() + trail;
  double a = 1.0;
  if (x < lo) a = p.ramp > 0.0 ? 1.0 - (lo - x) / p.ramp : 0.0;
  if (x > hi) a = release > 0.0 ? 1.0 - (x - hi) / release : 0.0;
  return std::clamp(a, 0.0, 1.0);
}

// The lift's offsets (hip, knee; rad) this period, `delta` as the lift asks them and `last` the
// previous period's, dt s before: with p.release_rate > 0, an offset shrinking toward zero (the
// lift letting go) moves by at most release_rate dt; one growing or changing sign is as asked.
inline Eigen::Vector2d LimitLiftRelease(const FootLiftParams& p, Eigen::Vector2d delta,
                                        const Eigen::Vector2d& last, double dt) {
  if (!(p.release_rate > 0.0 && dt > 0.0)) return delta;
  const double m = p.release_rate * dt;
  for (int j = 0; j < 2; ++j) {
    if (std::abs(delta[j]) < std::abs(last[j]) && delta[j] * last[j] >= 0.0) {
      delta[j] = std::clamp(delta[j], last[j] - m, last[j] + m);
    }
  }
  return delta;
}

}  // namespace rabbit

#endif  // RABBIT_CONTROL_FOOT_LIFT_H_
