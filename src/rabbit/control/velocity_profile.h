// The desired average velocity V_d(t) that a walker scenario commands.
#ifndef RABBIT_CONTROL_VELOCITY_PROFILE_H_
#define RABBIT_CONTROL_VELOCITY_PROFILE_H_

#include <string>
#include <utility>
#include <vector>

namespace rabbit {

// The desired average velocity V_d(t), from points (t_s, v_m_s) sorted by time:
//   constant  one point (or V_d of the first point everywhere);
//   ramp      piecewise linear between the points, constant before the first and after the last;
//   steps     each point's value held from its time until the next point's.
struct VelocityProfile {
  enum class Kind { kConstant, kRamp, kSteps };
  Kind kind = Kind::kConstant;
  std::vector<std::pair<double, double>> points = {{0.0, 0.6}};
  double At(double t) const;
  // At least one point, finite, times ascending (strictly for ramps), velocities in (0, 3) m/s.
  bool IsValid(std::string* error) const;
};
const char* VelocityProfileKindName(VelocityProfile::Kind kind);

}  // namespace rabbit

#endif  // RABBIT_CONTROL_VELOCITY_PROFILE_H_
