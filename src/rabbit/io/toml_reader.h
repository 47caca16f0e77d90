// Strict reading of TOML configuration (toml++): every key read is checked for type, finiteness and
// range, and Finish() rejects any key that nobody asked for, so a typo never passes silently.
// Every failure throws InputError with the file, line and full key path.
#ifndef RABBIT_IO_TOML_READER_H_
#define RABBIT_IO_TOML_READER_H_

#include <toml++/toml.h>

#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace rabbit {

// While alive, records the path of every key that a TomlReader on this thread accepts, with the
// file that first accepted it. A key is accepted once a read asks for it (Finish() refuses the
// others), so these are the keys the readers know, as far as the files read reach them. Paths are
// relative to the file's root, array elements as "name[]": "terrain.obstacles[].x_start". Used by
// the documentation test; recordings nest (the innermost records).
class TomlKeyRecording {
 public:
  TomlKeyRecording();
  ~TomlKeyRecording();
  TomlKeyRecording(const TomlKeyRecording&) = delete;
  TomlKeyRecording& operator=(const TomlKeyRecording&) = delete;

  // Key path -> the first file that accepted it.
  const std::map<std::string, std::string>& keys() const { return keys_; }

 private:
  friend class TomlReader;
  std::map<std::string, std::string> keys_;
  TomlKeyRecording* previous_ = nullptr;
};

class TomlReader {
 public:
  // Parses a whole file; syntax errors become InputError with the line.
  static TomlReader ParseFile(const std::string& path);
  // A reader over layers of tables, first layer first: a key is read from the first layer that
  // has it, sub-tables merge layer by layer (arrays do not merge: the first layer's wins), and
  // Finish() checks every layer's keys. E.g. a suite's scenario over the suite's [defaults].
  // Errors name `file` and the lines the nodes came from (none for tables built in memory).
  // `owners` keeps the tables alive.
  static TomlReader FromLayers(std::vector<std::shared_ptr<const toml::table>> owners,
                               std::vector<const toml::table*> layers, std::string file,
                               std::string prefix, int line);
  // Parameter patches: numbers that replace settings wherever they are read, each named by its path
  // below this reader ("controller.k_p"; array elements by 1-based index, "sets.d_obs.Small.2";
  // rows of DoubleRows "points.2.1"), whether the key is written or takes its default. Readers made
  // from this one (tables, arrays of tables) apply them too. Returns a copy carrying them, with a
  // fresh record of which were used (UnusedPatches).
  // `blame`, when given, is called for an error in a patched setting (Fail with a patched key),
  // with its path and the message, and throws there: an error of a value from an overlay names
  // the overlay's file and line, not the scenario's.
  using PatchBlame = std::function<void(const std::string& path, const std::string& message)>;
  TomlReader WithPatches(std::shared_ptr<const std::map<std::string, double>> patches,
                         std::shared_ptr<const PatchBlame> blame = nullptr) const;
  // The patches no read has used so far, in path order (a patch naming no numeric setting).
  std::vector<std::string> UnusedPatches() const;

  // Records into *settings the value every numeric read returns (patched or default included),
  // by its path below this reader, array elements 1-based: the scenario's effective settings.
  // Integer settings also get an entry "#integer:<path>".
  TomlReader WithObserver(std::shared_ptr<std::map<std::string, double>> settings) const;

  // This reader's layers (for building readers over them and more layers).
  const std::vector<const toml::table*>& layers() const { return layers_; }
  const std::vector<std::shared_ptr<const toml::table>>& owners() const { return owners_; }
  int line() const { return line_; }
  const std::string& prefix() const { return prefix_; }

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
  // An array of rows of `row_size` numbers, e.g. [[0, 0.4], [10, 0.6]]. Missing: empty.
  std::vector<std::vector<double>> DoubleRows(const std::string& key, size_t row_size);
  // An array of strings. Missing: the default.
  std::vector<std::string> Strings(const std::string& key,
                                   const std::vector<std::string>& default_value);
  // A sub-table (an empty reader when missing).
  TomlReader Table(const std::string& key);
  // A sub-table taken whole from the first layer that has it (no merging with lower layers): for
  // tables that only make sense as a whole, like a velocity profile.
  TomlReader WholeTable(const std::string& key);
  // A sub-table merged over the first `layers` layers only (the lower ones are ignored for it).
  TomlReader TableFromLayers(const std::string& key, size_t layers);
  // An array of tables ([[key]] or key = [{...}, ...]); empty when missing or [].
  std::vector<TomlReader> TableArray(const std::string& key);

  // Throws for the first key of this table that was never asked for.
  void Finish() const;
  [[noreturn]] void Fail(const std::string& key, const std::string& message) const;
  // The line of `key` in this table (the table's own when it is absent), for an error found later.
  int KeyLine(const std::string& key) const { return LineOf(Find(key)); }

  const std::string& file() const { return file_; }
  // The file's directory, to resolve relative paths named in it.
  std::string Directory() const;

 private:
  TomlReader(std::vector<std::shared_ptr<const toml::table>> owners,
             std::vector<const toml::table*> layers, std::string file, std::string prefix,
             int line);
  const toml::node* Node(const std::string& key);
  // Marks `key` of this table as known (Finish() accepts it) and records it (TomlKeyRecording).
  void Know(const std::string& key);
  int LineOf(const toml::node* node) const;
  // A key of this table that nobody asked for and that looks like a misspelling of `key`, as
  // "'path' at line N" for messages ("" when none).
  std::string MisspellingOf(const std::string& key) const;
  std::string PathOf(const std::string& key) const;

  // A reader over `layers` below this one (key path `rel`), sharing its patches.
  TomlReader Child(std::vector<const toml::table*> layers, std::string prefix, int line,
                   std::string rel) const;
  // The patch of `rel_ + key`, marked used; null when there is none.
  const double* Patch(const std::string& key) const;

  void Observe(const std::string& key, double value) const {
    if (observed_ != nullptr) (*observed_)[rel_ + key] = value;
  }
  // Integer settings are also recorded as "#integer:<path>" (paths never start with '#').
  void ObserveInteger(const std::string& key) const {
    if (observed_ != nullptr) (*observed_)["#integer:" + rel_ + key] = 1.0;
  }

  // The node of `key` in the first layer that has it (null: none).
  const toml::node* Find(const std::string& key) const;

  std::vector<std::shared_ptr<const toml::table>> owners_;
  std::vector<const toml::table*> layers_;  // empty: an absent optional table
  std::string file_;
  std::string prefix_;
  int line_ = 0;
  std::set<std::string> known_;
  std::shared_ptr<const std::map<std::string, double>> patches_;
  std::shared_ptr<std::set<std::string>> patches_used_;
  std::shared_ptr<const PatchBlame> patch_blame_;
  std::shared_ptr<std::map<std::string, double>> observed_;
  std::string rel_;  // this table's path below the reader the patches were attached to, "a.b."
  // For an absent table whose name a written table seems to misspell: a note for its required
  // keys' messages.
  std::string missing_table_;
};

}  // namespace rabbit

#endif  // RABBIT_IO_TOML_READER_H_
