// Fuzz target: TS-FIS definitions in FLL through ParseFll (fuzzylite's importer, then the project's
// checks and compilation). Any input must compile or throw rabbit::InputError.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_util.h"
#include "rabbit/io/error.h"
#include "rabbit/learn/fll.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    rabbit::ParseFll(text, "input.fll");
  } catch (const rabbit::InputError& e) {
    rabbit_fuzz::Refused(e);
  }
  return 0;
}
