// A targets file (TOML) of `rabbit gaits build` and `rabbit gaits generate`: what each reference
// gait of a database must be, how to search for it, and its per-gait walker settings.
//   model = "model.toml"        optional: the robot model's file (default: the built-in model)
//   [bounds]                    optional: search bounds over the defaults, for every target
//   [check] suite = "..."       optional: a suite run on the built database (each scenario must
//   pass)
//   [[gait]]
//   name = "vm_0.60"            optional (default vm_<v_m, 2 decimals>)
//   v_m = 0.6                   m/s
//   l_step = 0.34               m (0 or absent: no step-length target)
//   seed = 1                    the global stage's seed
//   budget = 1500               walks at most
//   [gait.bounds]               name = [lower, upper] for any searched parameter
//   [gait.walker]               per-gait walker settings (walker_settings.h): rule_share = 0
// Relative paths resolve against the targets file's folder (docs/gait-database.md).
#ifndef RABBIT_OPTIMIZERS_GAIT_TARGETS_H_
#define RABBIT_OPTIMIZERS_GAIT_TARGETS_H_

#include <string>
#include <vector>

#include "gait_synthesis.h"
#include "rabbit/gait/walker_settings.h"
#include "rabbit/model/params.h"

namespace rabbit {

struct GaitTarget {
  std::string name;
  SynthesisOptions synthesis;
  GaitWalkerSettings walker;
  int line = 0;  // of its [[gait]] in the targets file
};

struct GaitTargets {
  std::string file;
  std::string model_file;  // resolved path, empty: the built-in model
  ModelParams model;
  std::string check_suite;  // resolved path, empty: none
  std::vector<GaitTarget> gaits;
};

// "vm_0.60" for 0.6 m/s.
std::string DefaultGaitName(double v_m);

// Reads and validates a targets file. Throws InputError naming the file, line and key for unknown
// keys, bounds that are not finite lower < upper, a name that
// is not safe or is taken by the database's own files (index, manifest, walker, gait_pattern,
// networks, reference), and two targets with the same name or the same (v_m, l_step).
GaitTargets ReadGaitTargets(const std::string& path);

// Canonical text of one target's synthesis inputs (every number exact): part of what decides
// whether a built gait is kept when a build resumes.
std::string TargetInputsText(const GaitTarget& target);

}  // namespace rabbit

#endif  // RABBIT_OPTIMIZERS_GAIT_TARGETS_H_
