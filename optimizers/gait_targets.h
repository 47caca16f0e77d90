// A targets file (TOML) of `rabbit gaits build` and `rabbit gaits generate`: what each gait of a
// database must be, how to search for it, and its per-gait walker settings.
//   model = "model.toml"        optional: the robot model's file (default: the built-in model)
//   [bounds]                    optional: search bounds over the defaults, for every target
//   [check] suite = "..."       optional: a suite run on the built database (each scenario must
//                               pass)
//   [[gait]]
//   v_m = 0.6                   m/s (required)
//   l_step = 0.34               m (0 or absent: no step-length target; required for a library gait)
//   name = "vm_0.60"            optional (default vm_0.60 for a speed gait, vm_0.60_l_0.27 for a
//                               library gait)
//   role = "speed"              "speed" (a gait the chapter's walker blends over V_M) or
//                               "library" (one more step length at a speed, for a step planner)
//   seed = 1                    the global stage's seed
//   budget = 1500               walks at most
//   [gait.bounds]               name = [lower, upper] for any searched parameter
//   [gait.start]                name = value: where the search starts, for any searched
//                               parameter (within the bounds; the others: Table 2's values)
//   [gait.walker]               per-gait walker settings (walker_settings.h): rule_share = 0
// Relative paths resolve against the targets file's folder (docs/gait-database.md).
#ifndef RABBIT_OPTIMIZERS_GAIT_TARGETS_H_
#define RABBIT_OPTIMIZERS_GAIT_TARGETS_H_

#include <string>
#include <vector>

#include "gait_synthesis.h"
#include "rabbit/gait/gait_database.h"
#include "rabbit/gait/walker_settings.h"
#include "rabbit/model/params.h"

namespace rabbit {

struct GaitTarget {
  std::string name;  // the gait's name in the database (its file is name.csv)
  GaitRole role = GaitRole::kSpeed;
  SynthesisOptions synthesis;  // target_v_m, target_l_step, seed, budget, bounds, start
  GaitWalkerSettings walker;
  int line = 0;  // of its [[gait]] in the targets file (0: not from a file)
};

struct GaitTargets {
  std::string file;
  std::string model_file;  // resolved path, empty: the built-in model
  ModelParams model;
  std::string check_suite;  // resolved path, empty: none
  int check_line = 0;       // where the targets file names it
  std::vector<GaitTarget> gaits;
};

// The default names: vm_0.60 for a speed gait, vm_0.60_l_0.27 for a library gait (speed and step
// length to the centimetre).
std::string DefaultGaitName(double v_m, double l_step = 0.0, GaitRole role = GaitRole::kSpeed);

// Reads and validates a targets file. Throws InputError naming the file, line and key for unknown
// keys, bounds that are not finite lower < upper or outside their parameter's physical range, an
// unknown role, a library gait without a step length, a name that is not safe or is taken by the
// database's own files (index, manifest, walker, gait_pattern, networks, reference), and two
// targets with the same name or the same (v_m, l_step) (to the millimetre).
GaitTargets ReadGaitTargets(const std::string& path);

// The targets used when no file is given: the chapter's Table 2 (V_M, L_step), speed gaits.
std::vector<GaitTarget> DefaultGaitTargets();

// Canonical text of one target's inputs (every number exact): part of what decides whether a
// built gait is kept when a build resumes.
std::string TargetInputsText(const GaitTarget& target);

}  // namespace rabbit

#endif  // RABBIT_OPTIMIZERS_GAIT_TARGETS_H_
