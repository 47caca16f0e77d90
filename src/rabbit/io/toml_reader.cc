#include "rabbit/io/toml_reader.h"

#include <cmath>
#include <filesystem>
#include <sstream>

#include "rabbit/io/error.h"

namespace rabbit {

TomlReader::TomlReader(std::shared_ptr<const toml::table> root, const toml::table* table,
                       std::string file, std::string prefix, int line)
    : root_(std::move(root)),
      table_(table),
      file_(std::move(file)),
      prefix_(std::move(prefix)),
      line_(line) {}

TomlReader TomlReader::ParseFile(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) {
    throw InputError(path, 0, "", "no such file");
  }
  try {
    auto root = std::make_shared<const toml::table>(toml::parse_file(path));
    const toml::table* table = root.get();
    return TomlReader(std::move(root), table, path, "", 1);
  } catch (const toml::parse_error& e) {
    throw InputError(path, static_cast<int>(e.source().begin.line), "",
                     std::string("TOML syntax error: ") + std::string(e.description()));
  }
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
  const toml::node* node = table_ != nullptr && !key.empty() ? table_->get(key) : nullptr;
  throw InputError(file_, LineOf(node), key.empty() ? prefix_ : PathOf(key), message);
}

bool TomlReader::Has(const std::string& key) const {
  return table_ != nullptr && table_->contains(key);
}

bool TomlReader::IsArray(const std::string& key) const {
  return table_ != nullptr && table_->get(key) != nullptr && table_->get(key)->is_array();
}

const toml::node* TomlReader::Node(const std::string& key) {
  known_.insert(key);
  return table_ != nullptr ? table_->get(key) : nullptr;
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
  const toml::node* node = Node(key);
  if (node == nullptr) return default_value;
  double value = 0.0;
  if (!NumberOf(*node, &value)) Fail(key, "expected a number");
  if (!std::isfinite(value)) Fail(key, "expected a finite number");
  return value;
}

double TomlReader::RequiredDouble(const std::string& key) {
  if (!Has(key)) {
    known_.insert(key);
    Fail("", "missing required key '" + key + "'");
  }
  return Double(key, 0.0);
}

long TomlReader::Integer(const std::string& key, long default_value, long min, long max) {
  const toml::node* node = Node(key);
  if (node == nullptr) return default_value;
  const auto* i = node->as_integer();
  if (i == nullptr) Fail(key, "expected an integer");
  const auto value = i->get();
  if (value < min || value > max) {
    Fail(key, "expected an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
  }
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
  if (node == nullptr) return default_value;
  const auto* array = node->as_array();
  if (array == nullptr) Fail(key, "expected an array of numbers");
  std::vector<double> values;
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
  return values;
}

TomlReader TomlReader::Table(const std::string& key) {
  const toml::node* node = Node(key);
  if (node == nullptr) return TomlReader(root_, nullptr, file_, PathOf(key), line_);
  const auto* table = node->as_table();
  if (table == nullptr) Fail(key, "expected a table");
  return TomlReader(root_, table, file_, PathOf(key), LineOf(node));
}

std::vector<TomlReader> TomlReader::TableArray(const std::string& key) {
  std::vector<TomlReader> out;
  const toml::node* node = Node(key);
  if (node == nullptr) return out;
  const auto* array = node->as_array();
  if (array == nullptr || !array->is_array_of_tables()) Fail(key, "expected an array of tables");
  int index = 1;
  for (const toml::node& element : *array) {
    out.push_back(TomlReader(root_, element.as_table(), file_,
                             PathOf(key) + "[" + std::to_string(index++) + "]", LineOf(&element)));
  }
  return out;
}

void TomlReader::Finish() const {
  if (table_ == nullptr) return;
  for (const auto& [key, node] : *table_) {
    const std::string name(key.str());
    if (known_.count(name) != 0) continue;
    std::ostringstream expected;
    const char* separator = "";
    for (const std::string& k : known_) {
      expected << separator << k;
      separator = ", ";
    }
    throw InputError(file_, LineOf(&node), PathOf(name),
                     "unknown key (expected one of: " + expected.str() + ")");
  }
}

}  // namespace rabbit
