#include "rabbit/io/toml_reader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <vector>

#include "rabbit/io/bounded_read.h"
#include "rabbit/io/error.h"

namespace rabbit {
namespace {

thread_local TomlKeyRecording* g_recording = nullptr;

// "terrain.obstacles.1.x_start" -> "terrain.obstacles[].x_start": array elements by "[]".
std::string RecordedPath(const std::string& path) {
  std::string out;
  size_t start = 0;
  while (start <= path.size()) {
    size_t end = path.find('.', start);
    if (end == std::string::npos) end = path.size();
    const std::string part = path.substr(start, end - start);
    if (!part.empty() && !out.empty() &&
        part.find_first_not_of("0123456789") == std::string::npos) {
      out += "[]";
    } else {
      if (!out.empty()) out += '.';
      out += part;
    }
    start = end + 1;
  }
  return out;
}

// Whether `written` looks like a misspelling of `wanted`: another case, or at most one edit (two
// for names of six characters or more), an edit being a character added, removed, replaced, or
// two neighbours swapped (optimal string alignment distance).
bool LooksLikeMisspelling(const std::string& written, const std::string& wanted) {
  if (written == wanted) return false;
  const size_t n = written.size(), m = wanted.size();
  const size_t most = m >= 6 ? 2 : 1;
  if ((n > m ? n - m : m - n) > most) return false;
  auto lower = [](char c) {
    return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  };
  std::vector<std::vector<size_t>> d(n + 1, std::vector<size_t>(m + 1));
  for (size_t i = 0; i <= n; ++i) d[i][0] = i;
  for (size_t j = 0; j <= m; ++j) d[0][j] = j;
  for (size_t i = 1; i <= n; ++i) {
    for (size_t j = 1; j <= m; ++j) {
      const size_t cost = lower(written[i - 1]) == lower(wanted[j - 1]) ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && lower(written[i - 1]) == lower(wanted[j - 2]) &&
          lower(written[i - 2]) == lower(wanted[j - 1])) {
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    }
  }
  return d[n][m] <= most;
}

}  // namespace

std::string TomlReader::MisspellingOf(const std::string& key) const {
  for (const toml::table* layer : layers_) {
    for (const auto& [name, node] : *layer) {
      const std::string written(name.str());
      if (known_.count(written) == 0 && LooksLikeMisspelling(written, key)) {
        const int line = LineOf(&node);
        return "'" + PathOf(written) + "'" +
               (line > 0 ? " at line " + std::to_string(line) : std::string());
      }
    }
  }
  return "";
}

TomlKeyRecording::TomlKeyRecording() : previous_(g_recording) { g_recording = this; }

TomlKeyRecording::~TomlKeyRecording() { g_recording = previous_; }

void TomlReader::Know(const std::string& key) {
  known_.insert(key);
  if (g_recording != nullptr) g_recording->keys_.emplace(RecordedPath(rel_ + key), file_);
}

TomlReader::TomlReader(std::vector<std::shared_ptr<const toml::table>> owners,
                       std::vector<const toml::table*> layers, std::string file, std::string prefix,
                       int line)
    : owners_(std::move(owners)),
      layers_(std::move(layers)),
      file_(std::move(file)),
      prefix_(std::move(prefix)),
      line_(line) {}

TomlReader TomlReader::ParseFile(const std::string& path) {
  const std::string text = ReadBoundedFile(path, kTomlFileLimits);
  try {
    auto root = std::make_shared<const toml::table>(toml::parse(text, path));
    const toml::table* table = root.get();
    return TomlReader({std::move(root)}, {table}, path, "", 1);
  } catch (const toml::parse_error& e) {
    throw InputError(path, static_cast<int>(e.source().begin.line), "",
                     std::string("TOML syntax error: ") + std::string(e.description()));
  }
}

TomlReader TomlReader::FromLayers(std::vector<std::shared_ptr<const toml::table>> owners,
                                  std::vector<const toml::table*> layers, std::string file,
                                  std::string prefix, int line) {
  layers.erase(std::remove(layers.begin(), layers.end(), nullptr), layers.end());
  return TomlReader(std::move(owners), std::move(layers), std::move(file), std::move(prefix), line);
}

TomlReader TomlReader::WithPatches(std::shared_ptr<const std::map<std::string, double>> patches,
                                   std::shared_ptr<const PatchBlame> blame) const {
  TomlReader copy = *this;
  copy.patches_ = std::move(patches);
  copy.patch_blame_ = std::move(blame);
  copy.patches_used_ = std::make_shared<std::set<std::string>>();
  return copy;
}

TomlReader TomlReader::WithObserver(std::shared_ptr<std::map<std::string, double>> settings) const {
  TomlReader copy = *this;
  copy.observed_ = std::move(settings);
  return copy;
}

std::vector<std::string> TomlReader::UnusedPatches() const {
  std::vector<std::string> unused;
  if (patches_ == nullptr) return unused;
  for (const auto& [path, value] : *patches_) {
    if (patches_used_->count(path) == 0) unused.push_back(path);
  }
  return unused;
}

TomlReader TomlReader::Child(std::vector<const toml::table*> layers, std::string prefix, int line,
                             std::string rel) const {
  TomlReader child(owners_, std::move(layers), file_, std::move(prefix), line);
  child.patches_ = patches_;
  child.patches_used_ = patches_used_;
  child.patch_blame_ = patch_blame_;
  child.observed_ = observed_;
  child.rel_ = std::move(rel);
  return child;
}

const double* TomlReader::Patch(const std::string& key) const {
  if (patches_ == nullptr) return nullptr;
  const std::string path = rel_ + key;
  const auto found = patches_->find(path);
  if (found == patches_->end()) return nullptr;
  patches_used_->insert(path);
  return &found->second;
}

const toml::node* TomlReader::Find(const std::string& key) const {
  for (const toml::table* layer : layers_) {
    if (const toml::node* node = layer->get(key)) return node;
  }
  return nullptr;
}

std::string TomlReader::Directory() const {
  return std::filesystem::path(file_).parent_path().string();
}

std::string TomlReader::PathOf(const std::string& key) const {
  return prefix_.empty() ? key : prefix_ + "." + key;
}

int TomlReader::LineOf(const toml::node* node) const {
  return node != nullptr ? static_cast<int>(node->source().begin.line) : line_;
}

void TomlReader::Fail(const std::string& key, const std::string& message) const {
  if (patch_blame_ != nullptr && patches_ != nullptr) {
    // The setting at fault: `key`, or the one a table's check names first in its message
    // ("hip_kp must be >= 0", "recovery.response_catch_back must be ...").
    std::string path = rel_ + key;
    if (patches_->count(path) == 0) {
      const size_t end = message.find_first_not_of(
          "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.");
      const std::string named = message.substr(0, end);
      path = rel_ + (key.empty() ? "" : key + ".") + named;
    }
    if (patches_->count(path) != 0) {
      (*patch_blame_)(
          path, message + " (" + (key.empty() ? prefix_ : PathOf(key)) + " of " + file_ + ")");
    }
  }
  const toml::node* node = key.empty() ? nullptr : Find(key);
  throw InputError(file_, LineOf(node), key.empty() ? prefix_ : PathOf(key), message);
}

bool TomlReader::Has(const std::string& key) const {
  // A patched key counts as given: the checks that apply to a written value apply to it.
  return Find(key) != nullptr || (patches_ != nullptr && patches_->count(rel_ + key) != 0);
}

bool TomlReader::IsArray(const std::string& key) const {
  const toml::node* node = Find(key);
  return node != nullptr && node->is_array();
}

const toml::node* TomlReader::Node(const std::string& key) {
  Know(key);
  return Find(key);
}

namespace {

bool NumberOf(const toml::node& node, double* value) {
  if (const auto* f = node.as_floating_point()) {
    *value = f->get();
    return true;
  }
  if (const auto* i = node.as_integer()) {
    *value = static_cast<double>(i->get());
    return true;
  }
  return false;
}

}  // namespace

double TomlReader::Double(const std::string& key, double default_value) {
  if (const double* patch = Patch(key)) {
    Know(key);
    Observe(key, *patch);
    return *patch;
  }
  const toml::node* node = Node(key);
  double value = default_value;
  if (node != nullptr) {
    if (!NumberOf(*node, &value)) Fail(key, "expected a number");
    if (!std::isfinite(value)) Fail(key, "expected a finite number");
  }
  Observe(key, value);
  return value;
}

double TomlReader::RequiredDouble(const std::string& key) {
  if (!Has(key) && Patch(key) == nullptr) {
    Know(key);
    const std::string misspelt = MisspellingOf(key);
    Fail("", "missing required key '" + key + "'" +
                 (misspelt.empty() ? "" : " (is " + misspelt + " a misspelling of it?)") +
                 missing_table_);
  }
  return Double(key, 0.0);
}

long TomlReader::Integer(const std::string& key, long default_value, long min, long max) {
  if (const double* patch = Patch(key)) {
    Know(key);
    if (!(*patch == std::round(*patch) && *patch >= static_cast<double>(min) &&
          *patch <= static_cast<double>(max))) {
      Fail(key, "a parameter sets this integer setting to " + std::to_string(*patch) +
                    ": expected an integer in [" + std::to_string(min) + ", " +
                    std::to_string(max) + "]");
    }
    Observe(key, *patch);
    ObserveInteger(key);
    return static_cast<long>(*patch);
  }
  const toml::node* node = Node(key);
  ObserveInteger(key);
  if (node == nullptr) {
    Observe(key, static_cast<double>(default_value));
    return default_value;
  }
  const auto* i = node->as_integer();
  if (i == nullptr) Fail(key, "expected an integer");
  const auto value = i->get();
  if (value < min || value > max) {
    Fail(key, "expected an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
  }
  Observe(key, static_cast<double>(value));
  return static_cast<long>(value);
}

bool TomlReader::Bool(const std::string& key, bool default_value) {
  const toml::node* node = Node(key);
  if (node == nullptr) return default_value;
  const auto* b = node->as_boolean();
  if (b == nullptr) Fail(key, "expected true or false");
  return b->get();
}

std::string TomlReader::String(const std::string& key, const std::string& default_value) {
  const toml::node* node = Node(key);
  if (node == nullptr) return default_value;
  const auto* s = node->as_string();
  if (s == nullptr) Fail(key, "expected a string");
  return s->get();
}

std::vector<double> TomlReader::Doubles(const std::string& key,
                                        const std::vector<double>& default_value,
                                        size_t size_required) {
  const toml::node* node = Node(key);
  std::vector<double> values = default_value;
  if (node != nullptr) {
    const auto* array = node->as_array();
    if (array == nullptr) Fail(key, "expected an array of numbers");
    values.clear();
    for (const toml::node& element : *array) {
      double value = 0.0;
      if (!NumberOf(element, &value)) Fail(key, "expected an array of numbers");
      if (!std::isfinite(value)) Fail(key, "expected finite numbers");
      values.push_back(value);
    }
    if (size_required > 0 && values.size() != size_required) {
      Fail(key, "expected " + std::to_string(size_required) + " numbers, got " +
                    std::to_string(values.size()));
    }
  }
  for (size_t i = 0; i < values.size(); ++i) {
    const std::string element = key + "." + std::to_string(i + 1);
    if (const double* patch = Patch(element)) values[i] = *patch;
    Observe(element, values[i]);
  }
  return values;
}

std::vector<std::vector<double>> TomlReader::DoubleRows(const std::string& key, size_t row_size) {
  std::vector<std::vector<double>> rows;
  const toml::node* node = Node(key);
  if (node == nullptr) return rows;
  const auto* array = node->as_array();
  const std::string shape = "expected an array of [" + std::to_string(row_size) + " numbers] rows";
  if (array == nullptr) Fail(key, shape);
  for (const toml::node& element : *array) {
    const auto* row = element.as_array();
    if (row == nullptr || row->size() != row_size) Fail(key, shape);
    std::vector<double> values;
    for (const toml::node& cell : *row) {
      double value = 0.0;
      if (!NumberOf(cell, &value)) Fail(key, shape);
      if (!std::isfinite(value)) Fail(key, "expected finite numbers");
      values.push_back(value);
    }
    rows.push_back(std::move(values));
  }
  for (size_t i = 0; i < rows.size(); ++i) {
    for (size_t j = 0; j < rows[i].size(); ++j) {
      const std::string element = key + "." + std::to_string(i + 1) + "." + std::to_string(j + 1);
      if (const double* patch = Patch(element)) rows[i][j] = *patch;
      Observe(element, rows[i][j]);
    }
  }
  return rows;
}

std::vector<std::string> TomlReader::Strings(const std::string& key,
                                             const std::vector<std::string>& default_value) {
  const toml::node* node = Node(key);
  if (node == nullptr) return default_value;
  const auto* array = node->as_array();
  if (array == nullptr) Fail(key, "expected an array of strings");
  std::vector<std::string> values;
  for (const toml::node& element : *array) {
    const auto* text = element.as_string();
    if (text == nullptr) Fail(key, "expected an array of strings");
    values.push_back(text->get());
  }
  return values;
}

TomlReader TomlReader::Table(const std::string& key) {
  return TableFromLayers(key, layers_.size());
}

TomlReader TomlReader::TableFromLayers(const std::string& key, size_t layers) {
  Know(key);
  std::vector<const toml::table*> tables;
  int line = line_;
  bool first = true;
  for (size_t i = 0; i < layers && i < layers_.size(); ++i) {
    const toml::table* layer = layers_[i];
    const toml::node* node = layer->get(key);
    if (node == nullptr) continue;
    const auto* table = node->as_table();
    if (table == nullptr) {
      throw InputError(file_, LineOf(node), PathOf(key), "expected a table");
    }
    if (first) line = LineOf(node);
    first = false;
    tables.push_back(table);
  }
  TomlReader child = Child(std::move(tables), PathOf(key), line, rel_ + key + ".");
  if (child.layers_.empty()) {
    // Absent: a required key asked of it names a table written under a misspelt name.
    const std::string misspelt = MisspellingOf(key);
    if (!misspelt.empty()) {
      child.missing_table_ =
          " (no table '" + PathOf(key) + "' is written: is " + misspelt + " a misspelling of it?)";
    }
  }
  return child;
}

TomlReader TomlReader::WholeTable(const std::string& key) {
  const toml::node* node = Node(key);
  if (node == nullptr) return Child({}, PathOf(key), line_, rel_ + key + ".");
  const auto* table = node->as_table();
  if (table == nullptr) Fail(key, "expected a table");
  return Child({table}, PathOf(key), LineOf(node), rel_ + key + ".");
}

std::vector<TomlReader> TomlReader::TableArray(const std::string& key) {
  std::vector<TomlReader> out;
  const toml::node* node = Node(key);
  if (node == nullptr) return out;
  const auto* array = node->as_array();
  if (array == nullptr || (!array->empty() && !array->is_array_of_tables())) {
    Fail(key,
         "expected an array of tables ([[" + key + "]] sections, or " + key + " = [{...}, {...}])");
  }
  int index = 1;
  for (const toml::node& element : *array) {
    out.push_back(Child({element.as_table()}, PathOf(key) + "[" + std::to_string(index) + "]",
                        LineOf(&element), rel_ + key + "." + std::to_string(index) + "."));
    ++index;
  }
  return out;
}

void TomlReader::Finish() const {
  for (const toml::table* layer : layers_) {
    for (const auto& [key, node] : *layer) {
      const std::string name(key.str());
      if (known_.count(name) != 0) continue;
      std::ostringstream expected;
      const char* separator = "";
      for (const std::string& k : known_) {
        expected << separator << k;
        separator = ", ";
      }
      throw InputError(file_, LineOf(&node), PathOf(name),
                       known_.empty() ? std::string("unknown key (this table takes no keys)")
                                      : "unknown key (expected one of: " + expected.str() + ")");
    }
  }
}

}  // namespace rabbit
