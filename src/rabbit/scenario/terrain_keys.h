// [terrain] and [[push]] of a scenario: the ground (a uniform slope, a ground profile with its
// vertical steps, obstacles) and the trunk pushes.
#ifndef RABBIT_SCENARIO_TERRAIN_KEYS_H_
#define RABBIT_SCENARIO_TERRAIN_KEYS_H_

#include <vector>

#include "rabbit/contact/terrain.h"
#include "rabbit/io/toml_reader.h"
#include "rabbit/model/params.h"
#include "rabbit/sim/simulator.h"

namespace rabbit {

// [terrain]: a uniform slope (slope_deg, the tilted-gravity frame, into model->slope) or a ground
// profile (slopes = [{x_start, slope_deg}, ...]), not both; vertical steps (steps = [{x_start,
// rise}, ...]) on the profile; obstacles on flat ground. Bad values fail naming their key.
Terrain ReadTerrain(TomlReader t, ModelParams* model);

// The scenario's [[push]] tables, in order; bad values fail naming their key.
std::vector<TrunkPush> ReadPushes(TomlReader* root);

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_TERRAIN_KEYS_H_
