// The targets file of a gait database (gaits/targets.toml): one [[gait]] per gait to synthesize,
// over speed (v_m) and step length (l_step), each with a name, a role, a seed, a budget and
// optional search bounds.
#ifndef RABBIT_OPTIMIZERS_GAIT_TARGETS_H_
#define RABBIT_OPTIMIZERS_GAIT_TARGETS_H_

#include <string>
#include <vector>

#include "gait_synthesis.h"
#include "rabbit/gait/gait_database.h"

namespace rabbit {

struct GaitTarget {
  std::string name;  // the gait's name in the database (its file is name.csv)
  GaitRole role = GaitRole::kSpeed;
  SynthesisOptions options;  // target_v_m, target_l_step, seed, budget, bounds
  int line = 0;              // of its [[gait]] in the targets file (0: not from a file)
};

// The default names: vm_0.60 for a speed gait, vm_0.60_l_0.27 for a library gait (speed and step
// length to the centimetre).
std::string DefaultGaitName(double v_m, double l_step, GaitRole role);

// Reads a targets file:
//   [bounds]            optional, `name = [lower, upper]` over DefaultSynthesisBounds() for all
//   [[gait]]            v_m (m/s, required), l_step (m; 0 or absent: none), name, role ("speed",
//                       the default, or "library", which needs an l_step), seed, budget,
//     [gait.bounds]     and bounds over the file's.
// Throws InputError naming the file, line and key for an unknown key, a bad value, impossible
// bounds, two targets with one name or one (v_m, l_step), or a name that is not a safe file name
// or is one of the database's own files (index, manifest).
std::vector<GaitTarget> ReadGaitTargets(const std::string& path);

// The targets used when no file is given: the chapter's Table 2 (V_M, L_step), speed gaits.
std::vector<GaitTarget> DefaultGaitTargets();

}  // namespace rabbit

#endif  // RABBIT_OPTIMIZERS_GAIT_TARGETS_H_
