// Fuzz target: the targets file of `rabbit gaits generate` (gaits/targets.toml) through
// ReadGaitTargets: [[gait]] targets, their [gait.bounds] and a top-level [bounds].
#include <cstddef>
#include <cstdint>

#include "fuzz_util.h"
#include "gait_targets.h"
#include "rabbit/io/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = rabbit_fuzz::Dir().Write("targets-input.toml", data, size);
  try {
    rabbit::ReadGaitTargets(path);
  } catch (const rabbit::InputError& e) {
    rabbit_fuzz::Refused(e);
  }
  return 0;
}
