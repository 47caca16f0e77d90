#include "rabbit/scenario/params.h"

#include <cctype>
#include <charconv>
#include <optional>
#include <cmath>
#include <set>
#include <sstream>

#include "rabbit/io/error.h"
#include "rabbit/io/toml_reader.h"

namespace rabbit {
namespace {

int LineOf(const toml::node& node) { return static_cast<int>(node.source().begin.line); }

// Flattens the leaves of `table` below `prefix` into `out` (arrays by 1-based element).
void Flatten(const std::string& file, const toml::table& table, const std::string& prefix,
             ParamOverlay* out) {
  for (const auto& [key, node] : table) {
    const std::string name(key.str());
    const std::string path = prefix.empty() ? name : prefix + "." + name;
    auto add = [&](const toml::node& leaf, const std::string& leaf_path) {
      std::optional<double> value = leaf.value<double>();
      if (!value) {
        throw InputError(file, LineOf(leaf), "params." + leaf_path,
                         "expected a number (parameters set numeric settings)");
      }
      if (!std::isfinite(*value)) {
        throw InputError(file, LineOf(leaf), "params." + leaf_path, "expected a finite number");
      }
      std::string error;
      if (!IsParamPath(leaf_path, &error)) {
        throw InputError(file, LineOf(leaf), "params." + leaf_path, error);
      }
      out->values.push_back({leaf_path, *value, LineOf(leaf), file});
    };
    if (const toml::table* sub = node.as_table()) {
      Flatten(file, *sub, path, out);
    } else if (const toml::array* array = node.as_array()) {
      // An overlay sets numbers element by element: an empty array would set nothing, silently.
      if (array->empty()) {
        throw InputError(file, LineOf(*array), "params." + path,
                         "an empty array sets nothing (an overlay sets numbers, element by "
                         "element; to clear a list, write it in the suite)");
      }
      int index = 1;
      for (const toml::node& element : *array) {
        if (element.is_array() || element.is_table()) {
          throw InputError(file, LineOf(element), "params." + path,
                           "expected an array of numbers");
        }
        add(element, path + "." + std::to_string(index++));
      }
    } else {
      add(node, path);
    }
  }
}

}  // namespace

std::shared_ptr<const std::map<std::string, double>> ParamOverlay::Patches() const {
  auto patches = std::make_shared<std::map<std::string, double>>();
  for (const ParamValue& v : values) (*patches)[v.path] = v.value;
  return patches;
}

void ParamOverlay::Fail(const std::string& path, const std::string& message) const {
  int line = 0;
  std::string from = file.empty() ? "--params" : file;
  for (const ParamValue& v : values) {
    if (v.path != path) continue;
    line = v.line;
    if (!v.file.empty()) from = v.file;
  }
  throw InputError(from, line, path, message);
}

bool IsParamPath(const std::string& path, std::string* error) {
  std::stringstream in(path);
  std::string part;
  int parts = 0;
  while (std::getline(in, part, '.')) {
    ++parts;
    bool ok = !part.empty();
    for (const char c : part) {
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) ok = false;
    }
    if (ok && part.find_first_not_of("0123456789") == std::string::npos &&
        (part.size() > 6 || std::stol(part) < 1)) {
      ok = false;
    }
    if (!ok) {
      *error = "bad key path \"" + path + "\" (parts of letters, digits, '_', '-'; array " +
               "elements from 1)";
      return false;
    }
  }
  if (parts == 0 || path.back() == '.') {
    *error = "bad key path \"" + path + "\"";
    return false;
  }
  return true;
}

ParamOverlay LoadParamOverlay(const std::string& path) {
  TomlReader root = TomlReader::ParseFile(path);
  ParamOverlay overlay;
  overlay.file = path;
  const toml::table& top = *root.layers().front();
  for (const auto& [key, node] : top) {
    if (key.str() != "params") {
      throw InputError(path, LineOf(node), std::string(key.str()),
                       "unknown key (an overlay holds one table, [params])");
    }
  }
  const toml::node* params = top.get("params");
  if (params == nullptr || !params->is_table()) {
    throw InputError(path, 0, "params", "an overlay needs a [params] table of key paths = numbers");
  }
  Flatten(path, *params->as_table(), "", &overlay);
  std::set<std::string> seen;
  for (const ParamValue& v : overlay.values) {
    if (!seen.insert(v.path).second) {
      throw InputError(path, v.line, v.path, "the same key path is given twice");
    }
  }
  return overlay;
}

std::string ExactNumber(double value) {
  char buffer[64];
  const std::to_chars_result result = std::to_chars(buffer, buffer + sizeof buffer, value);
  std::string text(buffer, result.ptr);
  // TOML reads "1e-05" and "3" as numbers; keep them as they are.
  return text;
}

std::string ParamOverlayToml(const ParamOverlay& overlay, const std::string& comment) {
  std::ostringstream out;
  std::stringstream lines(comment);
  std::string line;
  while (std::getline(lines, line)) out << "# " << line << "\n";
  out << "[params]\n";
  for (const ParamValue& v : overlay.values) {
    out << "\"" << v.path << "\" = " << ExactNumber(v.value) << "\n";
  }
  return out.str();
}

}  // namespace rabbit
