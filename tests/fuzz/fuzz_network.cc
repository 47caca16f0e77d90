// Fuzz target: trained CMAC networks (rabbit-cmac/1 CSV) through ReadCmacFile, and one evaluation
// of what it accepts (a network that reads must be usable).
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

#include "fuzz_util.h"
#include "rabbit/io/error.h"
#include "rabbit/learn/network_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = rabbit_fuzz::Dir().Write("network-input.csv", data, size);
  std::map<std::string, std::string> metadata;
  try {
    const rabbit::Cmac cmac = rabbit::ReadCmacFile(path, &metadata);
    // Both edges and the middle of the range, and outside it (clamped).
    const rabbit::CmacOptions& o = cmac.options();
    for (const double x : {o.x_min, 0.5 * (o.x_min + o.x_max), o.x_max, o.x_max + 1.0}) {
      (void)cmac.Query(x);
    }
  } catch (const rabbit::InputError& e) {
    rabbit_fuzz::Refused(e);
  }
  return 0;
}
