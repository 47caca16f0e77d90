#include "rabbit/control/velocity_profile.h"

#include <cmath>

namespace rabbit {

double VelocityProfile::At(double t) const {
  if (points.empty()) return std::nan("");
  if (kind == Kind::kConstant || t <= points.front().first) return points.front().second;
  for (size_t i = 1; i < points.size(); ++i) {
    const auto& [t1, v1] = points[i];
    if (t < t1) {
      const auto& [t0, v0] = points[i - 1];
      if (kind == Kind::kSteps) return v0;
      return v0 + (v1 - v0) * (t - t0) / (t1 - t0);
    }
  }
  return points.back().second;
}

bool VelocityProfile::IsValid(std::string* error) const {
  if (points.empty()) {
    *error = "the velocity profile has no points";
    return false;
  }
  for (size_t i = 0; i < points.size(); ++i) {
    const auto& [t, v] = points[i];
    if (!std::isfinite(t) || !std::isfinite(v)) {
      *error = "velocity point " + std::to_string(i + 1) + " is not finite";
      return false;
    }
    if (!(v > 0.0 && v < 3.0)) {
      *error = "velocity point " + std::to_string(i + 1) + ": V_d must be in (0, 3) m/s";
      return false;
    }
    if (i > 0) {
      const double before = points[i - 1].first;
      if (t < before || (kind == Kind::kRamp && t == before)) {
        *error = "velocity point " + std::to_string(i + 1) + ": times must increase";
        return false;
      }
    }
  }
  return true;
}

const char* VelocityProfileKindName(VelocityProfile::Kind kind) {
  switch (kind) {
    case VelocityProfile::Kind::kRamp:
      return "ramp";
    case VelocityProfile::Kind::kSteps:
      return "steps";
    case VelocityProfile::Kind::kConstant:
      break;
  }
  return "constant";
}

}  // namespace rabbit
