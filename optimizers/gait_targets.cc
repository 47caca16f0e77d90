#include "gait_targets.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <utility>

#include "rabbit/io/error.h"
#include "rabbit/io/toml_reader.h"
#include "rabbit/learn/ts_fis.h"
#include "rabbit/scenario/params.h"
#include "rabbit/scenario/scenario.h"

namespace rabbit {
namespace {

using Bounds = std::array<std::pair<double, double>, kSynthesisParams>;

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

// A target's `start` table: `name = value` for any of kSynthesisParamNames (checked against the
// target's bounds by SynthesisOptions::IsValid).
void ReadStart(TomlReader& t, SynthesisOptions* o) {
  if (!t.Has("start")) return;
  TomlReader s = t.Table("start");
  for (int i = 0; i < kSynthesisParams; ++i) {
    const char* name = kSynthesisParamNames[i];
    if (!s.Has(name)) {
      s.Double(name, 0.0);  // known to Finish(), so that a typo lists every name
      continue;
    }
    o->start[i] = s.Double(name, 0.0);
    SynthesisOptions check;
    check.bounds = o->bounds;
    check.start[i] = o->start[i];
    std::string error;
    if (!check.IsValid(&error)) s.Fail(name, error);
  }
  s.Finish();
}

std::string Resolve(const TomlReader& t, const std::string& path) {
  const std::filesystem::path p(path);
  return p.is_absolute() ? path
                         : (std::filesystem::path(t.Directory()) / p).lexically_normal().string();
}

bool Reserved(const std::string& name) {
  for (const char* taken :
       {"index", "manifest", "walker", "gait_pattern", "networks", "reference"}) {
    if (name == taken) return true;
  }
  return false;
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

GaitTargets ReadGaitTargets(const std::string& path) {
  TomlReader root = TomlReader::ParseFile(path);
  GaitTargets out;
  out.file = path;
  const std::string model = root.String("model", "");
  if (!model.empty()) {
    out.model_file = Resolve(root, model);
    out.model = LoadModelFile(out.model_file);
  }
  Bounds common = DefaultSynthesisBounds();
  ReadBounds(root, &common);
  if (root.Has("check")) {
    TomlReader check = root.Table("check");
    const std::string suite = check.String("suite", "");
    if (suite.empty()) check.Fail("suite", "name the suite to run on the built database");
    out.check_suite = Resolve(check, suite);
    out.check_line = check.KeyLine("suite");
    check.Finish();
  }
  std::map<std::string, int> names;            // name -> line
  std::map<std::pair<long, long>, int> cells;  // (v_m, l_step) in mm -> line
  std::map<long, int> speeds;                  // a speed gait's v_m in mm -> line
  for (TomlReader& t : root.TableArray("gait")) {
    GaitTarget g;
    g.line = t.line();
    SynthesisOptions& o = g.synthesis;
    o.bounds = common;
    ReadBounds(t, &o.bounds);
    ReadStart(t, &o);
    o.target_v_m = t.RequiredDouble("v_m");
    o.target_l_step = t.Double("l_step", 0.0);
    o.seed = static_cast<unsigned>(t.Integer("seed", o.seed, 0, 4294967295L));
    o.budget = static_cast<int>(t.Integer("budget", o.budget, 1, 1000000));
    const std::string role = t.String("role", "speed");
    if (!ParseGaitRole(role, &g.role)) {
      t.Fail("role", "unknown role \"" + role + "\" (speed or library)");
    }
    if (g.role == GaitRole::kLibrary && !(o.target_l_step > 0.0)) {
      t.Fail("l_step", "a library gait needs a step length (l_step > 0)");
    }
    g.name = t.String("name", DefaultGaitName(o.target_v_m, o.target_l_step, g.role));
    if (t.Has("walker")) {
      TomlReader w = t.Table("walker");
      g.walker.rule_share = w.Double("rule_share", g.walker.rule_share);
      if (!(g.walker.rule_share >= 0.0 && g.walker.rule_share <= 1.0)) {
        w.Fail("rule_share", "must be in [0, 1]");
      }
      w.Finish();
    }
    t.Finish();
    std::string error;
    if (!o.IsValid(&error)) t.Fail("", error);
    if (!IsSafeName(g.name)) t.Fail("name", SafeNameRule(g.name) + " (it names the gait's file)");
    if (Reserved(g.name)) {
      t.Fail("name", "\"" + g.name + "\" is the name of one of the database's own files");
    }
    const auto named = names.emplace(g.name, g.line);
    if (!named.second) {
      t.Fail("name", "a second target named \"" + g.name + "\" (the first is at line " +
                         std::to_string(named.first->second) + ")");
    }
    const auto cell = cells.emplace(CellKey(o), g.line);
    if (!cell.second) {
      t.Fail("v_m", "a second target at the same (v_m, l_step) (the first is at line " +
                        std::to_string(cell.first->second) + ")");
    }
    // The fuzzy system blends the speed gaits by velocity: one each, and at most as many as its
    // sets (checked here, not after the build's synthesis).
    if (g.role == GaitRole::kSpeed) {
      const auto speed = speeds.emplace(CellKey(o).first, g.line);
      if (!speed.second) {
        t.Fail("v_m", "a second speed gait at this v_m (the first is at line " +
                          std::to_string(speed.first->second) +
                          "; the fuzzy system blends the speed gaits by velocity: give this one "
                          "role = \"library\", or another v_m)");
      }
      if (speeds.size() > kMaxGaitPatternGaits) {
        t.Fail("", "more than " + std::to_string(kMaxGaitPatternGaits) +
                       " speed gaits (the most the fuzzy system blends)");
      }
    }
    out.gaits.push_back(g);
  }
  root.Finish();
  if (out.gaits.empty()) root.Fail("gait", "no [[gait]] targets");
  return out;
}

std::vector<GaitTarget> DefaultGaitTargets() {
  const double table[5][2] = {{0.4, 0.24}, {0.5, 0.30}, {0.6, 0.34}, {0.7, 0.38}, {0.8, 0.43}};
  std::vector<GaitTarget> out;
  for (const auto& row : table) {
    GaitTarget t;
    t.synthesis.target_v_m = row[0];
    t.synthesis.target_l_step = row[1];
    t.name = DefaultGaitName(row[0], row[1], GaitRole::kSpeed);
    out.push_back(t);
  }
  return out;
}

std::string TargetInputsText(const GaitTarget& g) {
  const SynthesisOptions& o = g.synthesis;
  std::string text = "name " + g.name + "\nrole " + GaitRoleName(g.role) + "\nv_m " +
                     ExactNumber(o.target_v_m) + "\nl_step " + ExactNumber(o.target_l_step) +
                     "\nseed " + std::to_string(o.seed) + "\nbudget " + std::to_string(o.budget) +
                     "\nwalk_duration " + ExactNumber(o.walk_duration) + "\nwindow " +
                     std::to_string(o.window) + "\nlocal " + o.local_algorithm + "\nv_tolerance " +
                     ExactNumber(o.v_tolerance) + "\nl_tolerance " + ExactNumber(o.l_tolerance) +
                     "\nmax_l_spread " + ExactNumber(o.max_l_spread) + "\n";
  for (int i = 0; i < kSynthesisParams; ++i) {
    text += std::string("bounds ") + kSynthesisParamNames[i] + " " +
            ExactNumber(o.bounds[i].first) + " " + ExactNumber(o.bounds[i].second) + "\n";
  }
  for (int i = 0; i < kSynthesisParams; ++i) {
    if (o.start[i]) {
      text +=
          std::string("start ") + kSynthesisParamNames[i] + " " + ExactNumber(*o.start[i]) + "\n";
    }
  }
  return text;
}

}  // namespace rabbit
