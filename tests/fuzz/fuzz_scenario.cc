// Fuzz target: scenario and suite files (TOML) through LoadSuite, which reads a single scenario as
// a suite of one, and everything they name (models, gaits, networks, FLL, overlays of the shipped
// tree). Any input must load or throw rabbit::InputError; anything else is a finding.
#include <cstddef>
#include <cstdint>

#include "fuzz_util.h"
#include "rabbit/io/error.h"
#include "rabbit/scenario/suite.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = rabbit_fuzz::Dir().Write("scenarios/input.toml", data, size);
  try {
    rabbit::LoadSuite(path);
  } catch (const rabbit::InputError&) {
  }
  return 0;
}
