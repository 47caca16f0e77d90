#include "rabbit/io/key_value_csv.h"

#include <cmath>
#include <limits>
#include <utility>

#include "rabbit/io/csv.h"
#include "rabbit/io/error.h"

namespace rabbit {

KeyValueCsv KeyValueCsv::Read(const std::string& path) {
  KeyValueCsv kv(CsvTable::Read(path));
  const size_t key = kv.table_.Column("key");
  kv.value_ = kv.table_.Column("value");
  for (size_t r = 0; r < kv.table_.num_rows(); ++r) {
    const std::string name = kv.table_.Text(r, key);
    const auto [it, inserted] = kv.rows_.emplace(name, r);
    if (!inserted) {
      throw InputError(
          path, kv.table_.line(r), "key",
          "\"" + name + "\" also on line " + std::to_string(kv.table_.line(it->second)));
    }
  }
  return kv;
}

size_t KeyValueCsv::Row(const std::string& key) const {
  const auto it = rows_.find(key);
  if (it == rows_.end()) throw InputError(file(), 0, key, "missing key");
  return it->second;
}

std::string KeyValueCsv::Text(const std::string& key) const {
  return table_.Text(Row(key), value_);
}

double KeyValueCsv::Number(const std::string& key, CsvNumber policy) const {
  const size_t row = Row(key);
  try {
    return table_.Number(row, value_, policy);
  } catch (const InputError&) {
    // Not a number the policy allows: the same error, naming the key rather than the column.
    return ParseFiniteNumber(Text(key), file(), table_.line(row), key);
  }
}

int KeyValueCsv::Integer(const std::string& key) const {
  const double value = Number(key);
  if (value != std::floor(value) || std::abs(value) > std::numeric_limits<int>::max()) {
    throw InputError(file(), line(key), key, "expected an integer, got \"" + Text(key) + "\"");
  }
  return static_cast<int>(value);
}

}  // namespace rabbit
