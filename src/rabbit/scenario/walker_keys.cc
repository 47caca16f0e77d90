// [controller] of type "fuzzy_cmac": the walker's keys, read over its preset, and its gait
// database, fuzzy system and per-gait settings (docs/formats/scenario.md, "The walker").
#include "rabbit/scenario/walker_keys.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "rabbit/control/rule_gait_choice.h"
#include "rabbit/control/walker_presets.h"
#include "rabbit/gait/gait_database.h"
#include "rabbit/gait/walker_settings.h"
#include "rabbit/io/error.h"
#include "rabbit/learn/fll.h"
#include "rabbit/scenario/keys_internal.h"
#include "rabbit/scenario/slope_keys.h"
#include "rabbit/scenario/stall_recovery_keys.h"
#include "rabbit/scenario/step_map_keys.h"
#include "rabbit/scenario/terrain_step_keys.h"

namespace rabbit {
namespace {

using keys_internal::kDeg;
using keys_internal::Validate;

std::string ResolvePath(const TomlReader& t, const std::string& path) {
  const std::filesystem::path p(path);
  return p.is_absolute() ? path : (std::filesystem::path(t.Directory()) / p).string();
}

// A file's contents as `load` reads them, read once per file and process (again when the file's
// time or size changes): a suite's hundreds of walker scenarios share their database's files.
// Only what loads is kept: a bad file throws each time it is read.
template <typename T, typename Load>
std::shared_ptr<const T> CachedRead(const std::string& path, Load load) {
  static std::mutex mutex;
  using Stamp = std::pair<std::filesystem::file_time_type, std::uintmax_t>;
  static std::map<std::string, std::pair<Stamp, std::shared_ptr<const T>>> cache;
  std::error_code time_error, size_error;
  const Stamp stamp = {std::filesystem::last_write_time(path, time_error),
                       std::filesystem::file_size(path, size_error)};
  const bool stamped = !time_error && !size_error;
  std::lock_guard<std::mutex> lock(mutex);
  auto found = cache.find(path);
  if (stamped && found != cache.end() && found->second.first == stamp) return found->second.second;
  auto value = std::make_shared<const T>(load(path));
  if (stamped) cache[path] = {stamp, value};
  return value;
}

std::shared_ptr<const TsFis> CachedFll(const std::string& path) {
  return CachedRead<TsFis>(path, [](const std::string& p) { return LoadFll(p); });
}

// A membership function's parameters in the FLL's order (Triangle a b c, Trapezoid a b c d,
// Ramp start end, Gaussian mean sd), and back.
std::vector<double> FllParameters(const Membership& m) {
  switch (m.shape) {
    case Membership::Shape::kTriangle:
      return {m.a, m.b, m.c};
    case Membership::Shape::kTrapezoid:
      return {m.a, m.b, m.c, m.d};
    case Membership::Shape::kRampDown:
      return {m.b, m.a};
    case Membership::Shape::kRampUp:
    case Membership::Shape::kGaussian:
      break;
  }
  return {m.a, m.b};
}

Membership FromFllParameters(Membership m, const std::vector<double>& v) {
  if (m.shape == Membership::Shape::kRampUp || m.shape == Membership::Shape::kRampDown) {
    const bool falling = v[0] > v[1];  // Ramp start end
    m.shape = falling ? Membership::Shape::kRampDown : Membership::Shape::kRampUp;
    m.a = falling ? v[1] : v[0];
    m.b = falling ? v[0] : v[1];
    return m;
  }
  m.a = v[0];
  m.b = v[1];
  if (v.size() > 2) m.c = v[2];
  if (v.size() > 3) m.d = v[3];
  return m;
}

// [controller.sets]: <input>.<set> = [parameters in the FLL's order], replacing the FLL file's
// membership functions (every set is readable, so a parameter overlay may tune any breakpoint).
void ReadMembershipSets(TomlReader sets, const TsFis& fll, Scenario* s) {
  TsFis fis = fll;
  bool changed = false;
  for (FuzzyInput& input : fis.inputs) {
    TomlReader table = sets.Table(input.name);
    for (FuzzySet& set : input.sets) {
      const std::vector<double> base = FllParameters(set.membership);
      const std::vector<double> v = table.Doubles(set.name, base, base.size());
      if (v == base) continue;
      set.membership = FromFllParameters(set.membership, v);
      changed = true;
      std::string error;
      if (!set.membership.IsValid(&error)) table.Fail(set.name, error);
    }
    table.Finish();
  }
  sets.Finish();
  if (!changed) return;
  std::string error;
  if (!fis.IsValid(&error)) sets.Fail("", error);
  s->fis = std::move(fis);
}

// [controller.multi_cmac]: the multi_cmac baseline's settings (MultiCmacPatternOptions; angles in
// degrees here).
MultiCmacPatternOptions ReadMultiCmac(TomlReader t) {
  MultiCmacPatternOptions o;
  constexpr long kMaxWidth = 1 << 20;
  o.layers = static_cast<int>(t.Integer("layers", o.layers, 1, kMaxCmacLayers));
  o.e_quantum = t.Double("e_quantum_deg", o.e_quantum / kDeg) * kDeg;
  o.e_width = static_cast<int>(t.Integer("e_width", o.e_width, 1, kMaxWidth));
  o.v_m_quantum = t.Double("v_m_quantum", o.v_m_quantum);
  o.v_m_width = static_cast<int>(t.Integer("v_m_width", o.v_m_width, 1, kMaxWidth));
  o.d_obs_quantum = t.Double("d_obs_quantum", o.d_obs_quantum);
  o.d_obs_width = static_cast<int>(t.Integer("d_obs_width", o.d_obs_width, 1, kMaxWidth));
  o.hash_table_size =
      static_cast<int>(t.Integer("hash_table_size", o.hash_table_size, 1, kMaxMultiCmacTable));
  o.hash_seed = static_cast<std::uint64_t>(
      t.Integer("hash_seed", static_cast<long>(o.hash_seed), 0, std::numeric_limits<long>::max()));
  o.v_m_margin = t.Double("v_m_margin", o.v_m_margin);
  o.grid_e_step = t.Double("grid_e_step_deg", o.grid_e_step / kDeg) * kDeg;
  o.grid_v_m_step = t.Double("grid_v_m_step", o.grid_v_m_step);
  o.grid_d_obs_step = t.Double("grid_d_obs_step", o.grid_d_obs_step);
  o.ridge = t.Double("ridge", o.ridge);
  o.tolerance = t.Double("tolerance", o.tolerance);
  o.max_iterations = static_cast<int>(t.Integer("max_iterations", o.max_iterations, 1, 100000));
  t.Finish();
  for (const auto& [key, value] : {std::pair<const char*, double>{"e_quantum_deg", o.e_quantum},
                                   {"v_m_quantum", o.v_m_quantum},
                                   {"d_obs_quantum", o.d_obs_quantum},
                                   {"grid_e_step_deg", o.grid_e_step},
                                   {"grid_v_m_step", o.grid_v_m_step},
                                   {"grid_d_obs_step", o.grid_d_obs_step},
                                   {"ridge", o.ridge}}) {
    if (!(value > 0.0)) t.Fail(key, "must be > 0");
  }
  if (!(o.tolerance > 0.0 && o.tolerance < 1.0)) t.Fail("tolerance", "must be in (0, 1)");
  if (o.v_m_margin < 0.0) t.Fail("v_m_margin", "must be >= 0");
  for (const auto& [key, width] : {std::pair<const char*, int>{"e_width", o.e_width},
                                   {"v_m_width", o.v_m_width},
                                   {"d_obs_width", o.d_obs_width}}) {
    if (width < o.layers) {
      t.Fail(key, "must be >= layers (" + std::to_string(o.layers) + "): offsets would repeat");
    }
  }
  Validate(t, o);
  return o;
}

// [controller.recovery]: the walker's push recovery (push_recovery.h). Each key is checked here,
// so that an error names its line and key.
void ReadRecovery(TomlReader r, RecoveryParams* p) {
  p->enabled = r.Bool("enabled", p->enabled);
  p->backward_step_speed = r.Double("backward_step_speed", p->backward_step_speed);
  if (std::abs(p->backward_step_speed) > 5.0) {
    r.Fail("backward_step_speed", "must be in [-5, 5] m/s");
  }
  const auto nonnegative = [&r](const char* key, double value, double max, const char* range) {
    const double v = r.Double(key, value);
    if (!(v >= 0.0 && v <= max)) r.Fail(key, std::string("must be in ") + range);
    return v;
  };
  p->placement_gain = nonnegative("placement_gain", p->placement_gain, 10.0, "[0, 10] rad s/m");
  p->placement_max = nonnegative("placement_max", p->placement_max, 1.0, "[0, 1] rad");
  p->placement_start = nonnegative("placement_start", p->placement_start, 10.0, "[0, 10]");
  p->placement_full = nonnegative("placement_full", p->placement_full, 10.0, "[0, 10]");
  p->placement_dead = nonnegative("placement_dead", p->placement_dead, 10.0, "[0, 10] m/s");
  p->trunk_gain = nonnegative("trunk_gain", p->trunk_gain, 10.0, "[0, 10] rad s/m");
  p->trunk_max = nonnegative("trunk_max", p->trunk_max, 1.0, "[0, 1] rad");
  p->nominal_steps = static_cast<int>(r.Integer("nominal_steps", p->nominal_steps, 1, 100));
  p->response_dead = nonnegative("response_dead", p->response_dead, 2.0, "[0, 2] m/s");
  p->response_fis_gain = nonnegative("response_fis_gain", p->response_fis_gain, 10.0, "[0, 10]");
  p->response_fis_max = nonnegative("response_fis_max", p->response_fis_max, 2.0, "[0, 2] m/s");
  p->response_fis_step = nonnegative("response_fis_step", p->response_fis_step, 2.0, "[0, 2] m/s");
  p->response_fis_steps =
      static_cast<int>(r.Integer("response_fis_steps", p->response_fis_steps, 0, 100));
  p->response_hold_steps =
      static_cast<int>(r.Integer("response_hold_steps", p->response_hold_steps, 0, 100));
  p->response_rules_dead =
      nonnegative("response_rules_dead", p->response_rules_dead, 2.0, "[0, 2] m/s");
  p->response_rules_steps =
      static_cast<int>(r.Integer("response_rules_steps", p->response_rules_steps, 0, 100));
  p->response_place_gain =
      nonnegative("response_place_gain", p->response_place_gain, 10.0, "[0, 10] rad s/m");
  p->response_place_max =
      nonnegative("response_place_max", p->response_place_max, 1.0, "[0, 1] rad");
  p->response_place_back =
      nonnegative("response_place_back", p->response_place_back, 1.0, "[0, 1]");
  p->response_trunk_gain = r.Double("response_trunk_gain", p->response_trunk_gain);
  if (!(std::abs(p->response_trunk_gain) <= 10.0)) {
    r.Fail("response_trunk_gain", "must be in [-10, 10] rad s/m");
  }
  p->response_trunk_max =
      nonnegative("response_trunk_max", p->response_trunk_max, 1.0, "[0, 1] rad");
  p->response_catch_back =
      nonnegative("response_catch_back", p->response_catch_back, 0.5, "[0, 0.5] m");
  p->response_catch_from =
      nonnegative("response_catch_from", p->response_catch_from, 1.5, "[0, 1.5]");
  p->response_reach = nonnegative("response_reach", p->response_reach, 1.0, "[0, 1]");
  p->response_reach_dead =
      nonnegative("response_reach_dead", p->response_reach_dead, 2.0, "[0, 2] m/s");
  p->response_reach_ref_min =
      nonnegative("response_reach_ref_min", p->response_reach_ref_min, 2.0, "[0, 2] m/s");
  p->gravity = r.Double("gravity", p->gravity);
  if (!(p->gravity > 0.0 && p->gravity <= 100.0)) r.Fail("gravity", "must be in (0, 100] m/s^2");
  r.Finish();
  std::string error;
  if (!p->IsValid(&error)) r.Fail("", error);
}

// [controller.velocity_control]: the walker's speed transitions (velocity_control.h).
void ReadVelocityControl(TomlReader r, VelocityControlParams* p) {
  p->enabled = r.Bool("enabled", p->enabled);
  p->start_at_map = r.Bool("start_at_map", p->start_at_map);
  p->idle_shift_windup = r.Bool("idle_shift_windup", p->idle_shift_windup);
  for (const VelocityControlRange& range : VelocityControlRanges()) {
    double& value = p->*range.field;
    value = r.Double(range.key, value);
    if (!(value >= range.lo && value <= range.hi)) {
      char text[120];
      std::snprintf(text, sizeof text, "must be in [%g, %g]%s", range.lo, range.hi, range.unit);
      r.Fail(range.key, text);
    }
  }
  p->drop_no_raise = static_cast<int>(r.Integer("drop_no_raise", p->drop_no_raise, 0, 100));
  p->drop_floor_steps =
      static_cast<int>(r.Integer("drop_floor_steps", p->drop_floor_steps, 0, 100));
  p->drop_floor_margin = r.Double("drop_floor_margin_deg", p->drop_floor_margin / kDeg) * kDeg;
  if (!(std::abs(p->drop_floor_margin) <= M_PI / 4)) {
    r.Fail("drop_floor_margin_deg", "must be in [-45, 45] deg");
  }
  const std::string law = r.String("law", p->law == VelocityLaw::kStepMap ? "step_map" : "chapter");
  if (law != "chapter" && law != "step_map") r.Fail("law", "expected \"chapter\" or \"step_map\"");
  p->law = law == "step_map" ? VelocityLaw::kStepMap : VelocityLaw::kChapter;
  ReadStepMapKeys(r.Table("step_map"), &p->step_map);
  // A pitch map's [V_m_s, q0_d_deg] points, checked and in rad.
  auto points = [&r](const char* key) {
    std::vector<std::pair<double, double>> out;
    for (const std::vector<double>& row : r.DoubleRows(key, 2)) {
      if (!(row[0] >= 0.0 && row[0] < 3.0 && std::abs(row[1]) < 45.0)) {
        r.Fail(key, "each point [V_m_s, q0_d_deg] needs V in [0, 3) and |q0_d| < 45");
      }
      out.push_back({row[0], row[1] * kDeg});
    }
    return out;
  };
  // Absent or empty: the reference gaits' map.
  std::vector<std::pair<double, double>> map = points("pitch_map_deg");
  if (!map.empty()) p->pitch_map = std::move(map);
  // Written, even empty, it replaces the preset's (empty: none, the pitch map everywhere).
  if (r.Has("settled_pitch_map_deg")) p->settled_pitch_map = points("settled_pitch_map_deg");
  r.Finish();
}

// The walker's own keys of [controller] but the start's (StartOnGait), read over *w (a preset's
// settings). Its settings are checked once the start gait's are in.
void ReadWalkerKeys(TomlReader* t, const ModelParams& model, WalkerParams* walker) {
  WalkerParams& w = *walker;
  w.warmup_steps = static_cast<int>(t->Integer("warmup_steps", w.warmup_steps, 0, 1000));
  w.warmup_handover_ratio = t->Double("warmup_handover_ratio", w.warmup_handover_ratio);
  w.warmup_handover_after =
      static_cast<int>(t->Integer("warmup_handover_after", w.warmup_handover_after, 0, 1000));
  w.hip_kp = t->Double("hip_kp", w.hip_kp);
  w.hip_kd = t->Double("hip_kd", w.hip_kd);
  w.knee_kp = t->Double("knee_kp", w.knee_kp);
  w.knee_kd = t->Double("knee_kd", w.knee_kd);
  w.stance_knee_kp = t->Double("stance_knee_kp", w.stance_knee_kp);
  w.stance_knee_kd = t->Double("stance_knee_kd", w.stance_knee_kd);
  w.stance_knee_rate = t->Double("stance_knee_rate", w.stance_knee_rate);
  w.stance_knee_flexed = t->Double("stance_knee_flexed_deg", w.stance_knee_flexed / kDeg) * kDeg;
  w.trunk_kp = t->Double("trunk_kp", w.trunk_kp);
  w.trunk_kd = t->Double("trunk_kd", w.trunk_kd);
  w.k_p = t->Double("k_p", w.k_p);
  w.k_v = t->Double("k_v", w.k_v);
  w.q0_d_min = t->Double("q0_d_min_deg", w.q0_d_min / kDeg) * kDeg;
  w.q0_d_max = t->Double("q0_d_max_deg", w.q0_d_max / kDeg) * kDeg;
  w.v_m_average_steps =
      static_cast<int>(t->Integer("v_m_average_steps", w.v_m_average_steps, 1, 100));
  w.fis_v_lead = t->Double("fis_v_lead", w.fis_v_lead);
  w.d_obs_max = t->Double("d_obs_max", w.d_obs_max);
  w.thigh_frame = t->Bool("thigh_frame", w.thigh_frame);
  w.rule_gait_choice = t->Bool("rule_gait_choice", w.rule_gait_choice);
  for (const WalkerRange& range : RuleGaitChoiceRanges()) {
    double& value = w.*range.field;
    value = t->Double(range.key, value);
    if (!(value >= range.lo && value <= range.hi)) {
      char text[120];
      std::snprintf(text, sizeof text, "must be in [%g, %g]%s", range.lo, range.hi, range.unit);
      t->Fail(range.key, text);
    }
  }
  w.lift.clearance = t->Double("lift_clearance", w.lift.clearance);
  w.lift.height_gain = t->Double("lift_height_gain", w.lift.height_gain);
  w.lift.d_obs = t->Double("lift_d_obs", w.lift.d_obs);
  w.lift.lead = t->Double("lift_lead", w.lift.lead);
  w.lift.trail = t->Double("lift_trail", w.lift.trail);
  w.lift.ramp = t->Double("lift_ramp", w.lift.ramp);
  w.lift.release = t->Double("lift_release", w.lift.release);
  w.lift.release_rate = t->Double("lift_release_rate", w.lift.release_rate);
  w.lift.trailing_clearance = t->Double("lift_trailing_clearance", w.lift.trailing_clearance);
  w.lift.feedback = t->Bool("lift_feedback", w.lift.feedback);
  w.lift.keeps_rules = t->Bool("lift_keeps_rules", w.lift.keeps_rules);
  ReadRecovery(t->Table("recovery"), &w.recovery);
  ReadSlopeKeys(t->Table("slope"), &w.slope);
  ReadVelocityControl(t->Table("velocity_control"), &w.velocity_control);
  ReadStallRecovery(t->Table("stall_recovery"), &w.stall_recovery);
  w.stall_recovery.thigh_length = model.thigh_length;
  w.stall_recovery.shin_length = model.shin_length;
  ReadTerrainStepKeys(t->Table("steps"), &w.steps);
  w.steps.thigh_length = model.thigh_length;
  w.steps.shin_length = model.shin_length;
  w.thigh_length = model.thigh_length;
  w.shin_length = model.shin_length;
  {
    // [controller.planner]: the multi-step foot placement over obstacles (step_planner.h).
    TomlReader pt = t->Table("planner");
    StepPlannerParams& pp = w.planner;
    pp.tracked_gaits_only = pt.Bool("tracked_gaits_only", pp.tracked_gaits_only);
    // The preset's (docs/design/step-planner.md, "The step planner").
    pp.enabled = pt.Bool("enabled", pp.enabled);
    pp.horizon = pt.Double("horizon", pp.horizon);
    pp.margin_before = pt.Double("margin_before", pp.margin_before);
    pp.margin_after = pt.Double("margin_after", pp.margin_after);
    pp.l_min = pt.Double("l_min", pp.l_min);
    pp.l_max = pt.Double("l_max", pp.l_max);
    pp.l_nominal = pt.Double("l_nominal", pp.l_nominal);
    pp.l_over_max = pt.Double("l_over_max", pp.l_over_max);
    pp.l_over_min = pt.Double("l_over_min", pp.l_over_min);
    pp.feedback_gain = pt.Double("feedback_gain", pp.feedback_gain);
    pp.bias_initial = pt.Double("bias_initial", pp.bias_initial);
    pp.bias_max = pt.Double("bias_max", pp.bias_max);
    pp.recovery_steps = static_cast<int>(pt.Integer("recovery_steps", pp.recovery_steps, 0, 100));
    pp.stretch = pt.Double("stretch", pp.stretch);
    pp.over_lift_trail = pt.Double("over_lift_trail", pp.over_lift_trail);
    pp.over_lift_release = pt.Double("over_lift_release", pp.over_lift_release);
    pp.hold_margin = pt.Double("hold_margin", pp.hold_margin);
    pp.use_length = pt.Bool("use_length", pp.use_length);
    pp.assumed_length = pt.Double("assumed_length", pp.assumed_length);
    pp.follow_gait = pt.Bool("follow_gait", pp.follow_gait);
    pp.over_feedback = pt.Bool("over_feedback", pp.over_feedback);
    pp.hold_pitch_steps =
        static_cast<int>(pt.Integer("hold_pitch_steps", pp.hold_pitch_steps, 0, 100));
    pp.follow_shorten = pt.Double("follow_shorten", pp.follow_shorten);
    pp.follow_lengthen = pt.Double("follow_lengthen", pp.follow_lengthen);
    pp.approach_speed = pt.Double("approach_speed", pp.approach_speed);
    pp.approach_distance = pt.Double("approach_distance", pp.approach_distance);
    pp.push_dead = pt.Double("push_dead", pp.push_dead);
    pp.end_warmup_within = pt.Double("end_warmup_within", pp.end_warmup_within);
    pt.Finish();
    std::string planner_error;
    if (!pp.IsValid(&planner_error)) {
      // Name the key the message starts with ("planner.l_min ..." or "planner: need ...").
      std::string key;
      const std::string head = "planner.";
      if (planner_error.rfind(head, 0) == 0) {
        key = planner_error.substr(head.size(), planner_error.find(' ') - head.size());
      } else if (planner_error.find("l_min") != std::string::npos) {
        key = "l_min";
      }
      pt.Fail(key, planner_error);
    }
  }
  if (!(w.q0_d_min <= w.q0_d_max)) t->Fail("q0_d_min_deg", "must be <= q0_d_max_deg");
}

// The start gait's settings of the walker: its warm-up rules and step length, and, unless the
// scenario gives q0_d_initial_deg or v_m_initial, its trunk pitch (clamped into the walker's
// range) and V_M. Then the walker's settings are checked.
void StartOnGait(TomlReader* t, const GaitRecord& gait, WalkerParams* walker) {
  WalkerParams& w = *walker;
  w.warmup = gait.spec.rules;
  w.warmup_l_step = gait.measured.l_step;
  w.q0_d_initial = t->Double("q0_d_initial_deg", gait.spec.rules.q0_d / kDeg) * kDeg;
  w.v_m_initial = t->Double("v_m_initial", gait.measured.v_m);
  // A given pitch must lie in the range.
  if (t->Has("q0_d_initial_deg") &&
      !(w.q0_d_initial >= w.q0_d_min && w.q0_d_initial <= w.q0_d_max)) {
    t->Fail("q0_d_initial_deg", "must lie in [q0_d_min_deg, q0_d_max_deg]");
  }
  w.q0_d_initial = std::clamp(w.q0_d_initial, w.q0_d_min, w.q0_d_max);
  std::string error;
  if (!w.IsValid(&error)) t->Fail("", error);
}

// The speed gait whose measured V_M the walker's gait choice moves v0 to, or null where it leaves
// v0 as it is (docs/design/walker.md, "The walker": the start).
const GaitIndexEntry* ChosenStartGait(const std::vector<GaitIndexEntry>& index,
                                      const std::map<std::string, GaitWalkerSettings>& settings,
                                      double v0, double mixed_below, double mixed_point) {
  std::vector<const GaitIndexEntry*> gaits;
  std::vector<double> speeds, shares;
  for (const GaitIndexEntry& e : index) {
    if (e.role != GaitRole::kSpeed) continue;
    const auto it = settings.find(e.name);
    gaits.push_back(&e);
    speeds.push_back(e.measured_v_m);
    shares.push_back(it == settings.end() ? 0.0 : it->second.rule_share);
  }
  const double v = ChooseRuleGait(v0, speeds, shares, mixed_below, mixed_point);
  if (v == v0) return nullptr;
  for (size_t i = 0; i < gaits.size(); ++i) {
    if (speeds[i] == v) return gaits[i];
  }
  return nullptr;
}

}  // namespace

// type = "fuzzy_cmac": the chapter's walker (see FuzzyCmacWalker). Reads the gait database to
// choose the start gait; the walk starts from its documented walking start.
// The gait database (`database`, default the shipped one beside the scenario folder) gives the
// gait pattern's files and the per-gait walker settings; `fll`, `networks` and `gaits` may name
// other files for one part. A database override (`rabbit run --gaits DIR`) replaces all of them.
void ReadFuzzyCmac(TomlReader* t, Scenario* s, const std::string& database_override) {
  namespace fs = std::filesystem;
  s->controller = ControllerKind::kFuzzyCmac;
  GaitPatternFiles& f = s->pattern;
  // A path key given as "" is a mistake (it names nothing); left out, it follows `database`.
  auto path_key = [t](const std::string& key) {
    const std::string path = t->String(key, "");
    if (t->Has(key) && path.empty()) {
      t->Fail(key, "an empty path (name a file or folder, or leave the key out)");
    }
    return path;
  };
  const std::string database_key = t->String("database", "../gaits");
  if (database_key.empty()) t->Fail("database", "an empty path (name the gait database's folder)");
  const std::string database = ResolvePath(*t, database_key);
  const std::string fll = path_key("fll");
  const std::string networks = path_key("networks");
  const std::string gaits = path_key("gaits");
  if (!database_override.empty()) {
    f.database = database_override;
    f.fll = (fs::path(f.database) / "gait_pattern.fll").string();
    f.networks = (fs::path(f.database) / "networks").string();
    f.gaits = (fs::path(f.database) / "reference").string();
  } else {
    f.database = database;
    f.fll = fll.empty() ? (fs::path(database) / "gait_pattern.fll").string() : ResolvePath(*t, fll);
    f.networks =
        networks.empty() ? (fs::path(database) / "networks").string() : ResolvePath(*t, networks);
    f.gaits = gaits.empty() ? (fs::path(database) / "reference").string() : ResolvePath(*t, gaits);
  }
  ReadMembershipSets(t->Table("sets"), *CachedFll(f.fll), s);
  const auto index_file = CachedRead<std::vector<GaitIndexEntry>>(
      (std::filesystem::path(f.gaits) / "index.csv").string(),
      [](const std::string& p) { return ReadGaitIndex(p); });
  const std::vector<GaitIndexEntry>& index = *index_file;
  if (GaitsOfRole(index, GaitRole::kSpeed).empty()) {
    t->Fail("gaits", "the gait database " + f.gaits + " lists no speed gait");
  }
  // The preset the keys are read over (walker_presets.h); a baseline "chapter" is the chapter's
  // preset read with the same keys.
  const std::string preset_name = t->String("preset", "adaptive");
  WalkerPreset preset = WalkerPreset::kAdaptive;
  if (!ParseWalkerPreset(preset_name, &preset)) {
    t->Fail("preset",
            "unknown preset \"" + preset_name + "\" (expected " + WalkerPresetNames() + ")");
  }
  s->preset = preset;
  const auto preset_walker = [&](WalkerPreset which) {
    WalkerParams w = PresetWalkerParams(which);
    // The scenario's perception noise and seed ([noise], read before the controller).
    w.v_m_noise = s->walker.v_m_noise;
    w.d_obs_noise = s->walker.d_obs_noise;
    w.seed = s->walker.seed;
    return w;
  };
  s->walker = preset_walker(preset);
  ReadWalkerKeys(t, s->model, &s->walker);
  if (t->Has("rule_share")) {
    t->Fail("rule_share",
            "per-gait settings are no longer given in a scenario: the rule share of each gait "
            "is the rule_share column of the gait database's walker.csv (" +
                (fs::path(f.database) / kWalkerSettingsFile).string() +
                "; docs/gait-database.md); remove this key");
  }
  // Per-gait settings by name, checked here so that a bad file fails the load (exit 2).
  // gait_rules = false: the chapter's walker (PD tracking of the pattern only), whatever the
  // database's rule shares.
  const bool gait_rules = t->Bool("gait_rules", true);
  s->gait_settings = ReadDatabaseWalkerSettings(f.database);
  for (const auto& entry : s->gait_settings) {
    const std::string& name = entry.first;  // (a structured binding cannot be captured in C++17)
    const bool listed = std::any_of(index.begin(), index.end(),
                                    [&](const GaitIndexEntry& e) { return e.name == name; });
    if (!listed) {
      throw InputError((fs::path(f.database) / kWalkerSettingsFile).string(), 0, name,
                       "walker settings for gait \"" + name + "\", which " + f.gaits +
                           "/index.csv does not list");
    }
  }
  if (!gait_rules) s->gait_settings.clear();
  // The start gait: the one the scenario names, or else the gait the walker walks at V_d(0): the
  // nearest speed gait by measured V_M, or the other gait of a pair where the walker's gait choice
  // (rule_gait_choice.h) moves V_d(0) to it. Started on the nearest gait and handed over to the
  // other, the walker's first strides are those of neither.
  s->start_gait = t->String("start_gait", "");
  const GaitIndexEntry* start = nullptr;
  if (s->start_gait.empty()) {
    const double v0 = s->velocity.At(0.0);
    for (const GaitIndexEntry& e : index) {
      if (e.role != GaitRole::kSpeed) continue;  // the walker starts from a speed gait
      if (start == nullptr || std::abs(e.measured_v_m - v0) < std::abs(start->measured_v_m - v0)) {
        start = &e;
      }
    }
    if (s->walker.rule_gait_choice) {
      const GaitIndexEntry* chosen =
          ChosenStartGait(index, s->gait_settings, v0, s->walker.rule_gait_choice_mixed_below,
                          s->walker.rule_gait_choice_mixed_point);
      if (chosen != nullptr) start = chosen;
    }
    s->start_gait = start->name;
  } else {
    for (const GaitIndexEntry& e : index) {
      if (e.name == s->start_gait) start = &e;
    }
    if (start == nullptr) t->Fail("start_gait", "no gait \"" + s->start_gait + "\" in " + f.gaits);
  }
  const auto gait_file = CachedRead<GaitRecord>(
      (std::filesystem::path(f.gaits) / start->file).string(),
      [](const std::string& p) { return ReadGaitFile(p); });
  s->walking = gait_file->spec;
  StartOnGait(t, *gait_file, &s->walker);
  s->baselines = t->Strings("baselines", {});
  for (size_t i = 0; i < s->baselines.size(); ++i) {
    const std::string& b = s->baselines[i];
    if (b != "pragmatic" && b != "nearest_gait" && b != "multi_cmac" && b != "chapter") {
      t->Fail("baselines", "unknown baseline \"" + b +
                               "\" (expected \"chapter\", \"pragmatic\", \"nearest_gait\" or "
                               "\"multi_cmac\")");
    }
    for (size_t j = 0; j < i; ++j) {
      if (s->baselines[j] == b) t->Fail("baselines", "\"" + b + "\" listed twice");
    }
  }
  if (std::find(s->baselines.begin(), s->baselines.end(), "chapter") != s->baselines.end()) {
    if (preset == WalkerPreset::kChapter) {
      t->Fail("baselines", "\"chapter\" is the main walker here (preset = \"chapter\")");
    }
    s->chapter_walker = preset_walker(WalkerPreset::kChapter);
    // Without the observer: the settings a tuning job sees are the main walker's. The chapter's
    // walker starts on the main walker's start gait.
    TomlReader unobserved = t->WithObserver(nullptr);
    ReadWalkerKeys(&unobserved, s->model, &s->chapter_walker);
    StartOnGait(&unobserved, *gait_file, &s->chapter_walker);
  }
  s->multi_cmac = ReadMultiCmac(t->Table("multi_cmac"));
  t->Finish();
}

}  // namespace rabbit
