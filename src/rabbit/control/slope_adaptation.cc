#include "rabbit/control/slope_adaptation.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "rabbit/control/terrain_steps.h"

namespace rabbit {

bool SlopeParams::IsValid(std::string* error) const {
  const std::pair<const char*, double> bounded[] = {{"slope_max", slope_max},
                                                    {"min_baseline", min_baseline},
                                                    {"trunk_max", trunk_max},
                                                    {"overshoot_margin", overshoot_margin},
                                                    {"overshoot_gain", overshoot_gain},
                                                    {"preview", preview},
                                                    {"uphill_boost", uphill_boost},
                                                    {"downhill_brake", downhill_brake},
                                                    {"speed_lookahead", speed_lookahead},
                                                    {"speed_floor", speed_floor}};
  for (const auto& [name, value] : bounded) {
    if (!(std::isfinite(value) && value >= 0.0 && value <= 10.0)) {
      *error = std::string("slope.") + name + " must be in [0, 10]";
      return false;
    }
  }
  if (!(std::isfinite(filter) && filter > 0.0 && filter <= 1.0)) {
    *error = "slope.filter must be in (0, 1]";
    return false;
  }
  if (preview > 2.0) {
    *error = "slope.preview must be in [0, 2]";
    return false;
  }
  if (slope_max > 0.5 || trunk_max > 0.5) {
    *error = "slope.slope_max and slope.trunk_max must be <= 0.5 rad";
    return false;
  }
  const std::pair<const char*, double> gains[] = {
      {"trunk_gain", trunk_gain}, {"frame_gain", frame_gain}, {"fis_gain", fis_gain}};
  for (const auto& [name, value] : gains) {
    if (!(std::isfinite(value) && std::abs(value) <= 10.0)) {
      *error = std::string("slope.") + name + " must be in [-10, 10]";
      return false;
    }
  }
  return true;
}

double MeasuredGrade(const Vec2& landing, const Vec2& other, double min_baseline) {
  const double dx = landing.x() - other.x();
  if (!(std::abs(dx) >= min_baseline)) return std::nan("");
  // atan of the drop per metre toward +x, whichever foot is ahead.
  return std::atan((other.y() - landing.y()) / dx);
}

double GradeAhead(const GroundProfile& ground, double x_from, double x_to) {
  const double dx = x_to - x_from;
  if (!(dx >= 0.01)) return std::nan("");
  const double rise =
      ground.HeightAt(x_to) - ground.HeightAt(x_from) - RiseBetween(ground, x_from, x_to);
  return std::atan(-rise / dx);
}

std::pair<double, double> SteepestAhead(const GroundProfile& ground, double x_from, double x_to) {
  double up = 0.0, down = 0.0;
  const int last = ground.SegmentAt(x_to);
  for (int i = ground.SegmentAt(x_from); i <= last; ++i) {
    up = std::max(up, -ground.segment(i).slope);
    down = std::max(down, ground.segment(i).slope);
  }
  return {up, down};
}

SlopeAdaptation::SlopeAdaptation(const SlopeParams& params) : p_(params) {}

void SlopeAdaptation::OnTouchdown(const Vec2& landing, const Vec2& other, double grade_change) {
  if (!p_.enabled) return;
  double grade = MeasuredGrade(landing, other, p_.min_baseline);
  if (!std::isfinite(grade)) return;
  if (p_.preview > 0.0 && std::isfinite(grade_change)) grade += p_.preview * grade_change;
  slope_ += p_.filter * (std::clamp(grade, -p_.slope_max, p_.slope_max) - slope_);
}

double SlopeAdaptation::TrunkOffset() const {
  if (!p_.enabled) return 0.0;
  return std::clamp(-p_.trunk_gain * slope_, -p_.trunk_max, p_.trunk_max);
}

double SlopeAdaptation::FrameAngle() const { return p_.enabled ? -p_.frame_gain * slope_ : 0.0; }

double SlopeAdaptation::FisVelocityOffset() const {
  return p_.enabled ? p_.fis_gain * slope_ : 0.0;
}

double SlopeAdaptation::SpeedCommand(double v_d, const GroundProfile& ground, double x) const {
  if (!p_.enabled || (p_.uphill_boost == 0.0 && p_.downhill_brake == 0.0)) return v_d;
  const auto [up, down] = SteepestAhead(ground, x, x + p_.speed_lookahead);
  const double change = p_.uphill_boost * up - p_.downhill_brake * down;
  if (change == 0.0) return v_d;
  return std::max(v_d + change, std::min(v_d, p_.speed_floor));
}

double SlopeAdaptation::OvershootCorrection(double v_m, double v_d) const {
  if (!p_.enabled) return 0.0;
  const double excess = v_m - v_d - p_.overshoot_margin;
  return excess > 0.0 ? -p_.overshoot_gain * excess : 0.0;
}

}  // namespace rabbit
