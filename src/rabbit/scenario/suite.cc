#include "rabbit/scenario/suite.h"

#include <cstdio>
#include <filesystem>
#include <memory>
#include <set>
#include <sstream>

#include "rabbit/io/csv.h"
#include "rabbit/io/error.h"
#include "rabbit/io/toml_reader.h"
#include "rabbit/learn/cmac.h"

namespace rabbit {
namespace {

constexpr long kMaxFamilyCount = 10000;
constexpr size_t kMaxSuiteScenarios = 20000;  // over all scenarios and families of a suite

// Splits "a.b.1.c" into its parts.
std::vector<std::string> SplitPath(const std::string& path) {
  std::vector<std::string> parts;
  std::stringstream in(path);
  std::string part;
  while (std::getline(in, part, '.')) parts.push_back(part);
  return parts;
}

bool IsIndex(const std::string& part, size_t* index) {
  if (part.empty() || part.size() > 6 ||
      part.find_first_not_of("0123456789") != std::string::npos) {
    return false;
  }
  *index = std::stoul(part);
  return true;
}

// Sets `value` at `path` in `overrides` (a table layered above `layers`), copying from the layers
// the arrays the path goes through (arrays do not merge, so the whole array is overridden).
// Returns an error message, empty on success.
std::string SetOverride(const std::vector<const toml::table*>& layers, const std::string& path,
                        double value, toml::table* overrides) {
  const std::vector<std::string> parts = SplitPath(path);
  if (parts.empty()) return "empty key path";
  // Walk the layered tables down to the first array (or the leaf).
  std::vector<const toml::table*> here = layers;
  toml::table* out = overrides;
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string& key = parts[i];
    const toml::node* found = out->get(key);  // set by an earlier key, or a copied array's
    for (const toml::table* t : here) {
      if (found == nullptr) found = t->get(key);
    }
    if (found == nullptr) return "names no value of the template (no '" + key + "')";
    if (i + 1 == parts.size()) {
      if (!found->is_number()) return "is not a number in the template";
      out->insert_or_assign(key, value);
      return "";
    }
    if (found->is_array()) {
      // Copy the array once into the overrides, then descend into the copy.
      if (out->get(key) == nullptr) out->insert_or_assign(key, *found->as_array());
      toml::node* node = out->get(key);
      toml::array* array = node->as_array();
      size_t index = 0;
      if (array == nullptr || i + 1 >= parts.size() || !IsIndex(parts[i + 1], &index) ||
          index < 1 || index > array->size()) {
        return "array '" + key + "' needs a 1-based index within its " +
               std::to_string(array == nullptr ? 0 : array->size()) + " elements";
      }
      toml::node* element = array->get(index - 1);
      ++i;
      // Arrays of arrays (such as velocity points [[t, v], ...]): further 1-based indices.
      while (element->is_array() && i + 1 < parts.size()) {
        toml::array* inner = element->as_array();
        size_t j = 0;
        if (!IsIndex(parts[i + 1], &j) || j < 1 || j > inner->size()) {
          return "element " + parts[i] + " of '" + key + "' needs a 1-based index within its " +
                 std::to_string(inner->size()) + " elements";
        }
        array = inner;
        index = j;
        element = inner->get(j - 1);
        ++i;
      }
      if (i + 1 == parts.size()) {
        if (!element->is_number()) return "is not a number in the template";
        array->replace(array->cbegin() + static_cast<std::ptrdiff_t>(index - 1), value);
        return "";
      }
      toml::table* sub = element->as_table();
      if (sub == nullptr) return "element " + parts[i] + " of '" + key + "' is not a table";
      // Below the copied array, everything is in the copy.
      here.clear();
      out = sub;
      continue;
    }
    if (!found->is_table()) return "'" + key + "' is not a table";
    std::vector<const toml::table*> next;
    for (const toml::table* t : here) {
      if (const toml::node* n = t->get(key); n != nullptr && n->is_table()) {
        next.push_back(n->as_table());
      }
    }
    // The override layer starts from a copy of the highest layer's table, so that tables taken
    // whole from one layer (such as [velocity]) keep their other keys.
    if (out->get(key) == nullptr) {
      out->insert_or_assign(key, next.empty() ? toml::table{} : *next.front());
    }
    here = std::move(next);
    out = out->get(key)->as_table();
    if (out == nullptr) return "'" + key + "' is not a table";
  }
  return "";
}

}  // namespace

std::string TargetsCsv(const Suite& suite) {
  std::string out = "group,target_success_rate\n";
  for (const auto& [group, rate] : suite.targets) {
    out += FormatCsvCell(group) + ',' + FormatCsvNumber(rate) + '\n';
  }
  return out;
}

double FamilyDraw(std::uint64_t family_seed, int member, const std::string& key, double low,
                  double high) {
  std::uint64_t name = 0xCBF29CE484222325ULL;  // FNV-1a of the key
  for (const char c : key) name = (name ^ static_cast<unsigned char>(c)) * 0x100000001B3ULL;
  const std::uint64_t h =
      CmacHashStep(CmacHashStep(CmacMix64(family_seed), static_cast<std::uint64_t>(member)), name);
  const double u = static_cast<double>(h >> 11) * 0x1.0p-53;  // [0, 1)
  return low + u * (high - low);
}

bool IsSuiteFile(const std::string& path) {
  const TomlReader root = TomlReader::ParseFile(path);
  return root.Has("suite") || root.Has("scenario") || root.Has("family");
}

Suite LoadSuite(const std::string& path, const ParamOverlay* overlay,
                std::vector<std::map<std::string, double>>* settings) {
  if (settings != nullptr) settings->clear();
  auto record = [settings]() -> std::map<std::string, double>* {
    if (settings == nullptr) return nullptr;
    settings->emplace_back();
    return &settings->back();
  };
  TomlReader root = TomlReader::ParseFile(path);
  Suite suite;
  suite.file = path;
  if (!root.Has("suite") && !root.Has("scenario") && !root.Has("family")) {
    suite.scenarios.push_back(
        ReadScenario(root, std::filesystem::path(path).stem().string(), overlay, record()));
    suite.name = suite.scenarios.back().name;
    suite.description = suite.scenarios.back().description;
    return suite;
  }
  TomlReader header = root.Table("suite");
  suite.name = header.String("name", std::filesystem::path(path).stem().string());
  suite.description = header.String("description", "");
  TomlReader targets = header.Table("targets");
  for (const toml::table* layer : targets.layers()) {
    for (const auto& [key, node] : *layer) {
      const std::string group(key.str());
      const double rate = targets.Double(group, 0.0);
      if (!(rate > 0.0 && rate <= 1.0)) targets.Fail(group, "a success rate in (0, 1]");
      suite.targets.emplace_back(group, rate);
    }
  }
  targets.Finish();
  header.Finish();
  if (!IsSafeName(suite.name)) {
    header.Fail("name", SafeNameRule(suite.name) + " (it names the report folder)");
  }
  const TomlReader defaults = root.Table("defaults");
  const std::vector<const toml::table*>& default_layers = defaults.layers();

  for (TomlReader& s : root.TableArray("scenario")) {
    std::vector<const toml::table*> layers = s.layers();
    layers.insert(layers.end(), default_layers.begin(), default_layers.end());
    suite.scenarios.push_back(
        ReadScenario(TomlReader::FromLayers(s.owners(), layers, path, s.prefix(), s.line()), "",
                     overlay, record()));
  }
  std::set<std::string> family_names;
  for (TomlReader& f : root.TableArray("family")) {
    const std::string name = f.String("name", "");
    if (!IsSafeName(name)) f.Fail("name", "a family needs a name: " + SafeNameRule(name));
    if (name.size() > 96) f.Fail("name", "at most 96 characters (members add -000)");
    if (!family_names.insert(name).second) f.Fail("name", "two families named \"" + name + "\"");
    const long count = f.Integer("count", 0, 1, kMaxFamilyCount);
    if (!f.Has("count")) f.Fail("", "missing required key 'count'");
    if (suite.scenarios.size() + static_cast<size_t>(count) > kMaxSuiteScenarios) {
      f.Fail("count",
             "the suite would hold more than " + std::to_string(kMaxSuiteScenarios) + " scenarios");
    }
    const auto seed =
        static_cast<std::uint64_t>(f.Integer("seed", 1, 0, std::numeric_limits<long>::max()));
    TomlReader templ = f.Table("scenario");
    TomlReader vary = f.Table("vary");
    f.Finish();
    // The varied keys, in file order.
    struct Range {
      std::string key;
      double low = 0.0, high = 0.0;
      bool random_sign = false;  // the drawn magnitude gets a random sign
    };
    std::vector<Range> ranges;
    for (const toml::table* layer : vary.layers()) {
      for (const auto& [key, node] : *layer) {
        const std::string k(key.str());
        if (k == "name" || k == "seed" || k.rfind("name.", 0) == 0 || k.rfind("seed.", 0) == 0) {
          vary.Fail(k,
                    "a family member's name and seed are not varied (they come from the family)");
        }
        Range r;
        r.key = k;
        std::vector<double> range;
        if (node.is_table()) {  // { range = [low, high], random_sign = true }
          TomlReader t = vary.Table(k);
          if (!t.Has("range")) t.Fail("range", "missing required key 'range'");
          range = t.Doubles("range", {}, 2);
          r.random_sign = t.Bool("random_sign", false);
          t.Finish();
        } else {
          range = vary.Doubles(k, {}, 2);
        }
        if (!(range[0] <= range[1])) vary.Fail(k, "expected [low, high] with low <= high");
        r.low = range[0];
        r.high = range[1];
        ranges.push_back(r);
      }
    }
    vary.Finish();
    std::vector<const toml::table*> base = templ.layers();
    base.insert(base.end(), default_layers.begin(), default_layers.end());
    const bool template_seeds = templ.Has("seed");
    for (int i = 0; i < count; ++i) {
      auto overrides = std::make_shared<toml::table>();
      char member[16];
      std::snprintf(member, sizeof member, "-%03d", i);
      overrides->insert_or_assign("name", name + member);
      if (!template_seeds) {
        overrides->insert_or_assign(
            "seed", static_cast<int64_t>(
                        CmacHashStep(CmacMix64(seed), static_cast<std::uint64_t>(i)) >> 2));
      }
      for (const Range& r : ranges) {
        double value = FamilyDraw(seed, i, r.key, r.low, r.high);
        if (r.random_sign && FamilyDraw(seed, i, r.key + "#sign", 0.0, 1.0) < 0.5) value = -value;
        const std::string error = SetOverride(base, r.key, value, overrides.get());
        if (!error.empty()) vary.Fail(r.key, "'" + r.key + "' " + error);
      }
      std::vector<std::shared_ptr<const toml::table>> owners = templ.owners();
      owners.push_back(overrides);
      std::vector<const toml::table*> layers = {overrides.get()};
      layers.insert(layers.end(), base.begin(), base.end());
      suite.scenarios.push_back(ReadScenario(
          TomlReader::FromLayers(owners, layers, path,
                                 f.prefix() + ".scenario (" + name + member + ")", templ.line()),
          "", overlay, record()));
      suite.scenarios.back().family = name;
    }
  }
  root.Finish();
  if (suite.scenarios.empty()) root.Fail("", "the suite has no [[scenario]] and no [[family]]");
  std::set<std::string> names;
  for (const Scenario& s : suite.scenarios) {
    if (!names.insert(s.name).second) {
      throw InputError(path, 0, s.name, "two scenarios named \"" + s.name + "\"");
    }
  }
  for (const auto& [group, rate] : suite.targets) {
    if (family_names.count(group) == 0 && names.count(group) == 0) {
      targets.Fail(group, "names no family or scenario of the suite");
    }
  }
  return suite;
}

}  // namespace rabbit
