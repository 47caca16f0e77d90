#include "rabbit/gait/walker_settings.h"

#include <filesystem>

#include "rabbit/io/atomic_file.h"
#include "rabbit/io/csv.h"
#include "rabbit/io/csv_table.h"
#include "rabbit/io/error.h"

namespace rabbit {

const std::vector<std::string>& WalkerSettingColumns() {
  static const std::vector<std::string> columns = {"rule_share"};
  return columns;
}

void WriteWalkerSettings(const std::map<std::string, GaitWalkerSettings>& settings,
                         const std::string& path) {
  WriteFileAtomically(path, [&settings](std::ostream& out) {
    out << "name";
    for (const std::string& c : WalkerSettingColumns()) out << ',' << c;
    out << "\n";
    for (const auto& [name, s] : settings) {
      out << FormatCsvCell(name) << ',' << FormatCsvNumber(s.rule_share) << "\n";
    }
  });
}

std::map<std::string, GaitWalkerSettings> ReadWalkerSettings(const std::string& path) {
  const CsvTable table = CsvTable::Read(path, kWalkerFileLimits);
  const std::vector<std::string>& known = WalkerSettingColumns();
  for (const std::string& column : table.header()) {
    if (column == "name") continue;
    bool found = false;
    for (const std::string& k : known) found = found || k == column;
    if (!found) {
      throw InputError(path, 1, column, "unknown column (expected name and rule_share)");
    }
  }
  const size_t name_column = table.Column("name");
  const size_t share_column = table.Column("rule_share");
  std::map<std::string, GaitWalkerSettings> out;
  for (size_t r = 0; r < table.num_rows(); ++r) {
    const std::string name = table.Text(r, name_column);
    if (name.empty() ||
        name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                               "0123456789._-") != std::string::npos ||
        name.find("..") != std::string::npos) {
      throw InputError(path, table.line(r), "name",
                       "gait names use letters, digits, '.', '_' and '-' only");
    }
    GaitWalkerSettings s;
    s.rule_share = table.Number(r, share_column);
    if (!(s.rule_share >= 0.0 && s.rule_share <= 1.0)) {
      throw InputError(path, table.line(r), "rule_share", "must be in [0, 1]");
    }
    if (!out.emplace(name, s).second) {
      throw InputError(path, table.line(r), "name", "gait \"" + name + "\" listed twice");
    }
  }
  return out;
}

std::map<std::string, GaitWalkerSettings> ReadDatabaseWalkerSettings(const std::string& database) {
  const std::filesystem::path path = std::filesystem::path(database) / kWalkerSettingsFile;
  if (!std::filesystem::exists(path)) return {};
  return ReadWalkerSettings(path.string());
}

}  // namespace rabbit
