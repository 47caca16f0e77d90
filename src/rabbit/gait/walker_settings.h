// Per-gait walker settings of a gait database (walker.csv beside reference/ and networks/), keyed
// by gait name: what the Fuzzy-CMAC walker needs per reference gait beyond the gait file itself.
//   name,rule_share
//   vm_0.30,1
//   ...
// rule_share in [0, 1]: the share of the gait's swing and stance knee walked by its own pragmatic
// rules instead of PD tracking of its pattern (WalkerParams::rule_share). A gait the file does not
// list has the defaults (rule_share 0: the chapter's walker). Made by `rabbit gaits build` from the
// targets' [gait.walker] tables.
#ifndef RABBIT_GAIT_WALKER_SETTINGS_H_
#define RABBIT_GAIT_WALKER_SETTINGS_H_

#include <map>
#include <string>
#include <vector>

namespace rabbit {

constexpr const char* kWalkerSettingsFile = "walker.csv";

struct GaitWalkerSettings {
  double rule_share = 0.0;  // in [0, 1]
  bool operator==(const GaitWalkerSettings& o) const { return rule_share == o.rule_share; }
};

// The columns of walker.csv after `name`, in file order.
const std::vector<std::string>& WalkerSettingColumns();

// Writes the file (atomic), rows in the map's (name) order.
void WriteWalkerSettings(const std::map<std::string, GaitWalkerSettings>& settings,
                         const std::string& path);
// Reads the file. Throws InputError (file, line, column) for unknown or missing columns, an
// empty, unsafe or repeated name, or a value out of range.
std::map<std::string, GaitWalkerSettings> ReadWalkerSettings(const std::string& path);

// The settings of a database directory: its walker.csv, or none (every gait at the defaults) when
// the database has no such file.
std::map<std::string, GaitWalkerSettings> ReadDatabaseWalkerSettings(const std::string& database);

}  // namespace rabbit

#endif  // RABBIT_GAIT_WALKER_SETTINGS_H_
