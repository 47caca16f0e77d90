// Named starting points for the walker's settings. A scenario's `[controller] preset` picks one;
// every key the scenario sets is then read over it.
//   adaptive  (the default) the best shipped walker: the chapter's control strategy with every
//             mechanism this project adds that holds up on the training families (step planner,
//             push recovery, slope adaptation, velocity control with a trunk-led transition,
//             the FIS fed with the desired velocity, the terrain-step handling).
//   chapter   the walker that reproduces the chapter's section 6 (the paper suite): its control
//             strategy with only the departures its figures need (docs/design/walker.md, "The
//             walker"): no step planner, no slope adaptation, the chapter's q0_d law (push recovery
//             stays on, as the paper suite has always run it).
#ifndef RABBIT_CONTROL_WALKER_PRESETS_H_
#define RABBIT_CONTROL_WALKER_PRESETS_H_

#include <string>

#include "rabbit/control/fuzzy_cmac_walker.h"

namespace rabbit {

enum class WalkerPreset { kAdaptive, kChapter };

// "adaptive" or "chapter"; false for any other name.
bool ParseWalkerPreset(const std::string& name, WalkerPreset* preset);
const char* WalkerPresetName(WalkerPreset preset);
// The names, quoted and comma-separated, for error messages.
std::string WalkerPresetNames();

// The settings of a preset. Those the gait database gives (the warm-up gait, its trunk pitch and
// V_M, the per-gait rules) are left at WalkerParams' defaults: the scenario reader fills them in.
WalkerParams PresetWalkerParams(WalkerPreset preset);

}  // namespace rabbit

#endif  // RABBIT_CONTROL_WALKER_PRESETS_H_
