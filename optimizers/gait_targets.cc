#include "gait_targets.h"

#include <array>
#include <cstdio>
#include <map>
#include <utility>

#include "rabbit/io/toml_reader.h"

namespace rabbit {
namespace {

// A `bounds` table: `name = [lower, upper]` for any of kSynthesisParamNames, over *bounds.
void ReadBounds(TomlReader& t, std::array<std::pair<double, double>, kSynthesisParams>* bounds) {
  if (!t.Has("bounds")) return;
  TomlReader b = t.Table("bounds");
  for (int i = 0; i < kSynthesisParams; ++i) {
    const char* name = kSynthesisParamNames[i];
    if (!b.Has(name)) {
      b.Doubles(name, {});  // known to Finish(), so that a typo lists every name
      continue;
    }
    const std::vector<double> v = b.Doubles(name, {}, 2);
    if (!(v[0] < v[1])) b.Fail(name, "need [lower, upper] with lower < upper");
    (*bounds)[i] = {v[0], v[1]};
    SynthesisOptions check;
    check.bounds[i] = {v[0], v[1]};
    std::string error;
    if (!check.IsValid(&error)) b.Fail(name, error);
  }
  b.Finish();
}

}  // namespace

std::string DefaultGaitName(double v_m) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "vm_%.2f", v_m);
  return buffer;
}

std::vector<SynthesisOptions> ReadGaitTargets(const std::string& path) {
  TomlReader root = TomlReader::ParseFile(path);
  std::array<std::pair<double, double>, kSynthesisParams> common = DefaultSynthesisBounds();
  ReadBounds(root, &common);
  std::vector<SynthesisOptions> out;
  std::map<std::string, int> line_of_name;
  for (TomlReader& t : root.TableArray("gait")) {
    SynthesisOptions o;
    o.bounds = common;
    ReadBounds(t, &o.bounds);
    o.target_v_m = t.RequiredDouble("v_m");
    o.target_l_step = t.Double("l_step", 0.0);
    o.seed = static_cast<unsigned>(t.Integer("seed", o.seed, 0, 4294967295L));
    o.budget = static_cast<int>(t.Integer("budget", o.budget, 1, 1000000));
    t.Finish();
    std::string error;
    if (!o.IsValid(&error)) t.Fail("", error);
    const std::string name = DefaultGaitName(o.target_v_m);
    const auto [it, inserted] = line_of_name.insert({name, t.line()});
    if (!inserted) {
      t.Fail("v_m", "a second target for gait " + name + " (first at line " +
                        std::to_string(it->second) + "): each target writes its own gait");
    }
    out.push_back(o);
  }
  root.Finish();
  if (out.empty()) root.Fail("gait", "no [[gait]] targets");
  return out;
}

}  // namespace rabbit
