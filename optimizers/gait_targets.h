// The targets file of `rabbit gaits generate` (gaits/targets.toml): one [[gait]] per reference gait
// to synthesize, with v_m (m/s), l_step (m, 0 or absent: none), seed, budget and an optional
// [gait.bounds] table (`name = [lower, upper]` for any of kSynthesisParamNames) over a top-level
// [bounds] over the defaults.
#ifndef RABBIT_OPTIMIZERS_GAIT_TARGETS_H_
#define RABBIT_OPTIMIZERS_GAIT_TARGETS_H_

#include <string>
#include <vector>

#include "gait_synthesis.h"

namespace rabbit {

// The gait's default name in the database: vm_<v_m to 2 decimals>.
std::string DefaultGaitName(double v_m);

// Throws InputError (file, line, key) for anything malformed: unknown keys, bounds outside their
// parameter's range or not lower < upper, targets SynthesisOptions::IsValid refuses, no target,
// or two targets that would write the same gait (same name).
std::vector<SynthesisOptions> ReadGaitTargets(const std::string& path);

}  // namespace rabbit

#endif  // RABBIT_OPTIMIZERS_GAIT_TARGETS_H_
