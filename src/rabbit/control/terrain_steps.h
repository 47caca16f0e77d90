// Terrain-step handling for the walker (beyond the chapter; keys of [controller.steps]).
//
// The walker knows the terrain's vertical steps as it knows its obstacles: the ground profile's
// breakpoints with a rise (the ground height ahead). At each support exchange, with the landing
// (front) foot at x_f and the other (back) foot at x_b:
//   slope reading  the slope adaptation's grade through the two contact points is measured with
//                  the landing foot's height less the rise of the steps between the feet, so a
//                  step is not read as a ramp (a 5 cm step under a 0.35 m step reads as 8 deg);
//   step-up lift   when a step up's face lies between the swing foot and the coming swing's
//                  predicted landing (x_f plus the last step's length) + reach, the walker's
//                  foot lift is armed and the swing foot is raised to at least the upper level
//                  + clearance from `lead` before the face to `trail` past it (ramped in over
//                  `ramp` and out over `release`, in the foot's x), as over an obstacle;
//   placement      with the step planner on, a step's face within its horizon is planned for as
//                  an obstacle: the last foot before it lands face_before short of the face and
//                  the step across lands face_after past it, so that the foot lands on the
//                  step, not at its edge, with a step of about the nominal length;
//   trunk lean     q0_d moves by up_lean (rad per m of rise) for a step up and by down_lean (rad
//                  per m of drop) for a step down, from the touchdown whose coming swing is
//                  predicted (the last step's length ahead) to cross the face, for `lean_steps`
//                  steps;
//   stance knee    for a coming swing that lands beyond a step down, the stance knee's
//                  reference flexes so that the leg shortens by knee_share times the drop
//                  (ramped in over knee_ramp_s from the touchdown): the hip comes down with the
//                  swing foot instead of falling onto the lower level; after a landing on the
//                  upper level of a step up the new stance knee starts flexed so that the leg is
//                  shorter by up_knee_share times the rise and extends over up_knee_ramp_s: the
//                  knee lifts the hip onto the step; with up_knee_by_hip the extension starts
//                  only once the hip has come to up_knee_at (m, negative: behind) from the new
//                  stance foot (Observe): a leg that extends while its foot is still well ahead
//                  of the hip pushes the hip back and up, and the robot stops short of the foot
//                  and rolls back;
//   approach       while a step up's (down's) face lies between the back foot and speed_before
//                  beyond the front foot, the walker acts on up_speed (down_speed) in place of
//                  V_d (through the velocity control's rate limit), the larger when both: at a
//                  V_d near 0.4 m/s the robot crosses too slowly to climb, and the planner's
//                  approach steps (the 0.6 m/s walk's) topple it; at 0.8 m/s it falls off a step
//                  down;
//   pitch hold     for hold_steps touchdowns from each landing whose step crossed a face, the
//                  velocity control leaves q0_d unchanged (that step's V_M is the climb's or the
//                  drop's).
// With enabled = false every output is neutral (the walker is unchanged bit for bit).
#ifndef RABBIT_CONTROL_TERRAIN_STEPS_H_
#define RABBIT_CONTROL_TERRAIN_STEPS_H_

#include <cmath>
#include <string>

#include "rabbit/contact/terrain.h"
#include "rabbit/model/model.h"

namespace rabbit {

// Defaults: the best of the measured sets on the training suite scenarios/train/steps.toml
// (docs/design/steps.md, "Steps and platforms"); off unless enabled (on in the adaptive preset).
struct TerrainStepParams {
  bool enabled = false;
  double reach = 0.05;           // m beyond the predicted landing: a face there is crossed
  double clearance = 0.04;       // m above the upper level, over a step up's face
  double lead = 0.10;            // m before the face at full height
  double trail = 0.03;           // m past the face at full height
  double ramp = 0.10;            // m over which the lift comes in before `lead`
  double release = 0.05;         // m over which it goes out after `trail`
  bool placement = true;         // plan the foot placement before a face (with the step planner)
  double face_before = 0.18;     // m: the last foot before a face lands this far short of it
  double face_after = 0.18;      // m: the step across lands this far past it
  double up_lean = 6.0;          // rad of q0_d per m of rise (forward for a step up)
  double down_lean = -4.0;       // rad of q0_d per m of drop (negative: back for a step down)
  int lean_steps = 2;            // steps the lean lasts
  double knee_share = 0.2;       // share of a drop taken by the stance knee before a step down
  double knee_ramp_s = 0.25;     // s: the knee's flexion comes in over this after the touchdown
  double up_knee_share = 1.0;    // share of a rise the stance knee extends through after a step up
  double up_knee_ramp_s = 0.25;  // s: the knee extends over this after landing on the upper level
  bool up_knee_by_hip = false;   // the extension waits for the hip to reach up_knee_at
  double up_knee_at = 0.0;       // m: the hip's x less the stance foot's that starts the extension
  // Off (0) here; the adaptive preset sets them (walker_presets.cc).
  double up_speed = 0.0;      // m/s: the speed asked for approaching a step up (0: V_d)
  double down_speed = 0.0;    // m/s: the same approaching a step down (0: V_d)
  double speed_before = 2.5;  // m: from a front foot this far before the face
  int hold_steps = 0;         // touchdowns from a face's crossing that leave q0_d unchanged
  double thigh_length = 0.40, shin_length = 0.47;  // m: the model's (set by the runner, not keys)
  bool IsValid(std::string* error) const;
};

// A step's face: where it is and its rise (+ up toward +x).
struct StepFace {
  bool found = false;
  double x = 0.0;     // m
  double rise = 0.0;  // m
};

// The sum of the rises of the steps crossed going from x_a to x_b (signed for that direction: a
// step up toward +x counts +rise from left to right, -rise from right to left). A step at x
// belongs to the ground beyond it (GroundProfile::SegmentAt).
double RiseBetween(const GroundProfile& ground, double x_a, double x_b);
// The first step whose face lies in (x_lo, x_hi]; found = false when none.
StepFace StepIn(const GroundProfile& ground, double x_lo, double x_hi);
// The knee angle (rad, <= 0, flexed) that makes a leg of thigh l1 and shin l2 shorter than
// straight by `shorten` (m, clamped to [0, l1 + l2 - |l1 - l2|)).
double KneeForShortening(double l1, double l2, double shorten);

class TerrainSteps {
 public:
  explicit TerrainSteps(const TerrainStepParams& params) : p_(params) {}
  bool enabled() const { return p_.enabled; }

  // At each support exchange (t, the landing foot's and the other foot's positions): arms the
  // lift, the lean and the stance knee for the coming step.
  void OnTouchdown(const Terrain& terrain, double t, const Vec2& landing, const Vec2& other);
  // The landing foot as the slope adaptation should see it: its height less the rise of the
  // steps between the other foot and it (unchanged when disabled).
  Vec2 LevelledLanding(const Terrain& terrain, const Vec2& landing, const Vec2& other) const;
  // Whether the coming swing crosses a step up's face (the foot lift is to be armed).
  bool LiftArmed() const { return p_.enabled && lift_face_.found; }
  // The lift's target height (absolute y) at swing foot abscissa x; -infinity when none.
  double LiftHeight(const Terrain& terrain, double foot_x) const;
  // The next face ahead of x within `horizon` as the step planner should see it: an obstacle
  // whose near edge is `margin_before` (the planner's) beyond where the last foot should land,
  // face_before short of the face, and whose length brings the step across face_after past it
  // with the planner's margin_after. Returns the distance to that near edge and sets *length;
  // +infinity (and *length untouched) when disabled, placement is off, or there is no face.
  double FaceAhead(const Terrain& terrain, double x, double horizon, double margin_before,
                   double margin_after, double* length) const;
  // The speed the walker is to act on for the coming step (m/s): up_speed (or down_speed) in
  // place of v_d while a step up's (down's) face lies between the back foot and speed_before
  // beyond the front foot, the larger of the two when both do; v_d when none does or that speed
  // is 0.
  double SpeedCommand(double v_d) const {
    return p_.enabled && approach_speed_ > 0.0 ? approach_speed_ : v_d;
  }
  // Whether the velocity control is to leave q0_d unchanged at this touchdown: hold_steps
  // touchdowns from the one that ends a step crossing a face.
  bool HoldsPitch() const { return p_.enabled && hold_left_ > 0; }
  // Added to q0_d, rad.
  double TrunkOffset() const { return p_.enabled && lean_left_ > 0 ? lean_ : 0.0; }
  // Each control period with the hip's x: starts a waiting extension (up_knee_by_hip).
  void Observe(double t, double hip_x);
  // Added to the stance knee's reference at t, rad (<= 0).
  double StanceKnee(double t) const;

 private:
  TerrainStepParams p_;
  StepFace lift_face_;                      // the step up the coming swing crosses
  double approach_speed_ = 0.0;             // m/s: 0 unless approaching a step
  int hold_left_ = 0;                       // touchdowns the hold still lasts
  double takeoff_ = NAN;                    // m: the swinging foot's x at the last touchdown
  int lean_left_ = 0;                       // touchdowns the lean still lasts
  double lean_ = 0.0;                       // rad
  double knee_from_ = 0.0, knee_to_ = 0.0;  // rad: the stance knee's ramp (<= 0)
  double knee_t0_ = 0.0, knee_ramp_ = 0.0;  // s: its start and length
  double knee_gate_x_ = NAN;                // m: the hip's x that starts the extension (NaN: none)
};

}  // namespace rabbit

#endif  // RABBIT_CONTROL_TERRAIN_STEPS_H_
