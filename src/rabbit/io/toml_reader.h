// Strict reading of TOML configuration (toml++): every key read is checked for type, finiteness and
// range, and Finish() rejects any key that nobody asked for, so a typo never passes silently.
// Every failure throws InputError with the file, line and full key path.
#ifndef RABBIT_IO_TOML_READER_H_
#define RABBIT_IO_TOML_READER_H_

#include <toml++/toml.h>

#include <memory>
#include <set>
#include <string>
#include <vector>

namespace rabbit {

class TomlReader {
 public:
  // Parses a whole file; syntax errors become InputError with the line.
  static TomlReader ParseFile(const std::string& path);

  bool Has(const std::string& key) const;
  bool IsArray(const std::string& key) const;
  // Numbers (integers accepted), finite. Missing key: the default.
  double Double(const std::string& key, double default_value);
  // As Double, and the key must be present.
  double RequiredDouble(const std::string& key);
  // An integer in [min, max] (else an error naming the key and the range).
  long Integer(const std::string& key, long default_value, long min, long max);
  bool Bool(const std::string& key, bool default_value);
  std::string String(const std::string& key, const std::string& default_value);
  // An array of numbers; size_required > 0 demands exactly that many. Missing: the default.
  std::vector<double> Doubles(const std::string& key, const std::vector<double>& default_value,
                              size_t size_required = 0);
  // A sub-table (an empty reader when missing).
  TomlReader Table(const std::string& key);
  // An array of tables ([[key]]); empty when missing.
  std::vector<TomlReader> TableArray(const std::string& key);

  // Throws for the first key of this table that was never asked for.
  void Finish() const;
  [[noreturn]] void Fail(const std::string& key, const std::string& message) const;

  const std::string& file() const { return file_; }
  // The file's directory, to resolve relative paths named in it.
  std::string Directory() const;

 private:
  TomlReader(std::shared_ptr<const toml::table> root, const toml::table* table, std::string file,
             std::string prefix, int line);
  const toml::node* Node(const std::string& key);
  int LineOf(const toml::node* node) const;
  std::string PathOf(const std::string& key) const;

  std::shared_ptr<const toml::table> root_;
  const toml::table* table_ = nullptr;  // may be null: an absent optional table
  std::string file_;
  std::string prefix_;
  int line_ = 0;
  std::set<std::string> known_;
};

}  // namespace rabbit

#endif  // RABBIT_IO_TOML_READER_H_
