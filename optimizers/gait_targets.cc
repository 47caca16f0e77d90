#include "gait_targets.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <utility>

#include "rabbit/io/toml_reader.h"
#include "rabbit/scenario/scenario.h"

namespace rabbit {
namespace {

using Bounds = std::array<std::pair<double, double>, kSynthesisParams>;

// Names a database keeps for its own files.
const char* const kReservedNames[] = {"index", "manifest"};

// A `bounds` table: `name = [lower, upper]` for any of kSynthesisParamNames, over *bounds; each
// pair within its parameter's physical range (SynthesisOptions::IsValid).
void ReadBounds(TomlReader& t, Bounds* bounds) {
  if (!t.Has("bounds")) return;
  TomlReader b = t.Table("bounds");
  for (int i = 0; i < kSynthesisParams; ++i) {
    const char* name = kSynthesisParamNames[i];
    if (!b.Has(name)) {
      b.Doubles(name, {});  // known to Finish(), so that a typo lists every name
      continue;
    }
    const std::vector<double> v = b.Doubles(name, {}, 2);
    if (!(std::isfinite(v[0]) && std::isfinite(v[1]) && v[0] < v[1])) {
      b.Fail(name, "need [lower, upper] with finite lower < upper");
    }
    (*bounds)[i] = {v[0], v[1]};
    SynthesisOptions check;
    check.bounds[i] = {v[0], v[1]};
    std::string error;
    if (!check.IsValid(&error)) b.Fail(name, error);
  }
  b.Finish();
}

// The (v_m, l_step) of a target to the millimetre: two targets closer than that are one.
std::pair<long, long> CellKey(const SynthesisOptions& o) {
  return {std::lround(o.target_v_m * 1000.0), std::lround(o.target_l_step * 1000.0)};
}

}  // namespace

std::string DefaultGaitName(double v_m, double l_step, GaitRole role) {
  char buffer[64];
  if (role == GaitRole::kLibrary) {
    std::snprintf(buffer, sizeof buffer, "vm_%.2f_l_%.2f", v_m, l_step);
  } else {
    std::snprintf(buffer, sizeof buffer, "vm_%.2f", v_m);
  }
  return buffer;
}

std::vector<GaitTarget> ReadGaitTargets(const std::string& path) {
  TomlReader root = TomlReader::ParseFile(path);
  Bounds common = DefaultSynthesisBounds();
  ReadBounds(root, &common);
  std::vector<GaitTarget> out;
  std::map<std::string, int> names;            // name -> line
  std::map<std::pair<long, long>, int> cells;  // (v_m, l_step) in mm -> line
  for (TomlReader& t : root.TableArray("gait")) {
    GaitTarget target;
    target.line = t.line();
    SynthesisOptions& o = target.options;
    o.bounds = common;
    ReadBounds(t, &o.bounds);
    o.target_v_m = t.RequiredDouble("v_m");
    o.target_l_step = t.Double("l_step", 0.0);
    o.seed = static_cast<unsigned>(t.Integer("seed", o.seed, 0, 4294967295L));
    o.budget = static_cast<int>(t.Integer("budget", o.budget, 1, 1000000));
    const std::string role = t.String("role", "speed");
    if (!ParseGaitRole(role, &target.role)) {
      t.Fail("role", "unknown role \"" + role + "\" (speed or library)");
    }
    std::string error;
    if (!o.IsValid(&error)) t.Fail("", error);
    if (target.role == GaitRole::kLibrary && !(o.target_l_step > 0.0)) {
      t.Fail("l_step", "a library gait needs a step length (l_step > 0)");
    }
    target.name = t.String("name", DefaultGaitName(o.target_v_m, o.target_l_step, target.role));
    if (!IsSafeName(target.name)) {
      t.Fail("name", "use letters, digits, '.', '_' and '-' only (it names the gait's file)");
    }
    for (const char* reserved : kReservedNames) {
      if (target.name == reserved) {
        t.Fail("name", "\"" + target.name + "\" is the name of one of the database's own files");
      }
    }
    t.Finish();
    const auto named = names.emplace(target.name, target.line);
    if (!named.second) {
      t.Fail("name", "a second target named \"" + target.name + "\" (the first is at line " +
                         std::to_string(named.first->second) + ")");
    }
    const auto cell = cells.emplace(CellKey(o), target.line);
    if (!cell.second) {
      t.Fail("v_m", "a second target at the same (v_m, l_step) (the first is at line " +
                        std::to_string(cell.first->second) + ")");
    }
    out.push_back(target);
  }
  root.Finish();
  if (out.empty()) root.Fail("gait", "no [[gait]] targets");
  return out;
}

std::vector<GaitTarget> DefaultGaitTargets() {
  const double table[5][2] = {{0.4, 0.24}, {0.5, 0.30}, {0.6, 0.34}, {0.7, 0.38}, {0.8, 0.43}};
  std::vector<GaitTarget> out;
  for (const auto& row : table) {
    GaitTarget t;
    t.options.target_v_m = row[0];
    t.options.target_l_step = row[1];
    t.name = DefaultGaitName(row[0], row[1], GaitRole::kSpeed);
    out.push_back(t);
  }
  return out;
}

}  // namespace rabbit
