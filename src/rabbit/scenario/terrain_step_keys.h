// [controller.steps]: the keys of the walker's terrain-step handling
// (rabbit/control/terrain_steps.h).
#ifndef RABBIT_SCENARIO_TERRAIN_STEP_KEYS_H_
#define RABBIT_SCENARIO_TERRAIN_STEP_KEYS_H_

#include "rabbit/control/terrain_steps.h"
#include "rabbit/io/toml_reader.h"

namespace rabbit {

// Reads the table over the defaults in *p; a bad value fails naming its key (InputError).
void ReadTerrainStepKeys(TomlReader r, TerrainStepParams* p);

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_TERRAIN_STEP_KEYS_H_
