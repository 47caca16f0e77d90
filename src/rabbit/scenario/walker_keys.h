// Reading the walker's [controller] table (type = "fuzzy_cmac") of a scenario.
#ifndef RABBIT_SCENARIO_WALKER_KEYS_H_
#define RABBIT_SCENARIO_WALKER_KEYS_H_

#include <string>

#include "rabbit/io/toml_reader.h"
#include "rabbit/scenario/scenario.h"

namespace rabbit {

// Reads the walker's keys over its preset (walker_presets.h) into s->walker (and s->chapter_walker
// for a "chapter" baseline), with the gait pattern's files, the start gait, the per-gait settings
// and the baselines. database_override (`--gaits DIR`, empty: none) replaces the database the
// table names. Bad values throw InputError naming the file, line and key.
void ReadFuzzyCmac(TomlReader* t, Scenario* s, const std::string& database_override);

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_WALKER_KEYS_H_
