// What the walker reads from the known terrain at a touchdown (beyond the chapter): the change of
// grade over the coming step, and the speed command that the terrain asks for in place of V_d.
//
// The speed command stacks three mechanisms, in this order (docs/design/velocity-control.md):
//   1. the slope adaptation moves V_d with the grades ahead (V_d itself on flat ground);
//   2. the step planner raises it to its approach speed near an obstacle;
//   3. near a step up or down, the step handling's approach speed replaces it.
// The velocity control then rate-limits the result (VelocityControl::Command).
#ifndef RABBIT_CONTROL_TERRAIN_COMMAND_H_
#define RABBIT_CONTROL_TERRAIN_COMMAND_H_

#include "rabbit/contact/terrain.h"
#include "rabbit/control/slope_adaptation.h"
#include "rabbit/control/step_planner.h"
#include "rabbit/control/terrain_steps.h"
#include "rabbit/model/model.h"

namespace rabbit {

struct GradeView {
  // rad: the profile's grade over the coming step (about as long as the last one, l_step clamped
  // to [0.15, 0.6] m) less its grade between the feet.
  double change = 0.0;
  // Neither grade is non-zero (the ground between the feet and over the coming step is level).
  bool level = true;
};

// The grades around a touchdown of `landing` with the other foot at `other_foot` (m). Without a
// terrain, or with the feet within 1 cm of each other, no change and level ground.
GradeView GradeAround(const Terrain* terrain, const Vec2& landing, const Vec2& other_foot,
                      double l_step);

// Whether the terrain from x_from to x_to (m) is open level ground: flat, one segment of the
// ground's profile (no step or change of grade), and no obstacle. True without a terrain.
bool OpenLevelGround(const Terrain* terrain, double x_from, double x_to);

// The speed command (m/s) the terrain asks for at this touchdown, before the velocity control's
// rate limit; v_d itself without a terrain.
double TerrainSpeedCommand(const Terrain* terrain, const SlopeAdaptation& slope,
                           const StepPlannerParams& planner, const TerrainSteps& steps, double v_d,
                           const Vec2& landing, const Vec2& other_foot);

}  // namespace rabbit

#endif  // RABBIT_CONTROL_TERRAIN_COMMAND_H_
