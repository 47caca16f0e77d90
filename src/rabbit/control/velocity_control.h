// The walker's velocity control: one update of the desired trunk pitch q0_d per step (chapter
// eqs. 19-20), and, beyond the chapter, speed transitions led by the trunk
// (docs/design/velocity-control.md, "Velocity control").
//
// The chapter's law, at each touchdown with a measured step:
//   q0_d(n+1) = q0_d(n) + K_P (V_d - V_M) + K_V d/dt (V_d - V_M),
// the derivative being the change of the error over the last step divided by t_step, and q0_d
// clamped to [q0_d_min, q0_d_max].
//
// With `enabled` the walker acts on a command V_c instead of V_d, and the trunk leads the change:
//   rate limit    V_c moves toward V_d by at most v_d_rate per touchdown (the FIS and the law
//                 above see V_c), so that a large change does not swap the gait pattern to one
//                 far from the current speed in one step;
//   feed-forward  every change of V_c moves q0_d at once by feedforward_gain (P(V_c) - P(V_c')),
//                 V_c' the previous command, where P is the trunk pitch of the reference gaits as
//                 a function of their measured speed (the gait database's q0_d and V_M), made
//                 non-decreasing (pool-adjacent-violators) and interpolated linearly, constant
//                 beyond its ends. The feedback law then removes what the map leaves; its
//                 derivative term acts on V_M alone (-K_V dV_M/dt), so that a change of the
//                 command is answered by the feed-forward only, not kicked twice;
//   start         with start_at_map, the first update after the warm-up sets q0_d = P(V_c).
// P is the gaits' map, or a map given as points (pitch_map), e.g. the pitches the walker itself
// settles at (docs/design/velocity-control.md, "Velocity control").
//
// Gait shift (gait_shift_gain > 0; with the chapter's law): while the command V_c is below
// gait_shift_below, the law above moves an effort u instead of q0_d, and q0_d = clamp(u,
// q0_d_min, q0_d_max); u may go below the floor by at most gait_shift_max / gait_shift_gain, and
// that part, u - q0_d (rad, <= 0), moves the gait pattern instead: the FIS's velocity input is
// shifted by gait_shift_gain (u - q0_d) m/s. Split-range control: with the pitch at its floor and
// the stride too fast, the blend moves toward the slowest gait; when the error turns, the shift
// unwinds before the pitch leaves the floor. At the slow end the blend of the slowest gait (walked
// by its rules) with the next (tracked) walks faster than either, at any pitch in the range
// (docs/design/velocity-control.md, "Velocity control"). At or above gait_shift_below, u = q0_d (no
// shift). Where the walker's rule gait choice takes the shift's place (SetShiftIdle), the shift
// moves nothing; with idle_shift_windup false u stops at the floor there and the stored shift is
// dropped, so that the pitch rises at the first update whose error asks for it (after a drop to
// 0.30-0.37 m/s the effort wound below the floor held q0_d there for several steps while the
// stride ran 0.05-0.06 m/s slow).
//
// Drops (enabled only). A drop starts at a touchdown where the speed profile has stepped down by
// more than drop_min since the previous one, with V_d below V_c, and lasts until V_c has reached
// V_d (a command lowered by the slope brake or for an obstacle's approach is no drop). In a drop,
// v_d_rate_down (m/s per step, > 0) takes the place of v_d_rate where V_c is at most
// v_d_rate_down_below (above it, among the fast rule-walked gaits, v_d_rate stays); with
// drop_gap > 0, V_c does not go below V_M - drop_gap (it waits for the measured stride, so that
// the pattern does not reach a gait far slower than the robot); and for drop_no_raise touchdowns
// from each decrease of V_c the law may lower q0_d but not raise it (a stumble's slow stride is
// not answered by a lean forward that throws the robot past the new speed)
// (docs/design/velocity-control.md, "Velocity control"). In a drop, and for drop_floor_steps
// touchdowns from each decrease of V_c, q0_d does not go below the pitch the walker settles at
// for the command V_d (the settled map, or the pitch map without one) less drop_floor_margin; a
// higher command since (a rise, an obstacle's approach speed) does not raise the floor:
// the slower gait's pattern brakes the robot a few steps after the pitch has leaned back, and a
// pitch leaned past the new speed's then stops it (docs/design/velocity-control.md, "The drop's
// pitch floor").
//
// Rises (enabled only). A rise starts at a touchdown where the speed profile's V_d has stepped up
// since the previous one, with V_d above V_c and no slope, obstacle or step command moving it
// (V_d is the profile's own), and lasts while that holds; in a rise the feed-forward of each
// increase of V_c uses feedforward_gain + feedforward_rise_extra: the gait blends walked at
// 0.55-0.8 m/s need a few degrees more pitch than the gaits' map gives
// (docs/design/velocity-control.md, "Velocity control"). In a rise, v_d_rate_up (> 0) takes the
// place of v_d_rate for the increases of V_c.
//
// With law = kStepMap the feedback law above gives way to the identified step-to-step map
// (step_map_control.h), which chooses q0_d at each update; the rate limit still applies.
#ifndef RABBIT_CONTROL_VELOCITY_CONTROL_H_
#define RABBIT_CONTROL_VELOCITY_CONTROL_H_

#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "rabbit/control/step_map_control.h"

namespace rabbit {

// The feedback law of the q0_d update: the chapter's incremental law, or the identified
// step-to-step map (step_map_control.h).
enum class VelocityLaw { kChapter, kStepMap };

struct VelocityControlParams {
  bool enabled = false;  // false: the chapter's law alone (V_c = V_d)
  // Defaults: the best of the variants measured on the training families
  // (docs/design/velocity-control.md).
  double v_d_rate = 0.1;          // m/s per step: the largest change of V_c at a touchdown
  double feedforward_gain = 0.5;  // share of the map's pitch change applied at once
  // Added to feedforward_gain where V_c rises (0: the same share both ways, bit for bit).
  double feedforward_rise_extra = 0.0;
  // The rate of V_c in a rise of the profile's own V_d (m/s per step; 0: v_d_rate, the law bit for
  // bit): the commands of the slope, obstacle and step handling keep v_d_rate.
  double v_d_rate_up = 0.0;
  // The map P as (V in m/s, q0_d in rad) points (made non-decreasing); empty: the reference
  // gaits' (measured V_M, q0_d) from the gait database.
  std::vector<std::pair<double, double>> pitch_map;
  // At the first update after the warm-up, q0_d starts at P(V_c) instead of the start gait's.
  bool start_at_map = true;
  // The walker's own settled pitch S as (V in m/s, q0_d in rad) points (made non-decreasing;
  // empty: none). Where the walker asks for it (UseStartMap), the first update sets q0_d = S(V_c)
  // instead of P(V_c); with settled_feedforward_gain > 0 the changes of V_c in a rise or a drop of
  // the profile's own V_d lean by that share of S's change instead of feedforward_gain (and
  // feedforward_rise_extra) of P's. Every other change (the slope, obstacle and step commands)
  // keeps P.
  std::vector<std::pair<double, double>> settled_pitch_map;
  // m: the walker asks for S at the start only when the terrain from the back foot to this far
  // beyond the front foot is level ground without an obstacle, a step or a change of grade (0:
  // always).
  double settled_start_clear = 0.0;
  double settled_feedforward_gain = 0.0;  // 0: off, P for every change (the law bit for bit)
  double settled_rise_extra = 0.0;        // added to it for the increases of V_c in a rise
  // Gait shift: m/s of the FIS's velocity input per rad of the law's pitch below the q0_d floor
  // (0: off, the law as above bit for bit), the largest shift (m/s), and the command (m/s) from
  // which on there is none.
  double gait_shift_gain = 0.0;
  double gait_shift_max = 0.1;
  double gait_shift_below = 0.4;
  // Where the shift is idle (SetShiftIdle: the walker's rule gait choice takes its place while
  // the command holds), true (the default, the law bit for bit) still lets the effort go below
  // the floor, where it moves nothing and must unwind before q0_d can rise; false stops the
  // effort at the floor there and drops the stored shift.
  bool idle_shift_windup = true;
  // Drops: the rate while V_c decreases (0: v_d_rate; v_d_rate 0 is no limit either way), the
  // largest gap below the measured stride V_M that a decreasing V_c may open (m/s, 0: off), and the
  // touchdowns after a decrease of V_c during which the law does not raise q0_d (0: off). All off
  // (and v_d_rate_down_below at any value): the law as above bit for bit.
  double drop_min = 0.0;  // m/s: a step down of the profile larger than this starts a drop
  double v_d_rate_down = 0.0;
  double v_d_rate_down_below = 3.0;  // m/s: the V_c from which down v_d_rate_down applies
  double drop_gap = 0.0;
  int drop_no_raise = 0;
  // The drop's pitch floor: touchdowns from each decrease of V_c during which it holds (0: off,
  // the law bit for bit) and its margin below the map's pitch at V_d (rad).
  int drop_floor_steps = 0;
  double drop_floor_margin = 0.0;
  // law = "step_map": the step-to-step map chooses q0_d at each update instead of the law above
  // (the rate limit still applies when enabled; the feed-forward and start_at_map do not: the
  // map's q* takes their place).
  VelocityLaw law = VelocityLaw::kChapter;
  StepMapParams step_map;
  bool IsValid(std::string* error) const;
};

// A key of VelocityControlParams with a closed range: its name (under velocity_control), its
// member, the range and the unit its message gives it. IsValid and the scenario's key reader both
// check these, so a range is written once.
struct VelocityControlRange {
  const char* key;
  double VelocityControlParams::*field;
  double lo, hi;
  const char* unit;  // appended to "must be in [lo, hi]"
};
const std::vector<VelocityControlRange>& VelocityControlRanges();

// The reference gaits' trunk pitch against speed, non-decreasing (see above).
class PitchMap {
 public:
  PitchMap() = default;
  // points: (V_M in m/s, q0_d in rad) of each gait, any order; non-finite points are refused
  // (std::invalid_argument). An empty map is 0 everywhere.
  explicit PitchMap(std::vector<std::pair<double, double>> points);
  double At(double v) const;
  const std::vector<std::pair<double, double>>& points() const { return points_; }

 private:
  std::vector<std::pair<double, double>> points_;  // sorted by speed, pitch non-decreasing
};

// Pool-adjacent-violators: the non-decreasing sequence nearest y in least squares (equal
// weights).
std::vector<double> NonDecreasingFit(const std::vector<double>& y);

class VelocityControl {
 public:
  // k_p in rad per m/s, k_v in rad per m/s^2, the q0_d range and its start value in rad.
  VelocityControl(const VelocityControlParams& params, double k_p, double k_v, double q0_d_min,
                  double q0_d_max, double q0_d_initial, PitchMap map);
  // At each touchdown, before Update: the command V_c for the coming step (V_d itself when not
  // enabled). The first call starts V_c at v_d. v_m: the measured stride (m/s; NaN: unknown), used
  // by drop_gap; v_profile: the speed profile's V_d before the slope, obstacle and step handling
  // moved it (NaN: v_d), whose steps down start a drop.
  double Command(double v_d, double v_m = std::numeric_limits<double>::quiet_NaN(),
                 double v_profile = std::numeric_limits<double>::quiet_NaN());
  // The law at a touchdown whose step was measured (V_M in m/s, t_step in s) outside the warm-up:
  // returns the new q0_d. `extra` (rad) joins the step's change of q0_d before the clamp (the
  // slope adaptation's braking); the first update with start_at_map sets q0_d = P(V_c) and
  // ignores it.
  double Update(double v_m, double t_step, double extra = 0.0);
  double q0_d() const { return q0_d_; }
  // Before the first update: whether it takes the settled map (settled_pitch_map) rather than the
  // pitch map. No effect without a settled map or once started.
  void UseStartMap(bool use) { use_start_map_ = use; }
  bool started() const { return started_; }
  double command() const { return v_c_; }
  // Whether the gait shift is idle at the coming updates (idle_shift_windup); false until set.
  void SetShiftIdle(bool idle) { shift_idle_ = idle; }
  // The shift of the FIS's velocity input (m/s): the step map's, or with the chapter's law the
  // gait shift (0 when off).
  double FisOffset() const {
    return p_.law == VelocityLaw::kStepMap ? step_map_.fis_offset() : p_.gait_shift_gain * excess_;
  }

 private:
  VelocityControlParams p_;
  double k_p_, k_v_, q0_d_min_, q0_d_max_;
  PitchMap map_;
  PitchMap settled_map_;  // empty: none
  bool use_start_map_ = false;
  StepMapControl step_map_;
  double q0_d_;
  double v_c_ = 0.0;
  bool have_command_ = false;
  double pending_ff_ = 0.0;  // feed-forward of command changes not yet applied (rad)
  double last_error_ = 0.0;  // V_c - V_M at the previous update
  double last_v_m_ = 0.0;    // V_M at the previous update
  bool have_error_ = false;
  bool started_ = false;      // the first update has been made
  bool dropping_ = false;     // a drop is under way
  bool rising_ = false;       // a rise of the profile's own V_d is under way
  double last_source_ = 0.0;  // the profile's V_d at the previous call
  int since_drop_ = -1;       // touchdowns since V_c last decreased (-1: never)
  double last_v_d_ = 0.0;     // V_d at the last command (m/s)
  double drop_v_d_ = 0.0;     // V_d at the last decrease of V_c in a drop (m/s)
  bool shift_idle_ = false;   // the walker's gait choice holds in the gait shift's place
  double excess_ = 0.0;       // gait shift: the effort u below the q0_d floor, u - q0_d (rad, <= 0)
};

}  // namespace rabbit

#endif  // RABBIT_CONTROL_VELOCITY_CONTROL_H_
