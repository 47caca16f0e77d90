// [controller.velocity_control.step_map]: the keys of the step-to-step speed law
// (rabbit/control/step_map_control.h).
#ifndef RABBIT_SCENARIO_STEP_MAP_KEYS_H_
#define RABBIT_SCENARIO_STEP_MAP_KEYS_H_

#include "rabbit/control/step_map_control.h"
#include "rabbit/io/toml_reader.h"

namespace rabbit {

// Reads the table over the defaults in *p; a bad value fails naming its key (InputError).
void ReadStepMapKeys(TomlReader r, StepMapParams* p);

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_STEP_MAP_KEYS_H_
