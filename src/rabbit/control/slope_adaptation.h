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
//                  gives too slowly when a downhill keeps accelerating the robot.
// With enabled = false every output is 0 (the walker is unchanged).
#ifndef RABBIT_CONTROL_SLOPE_ADAPTATION_H_
#define RABBIT_CONTROL_SLOPE_ADAPTATION_H_

#include <limits>
#include <string>

#include "rabbit/contact/terrain.h"
#include "rabbit/model/model.h"

namespace rabbit {

// Defaults: the best of the measured sets on the training suite scenarios/train/slope.toml
// (docs/design.md, "Slope adaptation"); the adaptation is off unless enabled.
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
  bool IsValid(std::string* error) const;
};

// The grade (rad, positive descending toward +x) of the line through two contact points, the
// landing foot and the other; NaN when they are less than min_baseline apart along x.
double MeasuredGrade(const Vec2& landing, const Vec2& other, double min_baseline);

// The grade (rad, positive descending toward +x) of the ground profile between x_from and x_to
// (x_to > x_from), the rises of its vertical steps removed; NaN when they are less than 1 cm apart.
double GradeAhead(const GroundProfile& ground, double x_from, double x_to);

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
  // Change of q0_d (rad, <= 0) at a touchdown with stride velocity v_m and desired v_d.
  double OvershootCorrection(double v_m, double v_d) const;

 private:
  SlopeParams p_;
  double slope_ = 0.0;
};

}  // namespace rabbit

#endif  // RABBIT_CONTROL_SLOPE_ADAPTATION_H_
