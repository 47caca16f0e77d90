// Fuzz target: the gait database's CSV files. Every input is read both as a gait file and as an
// index.csv (the two share the CSV layer, and a corpus entry of one kind mutates into the other).
#include <cstddef>
#include <cstdint>

#include "fuzz_util.h"
#include "rabbit/gait/gait_database.h"
#include "rabbit/io/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = rabbit_fuzz::Dir().Write("gaits-input.csv", data, size);
  try {
    rabbit::ReadGaitFile(path);
  } catch (const rabbit::InputError& e) {
    rabbit_fuzz::Refused(e);
  }
  try {
    rabbit::ReadGaitIndex(path);
  } catch (const rabbit::InputError& e) {
    rabbit_fuzz::Refused(e);
  }
  return 0;
}
