// Mass and geometry of the RABBIT biped (docs/design/model.md, chapter Table 1).
// All values SI. Defaults are the documented RABBIT values; every one can be overridden from a
// `[model]` TOML table (see scenario/scenario.h and docs/formats/model.md).
#ifndef RABBIT_MODEL_PARAMS_H_
#define RABBIT_MODEL_PARAMS_H_

#include <string>

namespace rabbit {

struct ModelParams {
  // Trunk: mass, centre of mass above the hip, inertia about its centre of mass, and its drawn
  // length (the trunk has no contact role; the length is for figures only).
  double trunk_mass = 12.0;
  double trunk_com = 0.20;
  double trunk_inertia = 1.33;
  double trunk_length = 0.625;
  // Thigh (each leg): mass, hip-to-knee length, centre of mass from the hip, inertia about CoM.
  double thigh_mass = 6.8;
  double thigh_length = 0.40;
  double thigh_com = 0.11;
  double thigh_inertia = 0.47;
  // Shin (each leg): mass, knee-to-foot length, centre of mass from the knee, inertia about CoM.
  double shin_mass = 3.2;
  double shin_length = 0.47;
  double shin_com = 0.24;
  double shin_inertia = 0.20;
  // Motor rotor inertia (motor side) and gear ratio: adds gear_ratio^2 * rotor_inertia to the
  // diagonal of each joint coordinate. Default 0, as in the chapter's ADAMS model.
  double rotor_inertia = 0.0;
  double gear_ratio = 50.0;
  // Gravitational acceleration (m/s^2). 0 switches gravity off.
  double gravity = 9.81;
  // Uniform ground slope (rad), positive when the ground descends toward +x. The simulation runs in
  // the slope-aligned frame (x along the ground, y normal to it), so the slope tilts gravity:
  // g = gravity * (sin slope, -cos slope). Exact for a uniform slope; obstacles stand on it.
  double slope = 0.0;

  // True when every parameter is finite and physically possible; otherwise fills *error with
  // the name of the first offending parameter.
  bool IsValid(std::string* error) const;
};

}  // namespace rabbit

#endif  // RABBIT_MODEL_PARAMS_H_
