// Fuzz target: tuning jobs (TOML) through LoadTuneJob, which also loads the suites they name (the
// shipped ones, "../../scenarios/tune_ramp.toml", resolve from the temporary directory).
#include <cstddef>
#include <cstdint>

#include "fuzz_util.h"
#include "rabbit/io/error.h"
#include "tune_job.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = rabbit_fuzz::Dir().Write("optimizers/jobs/input.toml", data, size);
  try {
    rabbit::LoadTuneJob(path);
  } catch (const rabbit::InputError& e) {
    rabbit_fuzz::Refused(e);
  }
  return 0;
}
