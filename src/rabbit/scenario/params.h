// Parameter overlays: numbers that replace scenario settings, named by their key path in a scenario
// ("controller.k_p", "controller.sets.d_obs.Small.2", "terrain.obstacles.1.x_start"), applied to
// every scenario of a suite whether the suite writes the key or leaves its default (see
// TomlReader::WithPatches). `rabbit tune` writes its result as one (best.toml) and `rabbit run`,
// `rabbit simulate` and `rabbit tune` read one with --params.
//
// File format (TOML): a [params] table whose leaves are numbers or arrays of numbers; nested
// tables and dotted or quoted keys spell the same paths, and an array sets its elements:
//   [params]
//   "controller.k_p" = 0.25          # or [params.controller] k_p = 0.25
//   "controller.sets.d_obs.Small" = [0.0, 0.12, 0.3]
#ifndef RABBIT_SCENARIO_PARAMS_H_
#define RABBIT_SCENARIO_PARAMS_H_

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace rabbit {

struct ParamValue {
  std::string path;  // key path in a scenario, array elements 1-based
  double value = 0.0;
  int line = 0;  // where the overlay file gave it (0: built in memory)
  // The file that gave it, where overlays are merged (a tuning job's base, --params and tuned
  // values); empty: the overlay's own file.
  std::string file;
};

struct ParamOverlay {
  std::string file;  // names the overlay in errors ("" for one built in memory)
  std::vector<ParamValue> values;
  // A gait database (folder) replacing every walker scenario's `database`, `fll`, `networks` and
  // `gaits` (`--gaits DIR`); empty: none. Not counted by empty().
  std::string gait_database;

  bool empty() const { return values.empty(); }
  // path -> value, for TomlReader::WithPatches.
  std::shared_ptr<const std::map<std::string, double>> Patches() const;
  // Throws InputError naming the overlay's file and the line of the first of `paths` (an unused
  // patch), with `message`.
  [[noreturn]] void Fail(const std::string& path, const std::string& message) const;
};

// Whether `path` is a key path: dot-separated parts of letters, digits, '_' and '-' (indices are
// parts of digits, from 1). On failure says why in *error.
bool IsParamPath(const std::string& path, std::string* error);

// Reads an overlay file. Throws InputError (file, line, key) for a missing [params] table, a value
// that is not a finite number, a bad path or a path given twice.
ParamOverlay LoadParamOverlay(const std::string& path);

// TOML text of an overlay: `comment` lines (without '#') then [params] with one quoted path per
// line, numbers in the shortest form that reads back exactly.
std::string ParamOverlayToml(const ParamOverlay& overlay, const std::string& comment);

// The shortest decimal form of `value` that reads back to the same double.
std::string ExactNumber(double value);

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_PARAMS_H_
