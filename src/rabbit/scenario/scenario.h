// A single-run scenario file for `rabbit simulate` (TOML; see README "Scenario files").
#ifndef RABBIT_SCENARIO_SCENARIO_H_
#define RABBIT_SCENARIO_SCENARIO_H_

#include <memory>
#include <string>

#include "rabbit/contact/actuator.h"
#include "rabbit/contact/contact.h"
#include "rabbit/contact/terrain.h"
#include "rabbit/control/basic_controllers.h"
#include "rabbit/gait/gait_walk.h"
#include "rabbit/model/params.h"
#include "rabbit/sim/simulator.h"

namespace rabbit {

class TomlReader;

enum class ControllerKind { kPassive, kPdHold, kPragmatic };

struct Scenario {
  std::string file;
  std::string name;
  std::string description;
  ModelParams model;
  ContactParams contact;
  ActuatorParams actuator;
  Terrain terrain;
  SimOptions options;
  Vec7 q0 = Vec7::Zero();
  Vec7 qd0 = Vec7::Zero();
  ControllerKind controller = ControllerKind::kPassive;
  PdHoldParams pd_hold;
  GaitSpec walking;              // kPragmatic: the rules and the documented walking start
  std::string expected_outcome;  // empty: any outcome passes
};

// Reads and validates a scenario file. Throws InputError naming the file, line and key.
Scenario LoadScenario(const std::string& path);

// Reads a [model] table (all ModelParams fields, optionally `file = "other.toml"` whose [model]
// table gives the base values). Validates the result.
ModelParams ReadModelParams(TomlReader* table);
// Reads a model file: a TOML file with a [model] table.
ModelParams LoadModelFile(const std::string& path);

std::unique_ptr<Controller> MakeController(const Scenario& scenario);

// Names that become file or folder names: letters, digits, '.', '_', '-'; no "..".
bool IsSafeName(const std::string& name);

// The simulation set-up a scenario describes, on `model` (built from scenario.model; it must
// outlive the set-up).
SimSetup MakeSimSetup(const Scenario& scenario, const Model* model);

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_SCENARIO_H_
