// Slope adaptation for the Fuzzy-CMAC walker (beyond the chapter; keys of [controller.slope]).
//
// Perception: at each support exchange the two feet are on the ground; the line through their
// contact points gives the local grade
//   s_meas = atan2(y_other - y_landing, x_landing - x_other)
// (rad, positive when the ground descends toward +x, the sign of the terrain's slope_deg). The
// estimate follows it through a first-order filter over steps,
//   s = s + filter (clamp(s_meas, +-slope_max) - s),
// skipping a step whose feet are less than min_baseline apart along x (the line is ill-defined).
// With preview > 0 the reading also anticipates a change of grade known from the ground profile
// (as obstacles and steps are known): the grade of the profile over the coming step (from the
// landing foot to one step length ahead) less its grade between the two feet, steps' rises removed,
//   s_meas = s_feet + preview (s_ahead - s_between),
// so that the reactions start at the touchdown before a change of grade instead of a step after.
// On flat ground (and a uniform slope_deg, simulated in the slope's frame) both terrain grades
// are exactly 0 and the reading is the feet's alone, bit for bit; along one ramp of a profile,
// or between the flat levels of steps, they are equal to rounding.
// Its reactions, each off at a zero gain (fis_gain and overshoot_gain are 0 by default):
//   trunk lean     q0_d gets -trunk_gain s (an uphill, s < 0, leans the trunk forward), within
//                  +-trunk_max: a feed-forward beside the velocity control's once-per-step
//                  integration, which alone leans a step or two late;
//   pattern frame  the thigh-frame gait pattern is queried with thigh angles measured from a
//                  direction tilted by frame_gain times the ground normal's angle from the
//                  vertical (-s, positive forward), so that steps keep their length along the
//                  ground (frame_gain = 1: the whole normal);
//   gait choice    the velocity given to the fuzzy system moves by fis_gain s (m/s per rad;
//                  negative: a shorter, slower gait downhill);
//   speed cap      at a touchdown whose stride V_M exceeds V_d by more than overshoot_margin, q0_d
//                  moves back by overshoot_gain times the excess (rad per m/s), within the
//                  walker's q0_d range: a braking lean that the velocity control's small gain
//                  gives too slowly when a downhill keeps accelerating the robot;
//   speed command  the command the walker acts on (V_d, before the velocity control's rate limit)
//                  is raised by uphill_boost times the steepest uphill grade, and lowered by
//                  downhill_brake times the steepest downhill grade, of the known ground profile's
//                  pieces from the landing foot to speed_lookahead ahead (m/s per rad): the robot
//                  gathers speed before an uphill begins and keeps it on the climb, and slows
//                  down with shorter steps before and on a downhill. It acts through the velocity
//                  control (rate limit, pitch feed-forward) and the fuzzy system's lead. Flat
//                  pieces (flat ground, a uniform slope_deg simulated in its own frame, the levels
//                  of vertical steps) give exactly 0: V_d unchanged, bit for bit. The brake stops
//                  at speed_floor (or at V_d, when V_d is lower).
// With enabled = false every output is 0 (the walker is unchanged).
#ifndef RABBIT_CONTROL_SLOPE_ADAPTATION_H_
#define RABBIT_CONTROL_SLOPE_ADAPTATION_H_

#include <limits>
#include <string>
#include <utility>

#include "rabbit/contact/terrain.h"
#include "rabbit/model/model.h"

namespace rabbit {

// Defaults: the best of the measured sets on the training suite scenarios/train/slope.toml
// (docs/design/slope.md, "Slope adaptation"); the adaptation is off unless enabled.
struct SlopeParams {
  bool enabled = false;
  double filter = 1.0;            // weight of the newest step's grade in the estimate, (0, 1]
  double slope_max = 0.2;         // rad: bound of a measured grade (11.5 deg)
  double min_baseline = 0.1;      // m: feet closer than this along x give no grade
  double trunk_gain = 3.0;        // rad of q0_d per rad of slope
  double trunk_max = 0.2;         // rad: bound of the trunk lean
  double frame_gain = 1.5;        // share of the ground normal's tilt given to the pattern's frame
  double fis_gain = 0.0;          // m/s of the fuzzy system's velocity per rad of slope
  double overshoot_margin = 0.1;  // m/s of V_M above V_d before the speed cap acts
  double overshoot_gain = 0.0;    // rad of q0_d per m/s of excess
  double preview = 1.0;           // share of the known change of grade ahead, [0, 2]
  // The other foot's height as it was at its own touchdown (true) or as it is now (false).
  bool touchdown_heights = false;
  // Off here (the adaptive preset sets 1 and 3: walker_presets.cc).
  double uphill_boost = 0.0;     // m/s of the speed command per rad of uphill grade ahead
  double downhill_brake = 0.0;   // m/s taken off the speed command per rad of downhill grade ahead
  double speed_lookahead = 1.0;  // m ahead of the landing foot searched for those grades
  // m/s: the brake never takes the command below this (or below V_d, when V_d is lower); 0: off.
  double speed_floor = 0.0;
  bool IsValid(std::string* error) const;
};

// The grade (rad, positive descending toward +x) of the line through two contact points, the
// landing foot and the other; NaN when they are less than min_baseline apart along x.
double MeasuredGrade(const Vec2& landing, const Vec2& other, double min_baseline);

// The grade (rad, positive descending toward +x) of the ground profile between x_from and x_to
// (x_to > x_from), the rises of its vertical steps removed; NaN when they are less than 1 cm apart.
double GradeAhead(const GroundProfile& ground, double x_from, double x_to);

// The steepest uphill (first) and downhill (second) grades, rad and >= 0, of the ground profile's
// pieces that overlap [x_from, x_to]; 0 when none ascends (descends): flat pieces give (0, 0).
std::pair<double, double> SteepestAhead(const GroundProfile& ground, double x_from, double x_to);

class SlopeAdaptation {
 public:
  explicit SlopeAdaptation(const SlopeParams& params);

  // At each support exchange, with the landing foot's and the other foot's positions, and the
  // known change of grade ahead (GradeAhead over the coming step less GradeAhead between the
  // feet; NaN or 0 when unknown: the feet alone).
  void OnTouchdown(const Vec2& landing, const Vec2& other,
                   double grade_change = std::numeric_limits<double>::quiet_NaN());
  // The filtered slope estimate, rad (0 before the first usable step, or when disabled).
  double slope() const { return slope_; }
  // Added to the trunk's pitch reference q0_d, rad.
  double TrunkOffset() const;
  // The tilt (rad, positive forward) of the direction the pattern's thigh angles are measured
  // from.
  double FrameAngle() const;
  // Added to the velocity the fuzzy system sees, m/s.
  double FisVelocityOffset() const;
  // The speed command for V_d with the ground profile ahead of the landing foot at x: V_d itself
  // when disabled, with zero gains, or when the pieces ahead are flat.
  double SpeedCommand(double v_d, const GroundProfile& ground, double x) const;
  // Change of q0_d (rad, <= 0) at a touchdown with stride velocity v_m and desired v_d.
  double OvershootCorrection(double v_m, double v_d) const;

 private:
  SlopeParams p_;
  double slope_ = 0.0;
};

}  // namespace rabbit

#endif  // RABBIT_CONTROL_SLOPE_ADAPTATION_H_
