// Fuzz target: a gait database's walker.csv (per-gait walker settings) through ReadWalkerSettings.
#include <cstddef>
#include <cstdint>

#include "fuzz_util.h"
#include "rabbit/gait/walker_settings.h"
#include "rabbit/io/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = rabbit_fuzz::Dir().Write("walker-input.csv", data, size);
  try {
    rabbit::ReadWalkerSettings(path);
  } catch (const rabbit::InputError& e) {
    rabbit_fuzz::Refused(e);
  }
  return 0;
}
