// [controller.slope]: the keys of the walker's slope adaptation
// (rabbit/control/slope_adaptation.h).
#ifndef RABBIT_SCENARIO_SLOPE_KEYS_H_
#define RABBIT_SCENARIO_SLOPE_KEYS_H_

#include "rabbit/control/slope_adaptation.h"
#include "rabbit/io/toml_reader.h"

namespace rabbit {

// Reads the table over the defaults in *p; a bad value fails naming its key (InputError).
void ReadSlopeKeys(TomlReader r, SlopeParams* p);

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_SLOPE_KEYS_H_
