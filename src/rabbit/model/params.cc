#include "rabbit/model/params.h"

#include <cmath>
#include <utility>
#include <vector>

namespace rabbit {

bool ModelParams::IsValid(std::string* error) const {
  const std::vector<std::pair<const char*, double>> positive = {
      {"trunk_mass", trunk_mass},     {"trunk_inertia", trunk_inertia},
      {"trunk_length", trunk_length}, {"thigh_mass", thigh_mass},
      {"thigh_length", thigh_length}, {"thigh_inertia", thigh_inertia},
      {"shin_mass", shin_mass},       {"shin_length", shin_length},
      {"shin_inertia", shin_inertia}, {"gear_ratio", gear_ratio}};
  for (const auto& [name, value] : positive) {
    if (!std::isfinite(value) || value <= 0.0) {
      *error = std::string(name) + " must be a finite number > 0";
      return false;
    }
  }
  const std::vector<std::pair<const char*, double>> non_negative = {
      {"trunk_com", trunk_com},
      {"thigh_com", thigh_com},
      {"shin_com", shin_com},
      {"rotor_inertia", rotor_inertia},
      {"gravity", gravity}};
  for (const auto& [name, value] : non_negative) {
    if (!std::isfinite(value) || value < 0.0) {
      *error = std::string(name) + " must be a finite number >= 0";
      return false;
    }
  }
  if (!std::isfinite(slope) || std::abs(slope) >= 1.0) {
    *error = "slope must be finite and below 1 rad (57 deg) in magnitude";
    return false;
  }
  if (thigh_com > thigh_length) {
    *error = "thigh_com must not exceed thigh_length";
    return false;
  }
  if (shin_com > shin_length) {
    *error = "shin_com must not exceed shin_length";
    return false;
  }
  return true;
}

}  // namespace rabbit
