// What the scenario's key readers (scenario.cc, terrain_keys.cc, controller_keys.cc,
// walker_keys.cc) share: degrees at the edges, and the check of a parameter struct.
#ifndef RABBIT_SCENARIO_KEYS_INTERNAL_H_
#define RABBIT_SCENARIO_KEYS_INTERNAL_H_

#include <cmath>
#include <string>

#include "rabbit/io/toml_reader.h"

namespace rabbit::keys_internal {

inline constexpr double kDeg = M_PI / 180.0;

// Any parameter struct with IsValid(std::string*): an invalid one fails the table.
template <typename Params>
void Validate(const TomlReader& t, const Params& params) {
  std::string error;
  if (!params.IsValid(&error)) t.Fail("", error);
}

}  // namespace rabbit::keys_internal

#endif  // RABBIT_SCENARIO_KEYS_INTERNAL_H_
