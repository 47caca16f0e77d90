#include "rabbit/scenario/suite.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <set>
#include <sstream>

#include "rabbit/io/csv.h"
#include "rabbit/io/error.h"
#include "rabbit/io/toml_reader.h"
#include "rabbit/learn/cmac.h"
#include "rabbit/scenario/family_draws.h"

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
      if (found->is_integer()) {  // an integer key (after_touchdown, ...) takes a whole number
        if (std::floor(value) != value || std::abs(value) > 1e15) {
          return "is an integer in the template: draw it with { range = [low, high], integer = "
                 "true }";
        }
        out->insert_or_assign(key, static_cast<int64_t>(value));
      } else {
        out->insert_or_assign(key, value);
      }
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

// Writes a member's generated velocity profile (velocity.changes) over the template's [velocity]
// table (taken whole, from the highest layer that has one): its profile and points replaced, a
// constant profile's value dropped.
void SetVelocity(const std::vector<const toml::table*>& layers, const MemberDraws& drawn,
                 toml::table* overrides) {
  toml::table velocity;
  for (const toml::table* t : layers) {
    if (const toml::node* n = t->get("velocity"); n != nullptr && n->is_table()) {
      velocity = *n->as_table();
      break;
    }
  }
  velocity.erase("value");
  velocity.insert_or_assign("profile", drawn.velocity_profile);
  toml::array points;
  for (const auto& [t, v] : drawn.velocity_points) points.push_back(toml::array{t, v});
  velocity.insert_or_assign("points", std::move(points));
  overrides->insert_or_assign("velocity", std::move(velocity));
}

}  // namespace

std::string MembersCsv(const Suite& suite) {
  if (suite.members.empty()) return "";
  // The columns: every family's drawn keys, in order of first appearance.
  std::vector<std::string> columns;
  std::map<std::string, size_t> column_of;
  for (const FamilyMembers& f : suite.members) {
    for (const MemberRow& m : f.members) {
      for (const auto& [key, value] : m.values) {
        if (column_of.emplace(key, columns.size()).second) columns.push_back(key);
      }
    }
  }
  std::string out = "family,scenario,seed";
  for (const std::string& c : columns) out += ',' + FormatCsvCell(c);
  out += '\n';
  std::vector<std::string> cells(columns.size());
  for (const FamilyMembers& f : suite.members) {
    for (const MemberRow& m : f.members) {
      std::fill(cells.begin(), cells.end(), std::string());
      for (const auto& [key, value] : m.values) cells[column_of[key]] = FormatCsvNumber(value);
      out += FormatCsvCell(f.family) + ',' + FormatCsvCell(m.name) + ',' + std::to_string(m.seed);
      for (const std::string& c : cells) out += ',' + c;
      out += '\n';
    }
  }
  return out;
}

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

namespace {

// A suite has a [suite] table, or its scenarios in [[scenario]] or [[family]]; any other file is
// read as a single scenario.
bool IsSuite(const TomlReader& root) {
  return root.Has("suite") || root.Has("scenario") || root.Has("family");
}

// Reads a suite file as far as can be done without its gait database: a readable TOML file that
// is a suite or a scenario, not another kind of rabbit file.
void CheckSuiteFile(const std::string& path) {
  const TomlReader root = TomlReader::ParseFile(path);
  if (!IsSuite(root)) RefuseOtherKindsOfFile(root);
}

}  // namespace

void CheckNamedSuiteFile(const std::string& path, const std::string& file, int line,
                         const std::string& key) {
  try {
    CheckSuiteFile(path);
  } catch (const InputError& e) {
    throw InputError(file, line, key, e.what());
  }
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
  if (!IsSuite(root)) {
    RefuseOtherKindsOfFile(root);
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
    TomlReader draw = f.Table("draw");
    TomlReader vary = f.Table("vary");
    f.Finish();
    const FamilyDrawSpec spec = ReadFamilyDrawSpec(&draw, &vary);
    std::vector<const toml::table*> base = templ.layers();
    base.insert(base.end(), default_layers.begin(), default_layers.end());
    const bool template_seeds = templ.Has("seed");
    FamilyMembers record_members;
    record_members.family = name;
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
      MemberDraws drawn;
      std::string error;
      std::string failed_key;  // the [family.vary] key whose expression failed, if one did
      if (!DrawMember(spec, seed, i, &drawn, &error, &failed_key)) {
        vary.Fail(failed_key, "member " + name + member + ": " + error);
      }
      if (spec.changes.present) SetVelocity(base, drawn, overrides.get());
      for (const auto& [key, value] : drawn.keys) {
        error = SetOverride(base, key, value, overrides.get());
        if (!error.empty()) vary.Fail(key, "'" + key + "' " + error);
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
      record_members.members.push_back(
          MemberRow{name + member, suite.scenarios.back().seed, std::move(drawn.columns)});
    }
    suite.members.push_back(std::move(record_members));
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
