// The [controller] table of a scenario but the walker's (walker_keys.h): which layers it is read
// from, and the passive, pd_hold and pragmatic controllers' keys.
#ifndef RABBIT_SCENARIO_CONTROLLER_KEYS_H_
#define RABBIT_SCENARIO_CONTROLLER_KEYS_H_

#include "rabbit/io/toml_reader.h"
#include "rabbit/scenario/scenario.h"

namespace rabbit {

// The controller type's name as the scenario files spell it.
const char* ControllerName(ControllerKind kind);

// [controller], merged over the layers (a suite's scenario over its defaults) unless a layer names
// a different `type` than a lower one: then it is read from the layers above that lower one only,
// since the lower layers' keys belong to another controller.
TomlReader ControllerTable(TomlReader* root);

// type = "passive" or "pd_hold" (the caller has checked the type), into s.
void ReadController(TomlReader t, Scenario* s);

// type = "pragmatic": the five rules, from a gait file (`gait`, relative to the scenario) and/or
// single keys; the walk starts from WalkingStartState.
void ReadPragmatic(TomlReader* t, Scenario* s);

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_CONTROLLER_KEYS_H_
