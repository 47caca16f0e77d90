// A single-run scenario file for `rabbit simulate` (TOML; see docs/formats/scenario.md).
#ifndef RABBIT_SCENARIO_SCENARIO_H_
#define RABBIT_SCENARIO_SCENARIO_H_

#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rabbit/contact/actuator.h"
#include "rabbit/contact/contact.h"
#include "rabbit/contact/terrain.h"
#include "rabbit/control/basic_controllers.h"
#include "rabbit/control/fuzzy_cmac_walker.h"
#include "rabbit/control/walker_presets.h"
#include "rabbit/gait/gait_walk.h"
#include "rabbit/gait/walker_settings.h"
#include "rabbit/learn/multi_cmac_pattern.h"
#include "rabbit/model/params.h"
#include "rabbit/scenario/stall_watch.h"
#include "rabbit/sim/simulator.h"

namespace rabbit {

class TomlReader;
struct ParamOverlay;

enum class ControllerKind { kPassive, kPdHold, kPragmatic, kFuzzyCmac };

// What a scenario must show to pass (checked after the run by EvaluateCriteria in
// rabbit/scenario/run.h; docs/outcomes.md lists every key). Unset criteria (0 or infinity) are not
// checked.
struct PassCriteria {
  int min_steps = 0;          // steps taken without falling
  double min_distance = 0.0;  // m the hip travelled
  // L_step spread (max - min) over the last `spread_steps` steps.
  double max_l_step_spread = std::numeric_limits<double>::infinity();  // m
  int spread_steps = 10;
  // The mean L_step over the same last `spread_steps` steps must be at least this (0: unchecked).
  double min_l_step = 0.0;  // m
  // Velocity tracking: every step at least `settle_steps` steps after the last change of V_d (the
  // steps in between all saw the same V_d), with V_d <= track_up_to, has |V_M - V_d| <= tolerance.
  // V_M here is the stride velocity (mean of the step and the one before: one step of each leg).
  double speed_tolerance = std::numeric_limits<double>::infinity();  // m/s
  int settle_steps = 10;
  double track_up_to = std::numeric_limits<double>::infinity();  // m/s
  // Obstacles: at least this many steps after the hip passed the last obstacle's far edge, and no
  // foot ever landed on an obstacle's top unless allowed.
  int min_steps_after_obstacles = 0;
  bool allow_obstacle_contact = true;
  // Walking scenarios (a pragmatic or fuzzy_cmac controller) with a V_d profile: the hip's forward
  // travel must be at least this share of the integral of V_d over the run (0: unchecked).
  double min_travel_ratio = 0.7;
  // Walking scenarios: when the run ends as `stalled` (rabbit/scenario/stall_watch.h).
  StallCriteria stall;
};

// The walker's gait database and, within it (or named apart), its gait pattern and reference
// gaits, as paths (resolved against the scenario file).
struct GaitPatternFiles {
  std::string fll, networks, gaits;
  std::string database;  // the folder with walker.csv (docs/gait-database.md)
};

struct Scenario {
  std::string file;
  std::string name;
  std::string description;
  ModelParams model;
  std::string model_file;  // the [model] file the model was read from (empty: none)
  ContactParams contact;
  ActuatorParams actuator;
  Terrain terrain;
  SimOptions options;
  Vec7 q0 = Vec7::Zero();
  Vec7 qd0 = Vec7::Zero();
  ControllerKind controller = ControllerKind::kPassive;
  PdHoldParams pd_hold;
  GaitSpec walking;              // kPragmatic: the rules and the documented walking start
  std::string expected_outcome;  // empty: any outcome passes
  // kFuzzyCmac: the walker, its files, the gait it starts from (its documented walking start and
  // pragmatic warm-up), and the baselines to run beside it ("pragmatic", "nearest_gait",
  // "multi_cmac").
  WalkerParams walker;
  WalkerPreset preset = WalkerPreset::kAdaptive;  // `preset`: the settings `walker` was read over
  // The baseline "chapter": the chapter preset with the scenario's keys (set when it is listed).
  WalkerParams chapter_walker;
  GaitPatternFiles pattern;
  // The gait pattern's fuzzy system when [controller.sets] changes the FLL file's membership
  // functions (else empty: the FLL file's, from the gait library).
  std::optional<TsFis> fis;
  // The speed gait the walk starts from (its walking start and warm-up rules, for every variant):
  // the scenario's `start_gait`, else the gait the main walker walks at V_d(0) (walker_keys.cc).
  std::string start_gait;
  // The per-gait walker settings of the database (walker.csv), by gait name; RunScenario turns
  // them into WalkerParams::rule_share in the gait pattern's order.
  std::map<std::string, GaitWalkerSettings> gait_settings;
  std::vector<std::string> baselines;
  // The multi_cmac baseline's settings ([controller.multi_cmac]).
  MultiCmacPatternOptions multi_cmac;
  // The desired velocity V_d(t) (for every walking controller; the baselines only report it).
  VelocityProfile velocity;
  bool has_velocity = false;  // the file gave one (else V_d is not reported: nan)
  std::vector<TrunkPush> pushes;
  PassCriteria criteria;
  bool required = true;  // false: its failures are reported but do not fail the suite
  std::uint64_t seed = 1;
  // The suite's [[family]] this scenario is a member of (empty: a plain scenario); the report
  // compares the variants over a family's members together (rabbit/report/comparison.h).
  std::string family;
};

// Throws InputError naming the file when `root` is another kind of TOML file rabbit reads (a
// suite, a tuning job, gait targets, a parameter overlay: its [suite], [[scenario]] or
// [[family]], [job], [[gait]] or [params], and no [simulation]), saying which command takes it.
void RefuseOtherKindsOfFile(const TomlReader& root);

// Reads and validates a scenario file. Throws InputError naming the file, line and key.
// With an overlay, its parameters replace the scenario's settings (InputError, naming the overlay,
// for a parameter that names no numeric setting of the scenario).
Scenario LoadScenario(const std::string& path, const ParamOverlay* overlay = nullptr);
// Reads and validates one scenario from a table (a scenario file's root, or a suite's scenario
// merged with its defaults); relative paths resolve against the reader's file's directory.
// With `settings`, records the scenario's effective numeric settings (key path -> value, see
// TomlReader::WithObserver): what a parameter overlay can change.
Scenario ReadScenario(TomlReader root, const std::string& default_name,
                      const ParamOverlay* overlay = nullptr,
                      std::map<std::string, double>* settings = nullptr);

// Reads a [model] table (all ModelParams fields, optionally `file = "other.toml"` whose [model]
// table gives the base values). Validates the result. With `file`, records the model file read.
ModelParams ReadModelParams(TomlReader* table, std::string* file = nullptr);
// Reads a model file: a TOML file with a [model] table.
ModelParams LoadModelFile(const std::string& path);

// The controller of a passive, pd_hold or pragmatic scenario (throws std::invalid_argument for
// fuzzy_cmac, whose walker needs its gait pattern: see RunScenario in run.h).
std::unique_ptr<Controller> MakeController(const Scenario& scenario);

// Names that become file or folder names: 1 to kMaxNameChars (100) letters, digits, '.', '_', '-';
// no "..".
bool IsSafeName(const std::string& name);
// What IsSafeName demands, for messages; with the length of `name` when it is too long.
std::string SafeNameRule(const std::string& name);

// The simulation set-up a scenario describes, on `model` (built from scenario.model; it must
// outlive the set-up).
SimSetup MakeSimSetup(const Scenario& scenario, const Model* model);

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_SCENARIO_H_
