// Fuzz target: parameter overlays (TOML [params] tables) through LoadParamOverlay.
#include <cstddef>
#include <cstdint>

#include "fuzz_util.h"
#include "rabbit/io/error.h"
#include "rabbit/scenario/params.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = rabbit_fuzz::Dir().Write("params-input.toml", data, size);
  try {
    rabbit::LoadParamOverlay(path);
  } catch (const rabbit::InputError& e) {
    rabbit_fuzz::Refused(e);
  }
  return 0;
}
