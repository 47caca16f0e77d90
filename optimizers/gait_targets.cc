#include "gait_targets.h"

#include <array>
#include <cstdio>
#include <filesystem>
#include <map>
#include <utility>

#include "rabbit/io/error.h"
#include "rabbit/io/toml_reader.h"
#include "rabbit/scenario/params.h"
#include "rabbit/scenario/scenario.h"

namespace rabbit {
namespace {

using Bounds = std::array<std::pair<double, double>, kSynthesisParams>;

// A `bounds` table: `name = [lower, upper]` for any of kSynthesisParamNames, over *bounds.
void ReadBounds(TomlReader& t, Bounds* bounds) {
  if (!t.Has("bounds")) return;
  TomlReader b = t.Table("bounds");
  for (int i = 0; i < kSynthesisParams; ++i) {
    const char* name = kSynthesisParamNames[i];
    if (!b.Has(name)) continue;
    const std::vector<double> v = b.Doubles(name, {}, 2);
    if (!(v[0] < v[1])) b.Fail(name, "need [lower, upper] with lower < upper");
    (*bounds)[i] = {v[0], v[1]};
  }
  b.Finish();
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

}  // namespace

std::string DefaultGaitName(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "vm_%.2f", v);
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
    check.Finish();
  }
  std::map<std::string, int> names;
  std::map<std::pair<double, double>, int> cells;
  for (TomlReader& t : root.TableArray("gait")) {
    GaitTarget g;
    g.line = t.line();
    SynthesisOptions& o = g.synthesis;
    o.bounds = common;
    ReadBounds(t, &o.bounds);
    o.target_v_m = t.RequiredDouble("v_m");
    o.target_l_step = t.Double("l_step", 0.0);
    o.seed = static_cast<unsigned>(t.Integer("seed", o.seed, 0, 4294967295L));
    o.budget = static_cast<int>(t.Integer("budget", o.budget, 1, 1000000));
    g.name = t.String("name", DefaultGaitName(o.target_v_m));
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
    if (!IsSafeName(g.name)) t.Fail("name", "use letters, digits, '.', '_' and '-' only");
    if (Reserved(g.name)) {
      t.Fail("name", "\"" + g.name + "\" is taken by the database's own files");
    }
    if (!names.emplace(g.name, g.line).second) {
      t.Fail("name", "a second target named \"" + g.name + "\" (the first is on line " +
                         std::to_string(names[g.name]) + ")");
    }
    const std::pair<double, double> cell{o.target_v_m, o.target_l_step};
    if (!cells.emplace(cell, g.line).second) {
      t.Fail("v_m", "a second target with the same (v_m, l_step) (the first is on line " +
                        std::to_string(cells[cell]) + ")");
    }
    out.gaits.push_back(g);
  }
  root.Finish();
  if (out.gaits.empty()) root.Fail("gait", "no [[gait]] targets");
  return out;
}

std::string TargetInputsText(const GaitTarget& g) {
  const SynthesisOptions& o = g.synthesis;
  std::string text = "name " + g.name + "\nv_m " + ExactNumber(o.target_v_m) + "\nl_step " +
                     ExactNumber(o.target_l_step) + "\nseed " + std::to_string(o.seed) +
                     "\nbudget " + std::to_string(o.budget) + "\nwalk_duration " +
                     ExactNumber(o.walk_duration) + "\nwindow " + std::to_string(o.window) +
                     "\nlocal " + o.local_algorithm + "\nv_tolerance " +
                     ExactNumber(o.v_tolerance) + "\nl_tolerance " + ExactNumber(o.l_tolerance) +
                     "\nmax_l_spread " + ExactNumber(o.max_l_spread) + "\n";
  for (int i = 0; i < kSynthesisParams; ++i) {
    text += std::string("bounds ") + kSynthesisParamNames[i] + " " +
            ExactNumber(o.bounds[i].first) + " " + ExactNumber(o.bounds[i].second) + "\n";
  }
  return text;
}

}  // namespace rabbit
