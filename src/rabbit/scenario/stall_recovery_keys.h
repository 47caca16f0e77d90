// The keys of a walker's [controller.stall_recovery] table (rabbit/control/stall_recovery.h).
#ifndef RABBIT_SCENARIO_STALL_RECOVERY_KEYS_H_
#define RABBIT_SCENARIO_STALL_RECOVERY_KEYS_H_

#include "rabbit/control/stall_recovery.h"
#include "rabbit/io/toml_reader.h"

namespace rabbit {

// Reads every key of the table over p's values; an error names the key and its line.
void ReadStallRecovery(TomlReader r, StallRecoveryParams* p);

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_STALL_RECOVERY_KEYS_H_
