// Fuzz target: scenario and suite files (TOML) through LoadSuite, which reads a single scenario as
// a suite of one, and everything they name (models, gaits, networks, FLL of the shipped tree).
// Any input must load or throw rabbit::InputError; anything else is a finding. What loads must
// also set up (the model, the simulation set-up and the controller, without simulating): the
// readers' validation is the only check those constructors get from user input.
#include <cstddef>
#include <cstdint>
#include <memory>

#include "fuzz_util.h"
#include "rabbit/io/error.h"
#include "rabbit/model/model.h"
#include "rabbit/scenario/suite.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = rabbit_fuzz::Dir().Write("scenarios/input.toml", data, size);
  rabbit::Suite suite;
  try {
    suite = rabbit::LoadSuite(path);
  } catch (const rabbit::InputError& e) {
    rabbit_fuzz::Refused(e);
    return 0;
  }
  for (const rabbit::Scenario& scenario : suite.scenarios) {
    const rabbit::Model model(scenario.model);
    const rabbit::SimSetup setup = rabbit::MakeSimSetup(scenario, &model);
    (void)setup;
    // The walker's controller needs the gait library RunScenario builds (see MakeController).
    if (scenario.controller != rabbit::ControllerKind::kFuzzyCmac) {
      const std::unique_ptr<rabbit::Controller> controller = rabbit::MakeController(scenario);
    }
  }
  return 0;
}
