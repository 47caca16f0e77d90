// A `key,value` CSV file (a run's or a tuning job's meta.csv), looked up by key: each key once,
// values parsed on demand as CsvTable parses cells, errors naming the file, the key's line and
// the key.
#ifndef RABBIT_IO_KEY_VALUE_CSV_H_
#define RABBIT_IO_KEY_VALUE_CSV_H_

#include <cstddef>
#include <map>
#include <string>

#include "rabbit/io/csv_table.h"

namespace rabbit {

class KeyValueCsv {
 public:
  // Reads the file at path (CsvTable::Read) with its `key` and `value` columns; throws InputError
  // for a missing column or a key given twice (naming both lines).
  static KeyValueCsv Read(const std::string& path);

  const std::string& file() const { return table_.file(); }
  bool Has(const std::string& key) const { return rows_.count(key) != 0; }
  // The key's line in the file; InputError(file, 0, key, "missing key") when it is absent (as
  // for every lookup below).
  int line(const std::string& key) const { return table_.line(Row(key)); }
  std::string Text(const std::string& key) const;
  // The value as a number, as `policy` allows, or an integer; else InputError naming the key.
  double Number(const std::string& key, CsvNumber policy = CsvNumber::kFinite) const;
  int Integer(const std::string& key) const;

 private:
  explicit KeyValueCsv(CsvTable table) : table_(std::move(table)) {}
  size_t Row(const std::string& key) const;

  CsvTable table_;
  size_t value_ = 0;                    // the value column
  std::map<std::string, size_t> rows_;  // key -> row
};

}  // namespace rabbit

#endif  // RABBIT_IO_KEY_VALUE_CSV_H_
