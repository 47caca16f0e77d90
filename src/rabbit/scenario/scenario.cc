#include "rabbit/scenario/scenario.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <limits>
#include <map>
#include <mutex>
#include <utility>

#include "rabbit/gait/gait_database.h"
#include "rabbit/gait/walker_settings.h"
#include "rabbit/io/error.h"
#include "rabbit/io/limits.h"
#include "rabbit/io/toml_reader.h"
#include "rabbit/learn/fll.h"
#include "rabbit/scenario/controller_keys.h"
#include "rabbit/scenario/keys_internal.h"
#include "rabbit/scenario/params.h"
#include "rabbit/scenario/terrain_keys.h"
#include "rabbit/scenario/walker_keys.h"

namespace rabbit {
namespace {

using keys_internal::kDeg;
using keys_internal::Validate;

constexpr double kMaxControlRate = 1e5;  // Hz
constexpr double kMaxPeriods = 1e8;      // control periods in one run
// A foot may start at most this deep in its surface (a computed pose on the ground sinks ~2 mm
// under load; deeper is a mistake in the scenario).
constexpr double kMaxInitialPenetration = 0.005;  // m
constexpr double kMaxInitialSpeed = 20.0;         // m/s or rad/s, any coordinate
// A run given by distance only stops at the latest after this time.
constexpr double kDefaultDistanceTimeLimit = 600.0;  // s

// The initial state must be physically sensible: finite, bounded rates, feet not deep in the
// ground, no link inside an obstacle.
void ValidateInitialState(const TomlReader& t, const Model& model, const Scenario& s) {
  if (!s.q0.allFinite() || !s.qd0.allFinite()) t.Fail("", "initial state is not finite");
  if (s.q0.tail<5>().cwiseAbs().maxCoeff() > 2 * M_PI) t.Fail("", "angles beyond +-360 deg");
  if (s.qd0.cwiseAbs().maxCoeff() > kMaxInitialSpeed) {
    t.Fail("", "initial rates beyond 20 m/s or rad/s");
  }
  if (std::abs(s.q0[kX]) > 1e3 || s.q0[kY] > 1e3) t.Fail("", "hip position beyond 1 km");
  const Pose pose = ComputePose(model, s.q0);
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const Vec2& foot = pose.foot[leg];
    const double depth = s.terrain.HeightAt(foot.x()) - foot.y();
    if (depth > kMaxInitialPenetration) {
      t.Fail("", "foot " + std::to_string(leg + 1) + " starts " +
                     std::to_string(static_cast<int>(std::lround(depth * 1000))) +
                     " mm below its surface (at most 5 mm)");
    }
    for (const auto& [a, b] : {std::pair<Vec2, Vec2>{pose.hip, pose.knee[leg]},
                               std::pair<Vec2, Vec2>{pose.knee[leg], pose.foot[leg]},
                               std::pair<Vec2, Vec2>{pose.hip, pose.trunk_top}}) {
      const int hit = s.terrain.SegmentHitsObstacle(a, b, 0.01);
      if (hit >= 0) {
        t.Fail("", "the robot starts inside obstacle " + std::to_string(hit + 1));
      }
    }
  }
}

void ReadModelFields(TomlReader* t, ModelParams* p) {
  p->trunk_mass = t->Double("trunk_mass", p->trunk_mass);
  p->trunk_com = t->Double("trunk_com", p->trunk_com);
  p->trunk_inertia = t->Double("trunk_inertia", p->trunk_inertia);
  p->trunk_length = t->Double("trunk_length", p->trunk_length);
  p->thigh_mass = t->Double("thigh_mass", p->thigh_mass);
  p->thigh_length = t->Double("thigh_length", p->thigh_length);
  p->thigh_com = t->Double("thigh_com", p->thigh_com);
  p->thigh_inertia = t->Double("thigh_inertia", p->thigh_inertia);
  p->shin_mass = t->Double("shin_mass", p->shin_mass);
  p->shin_length = t->Double("shin_length", p->shin_length);
  p->shin_com = t->Double("shin_com", p->shin_com);
  p->shin_inertia = t->Double("shin_inertia", p->shin_inertia);
  p->rotor_inertia = t->Double("rotor_inertia", p->rotor_inertia);
  p->gear_ratio = t->Double("gear_ratio", p->gear_ratio);
  p->gravity = t->Double("gravity", p->gravity);
}

ContactParams ReadContact(TomlReader t) {
  ContactParams p;
  p.k_n = t.Double("k_n", p.k_n);
  p.lambda_n = t.Double("lambda_n", p.lambda_n);
  p.k_t = t.Double("k_t", p.k_t);
  p.lambda_t = t.Double("lambda_t", p.lambda_t);
  p.mu_s = t.Double("mu_s", p.mu_s);
  p.lambda_g = t.Double("lambda_g", p.lambda_g);
  p.mu_g = t.Double("mu_g", p.mu_g);
  p.resume_fraction = t.Double("resume_fraction", p.resume_fraction);
  t.Finish();
  Validate(t, p);
  return p;
}

ActuatorParams ReadActuator(TomlReader t) {
  ActuatorParams p;
  p.enabled = t.Bool("enabled", p.enabled);
  p.max_torque = t.Double("max_torque", p.max_torque);
  p.max_power = t.Double("max_power", p.max_power);
  p.full_torque_speed = t.Double("full_torque_speed", p.full_torque_speed);
  p.max_speed = t.Double("max_speed", p.max_speed);
  t.Finish();
  Validate(t, p);
  return p;
}

void ReadSimulation(TomlReader t, Scenario* s) {
  SimOptions& o = s->options;
  if (t.Has("distance")) {
    o.stop_distance = t.Double("distance", 0.0);
    if (!(o.stop_distance > 0.0 && o.stop_distance <= 1e4)) {
      t.Fail("distance", "must be in (0, 1e4] m");
    }
    o.duration = t.Double("duration", kDefaultDistanceTimeLimit);
  } else {
    o.duration = t.RequiredDouble("duration");
  }
  if (!(o.duration >= 0.0 && o.duration <= kMaxDurationS)) {
    t.Fail("duration",
           "must be in [0, " + FormatLimit(kMaxDurationS) + "] s, got " + FormatLimit(o.duration));
  }
  const double rate = t.Double("control_rate_hz", 1.0 / o.control_period);
  if (!(rate >= 1.0 && rate <= kMaxControlRate)) {
    t.Fail("control_rate_hz",
           "must be in [1, " + std::to_string(static_cast<long>(kMaxControlRate)) + "] Hz");
  }
  o.control_period = 1.0 / rate;
  const std::string integrator = t.String("integrator", IntegratorName(o.integrator.kind));
  if (!ParseIntegratorName(integrator, &o.integrator.kind)) {
    t.Fail("integrator",
           "expected \"cvode\", \"cvode-adams\" or \"arkode\", got \"" + integrator + "\"");
  }
  o.integrator.rtol = t.Double("rtol", o.integrator.rtol);
  o.integrator.atol = t.Double("atol", o.integrator.atol);
  o.integrator.max_step = t.Double("max_step", o.integrator.max_step);
  o.integrator.order = static_cast<int>(t.Integer("order", o.integrator.order, 0, 12));
  o.integrator.fixed_step = t.Double("fixed_step", o.integrator.fixed_step);
  o.contact = t.Bool("contact", o.contact);
  o.restart_at_samples = t.Bool("restart_at_samples", o.restart_at_samples);
  // 0 (record nothing) is for internal runs only: distance, speed and cost of transport come from
  // the samples.
  o.record_every = static_cast<int>(t.Integer("record_every", o.record_every, 1, 1000000));
  if (t.Has("max_wall_s")) {
    o.max_wall = t.Double("max_wall_s", 0.0);
    if (!(o.max_wall > 0.0)) t.Fail("max_wall_s", "must be > 0 s");
  }
  if (!t.Bool("gravity", true)) s->model.gravity = 0.0;
  t.Finish();
  if (o.duration / o.control_period > kMaxPeriods) {
    t.Fail("duration", "too long for the control rate (more than 1e8 control periods)");
  }
  if (o.duration / o.control_period / o.record_every > kMaxRecordedSamples) {
    t.Fail("record_every", "the run would record more than " + FormatLimit(kMaxRecordedSamples) +
                               " samples (duration / control period / record_every): raise "
                               "record_every or shorten the run");
  }
  std::string error;
  if (!o.IsValid(&error)) t.Fail("", error);
}

void ReadFall(TomlReader t, FallCriteria* f) {
  f->enabled = t.Bool("enabled", f->enabled);
  f->min_hip_height = t.Double("min_hip_height", f->min_hip_height);
  f->max_trunk_pitch = t.Double("max_trunk_pitch_deg", f->max_trunk_pitch / kDeg) * kDeg;
  if (f->max_trunk_pitch <= 0.0) t.Fail("max_trunk_pitch_deg", "must be > 0");
  t.Finish();
}

void ReadInitial(TomlReader t, const Model& model, Scenario* s) {
  Vec7& q = s->q0;
  Vec7& qd = s->qd0;
  q[kX] = t.Double("x", 0.0);
  q[kQ0] = t.Double("q0_deg", 0.0) * kDeg;
  q[kQ11] = t.Double("q11_deg", 0.0) * kDeg;
  q[kQ12] = t.Double("q12_deg", 0.0) * kDeg;
  q[kQ21] = t.Double("q21_deg", 0.0) * kDeg;
  q[kQ22] = t.Double("q22_deg", 0.0) * kDeg;
  qd[kX] = t.Double("xd", 0.0);
  qd[kY] = t.Double("yd", 0.0);
  qd[kQ0] = t.Double("q0d_deg_s", 0.0) * kDeg;
  qd[kQ11] = t.Double("q11d_deg_s", 0.0) * kDeg;
  qd[kQ12] = t.Double("q12d_deg_s", 0.0) * kDeg;
  qd[kQ21] = t.Double("q21d_deg_s", 0.0) * kDeg;
  qd[kQ22] = t.Double("q22d_deg_s", 0.0) * kDeg;
  const bool has_y = t.Has("y"), has_clearance = t.Has("foot_clearance");
  if (has_y == has_clearance) {
    t.Fail("",
           "give exactly one of 'y' (hip height, m) or 'foot_clearance' (lowest foot "
           "above the ground, m)");
  }
  if (has_y) {
    q[kY] = t.Double("y", 0.0);
  } else {
    // Hip height that puts the lowest foot at the requested clearance above its surface.
    const double clearance = t.Double("foot_clearance", 0.0);
    double y = -1e9;
    for (int leg = 0; leg < kNumLegs; ++leg) {
      Vec7 at_zero = q;
      at_zero[kY] = 0.0;
      const Vec2 foot = FootPosition(model, at_zero, leg);
      y = std::max(y, s->terrain.HeightAt(foot.x()) + clearance - foot.y());
    }
    q[kY] = y;
  }
  t.Finish();
}

// [velocity]: profile = "constant" (value = V_d) | "ramp" | "steps" (points = [[t_s, v_m_s], ...]).
VelocityProfile ReadVelocity(TomlReader t) {
  VelocityProfile v;
  const std::string kind = t.String("profile", "constant");
  if (kind == "constant") {
    v.kind = VelocityProfile::Kind::kConstant;
  } else if (kind == "ramp") {
    v.kind = VelocityProfile::Kind::kRamp;
  } else if (kind == "steps") {
    v.kind = VelocityProfile::Kind::kSteps;
  } else {
    t.Fail("profile", "expected \"constant\", \"ramp\" or \"steps\", got \"" + kind + "\"");
  }
  v.points.clear();
  if (v.kind == VelocityProfile::Kind::kConstant && t.Has("value")) {
    if (t.Has("points")) t.Fail("points", "a constant profile takes value or points, not both");
    v.points.push_back({0.0, t.Double("value", 0.0)});
  }
  for (const std::vector<double>& row : t.DoubleRows("points", 2)) {
    v.points.push_back({row[0], row[1]});
  }
  t.Finish();
  if (v.points.empty()) {
    t.Fail(v.kind == VelocityProfile::Kind::kConstant ? "value" : "points",
           "the velocity profile has no points (give value = V_d, or points = [[t_s, V_d], ...])");
  }
  std::string error;
  if (!v.IsValid(&error)) t.Fail("points", error);
  return v;
}

PassCriteria ReadCriteria(TomlReader t) {
  PassCriteria c;
  constexpr long kMaxSteps = 1000000;
  c.min_steps = static_cast<int>(t.Integer("min_steps", c.min_steps, 0, kMaxSteps));
  c.min_distance = t.Double("min_distance_m", c.min_distance);
  c.max_l_step_spread = t.Double("max_l_step_spread_m", c.max_l_step_spread);
  c.spread_steps = static_cast<int>(t.Integer("spread_steps", c.spread_steps, 1, kMaxSteps));
  c.min_l_step = t.Double("min_l_step_m", c.min_l_step);
  c.speed_tolerance = t.Double("speed_tolerance_m_s", c.speed_tolerance);
  c.settle_steps = static_cast<int>(t.Integer("settle_steps", c.settle_steps, 0, kMaxSteps));
  c.track_up_to = t.Double("track_up_to_m_s", c.track_up_to);
  c.min_steps_after_obstacles = static_cast<int>(
      t.Integer("min_steps_after_obstacles", c.min_steps_after_obstacles, 0, kMaxSteps));
  c.allow_obstacle_contact = t.Bool("allow_obstacle_contact", c.allow_obstacle_contact);
  c.min_travel_ratio = t.Double("min_travel_ratio", c.min_travel_ratio);
  c.stall.no_touchdown = t.Double("stall_no_touchdown_s", c.stall.no_touchdown);
  c.stall.window = t.Double("stall_window_s", c.stall.window);
  c.stall.min_advance = t.Double("stall_min_advance_m", c.stall.min_advance);
  t.Finish();
  for (const auto& [key, value] : {std::pair<const char*, double>{"min_distance_m", c.min_distance},
                                   {"max_l_step_spread_m", c.max_l_step_spread},
                                   {"min_l_step_m", c.min_l_step},
                                   {"speed_tolerance_m_s", c.speed_tolerance},
                                   {"track_up_to_m_s", c.track_up_to},
                                   {"min_travel_ratio", c.min_travel_ratio},
                                   {"stall_no_touchdown_s", c.stall.no_touchdown},
                                   {"stall_window_s", c.stall.window},
                                   {"stall_min_advance_m", c.stall.min_advance}}) {
    if (value < 0.0) t.Fail(key, "must be >= 0");
  }
  return c;
}

}  // namespace

std::string SafeNameRule(const std::string& name) {
  std::string rule = "use 1 to " + std::to_string(kMaxNameChars) +
                     " letters, digits, '.', '_' and '-' (no \"..\")";
  if (name.size() > kMaxNameChars) rule += ", got " + std::to_string(name.size()) + " characters";
  return rule;
}

bool IsSafeName(const std::string& name) {
  if (name.empty() || name.size() > kMaxNameChars || name == "." ||
      name.find("..") != std::string::npos) {
    return false;
  }
  for (char c : name) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-')) {
      return false;
    }
  }
  return true;
}

ModelParams ReadModelParams(TomlReader* t, std::string* file) {
  ModelParams p;
  const std::string base = t->String("file", "");
  if (!base.empty()) {
    const std::filesystem::path path = std::filesystem::path(t->Directory()) / base;
    if (!std::filesystem::is_regular_file(path)) {
      t->Fail("file", "no model file " + path.string());
    }
    p = LoadModelFile(path.string());
    if (file != nullptr) *file = path.string();
  }
  ReadModelFields(t, &p);
  t->Finish();
  Validate(*t, p);
  return p;
}

ModelParams LoadModelFile(const std::string& path) {
  TomlReader root = TomlReader::ParseFile(path);
  TomlReader model = root.Table("model");
  ModelParams p;
  ReadModelFields(&model, &p);
  model.Finish();
  root.Finish();
  Validate(model, p);
  return p;
}

void RefuseOtherKindsOfFile(const TomlReader& root) {
  // The other TOML files rabbit reads, by the table each one has at its root: without this, the
  // first required key a scenario lacks would be the message. A file with a [simulation] table is
  // a scenario, whatever else it holds: a stray `gait = ...` or [params] in it is named as an
  // unknown key, with its line.
  if (root.layers().empty() || root.Has("simulation")) return;
  const toml::table& top = *root.layers().front();
  constexpr const char* kSuite = "this is a suite of scenarios: run it with `rabbit run`";
  constexpr const char* kElse = ", not a scenario or a suite: ";
  struct Kind {
    const char* key;
    bool array_of_tables;  // [[key]] rather than [key]
    std::string message;
  };
  const Kind kinds[] = {
      {"suite", false, kSuite},
      {"scenario", true, kSuite},
      {"family", true, kSuite},
      {"job", false, std::string("this is a tuning job") + kElse + "run it with `rabbit tune`"},
      {"gait", true,
       std::string("this is a gait targets file") + kElse +
           "build it with `rabbit gaits build` (or `rabbit gaits generate`)"},
      {"params", false,
       std::string("this is a parameter overlay") + kElse + "give it to a command with --params"}};
  for (const Kind& kind : kinds) {
    const toml::node* node = top.get(kind.key);
    if (node != nullptr && (kind.array_of_tables ? node->is_array_of_tables() : node->is_table())) {
      throw InputError(root.file(), 0, "", kind.message);
    }
  }
}

Scenario LoadScenario(const std::string& path, const ParamOverlay* overlay) {
  TomlReader root = TomlReader::ParseFile(path);
  RefuseOtherKindsOfFile(root);
  return ReadScenario(root, std::filesystem::path(path).stem().string(), overlay);
}

Scenario ReadScenario(TomlReader root, const std::string& default_name, const ParamOverlay* overlay,
                      std::map<std::string, double>* settings) {
  if (settings != nullptr) {
    auto observed = std::make_shared<std::map<std::string, double>>();
    Scenario s = ReadScenario(root.WithObserver(observed), default_name, overlay, nullptr);
    *settings = std::move(*observed);
    return s;
  }
  const std::string database_override = overlay != nullptr ? overlay->gait_database : "";
  if (overlay != nullptr && !overlay->empty()) {
    TomlReader patched = root.WithPatches(
        overlay->Patches(), std::make_shared<const TomlReader::PatchBlame>(
                                [overlay](const std::string& path, const std::string& message) {
                                  overlay->Fail(path, message);
                                }));
    ParamOverlay database_only;
    database_only.gait_database = database_override;
    Scenario s = ReadScenario(patched, default_name, &database_only);
    const std::vector<std::string> unused = patched.UnusedPatches();
    if (!unused.empty()) {
      overlay->Fail(unused.front(), "names no numeric setting of scenario \"" + s.name + "\" (" +
                                        s.file + ", controller " + ControllerName(s.controller) +
                                        "): see docs/formats/overlay.md");
    }
    return s;
  }
  Scenario s;
  s.file = root.file();
  s.name = root.String("name", default_name);
  if (s.name.empty()) root.Fail("name", "missing: every scenario of a suite needs a name");
  if (!IsSafeName(s.name)) {
    root.Fail("name", SafeNameRule(s.name) + " (it names the output folder)");
  }
  // "shards" is where a sharded run's parts wait for their merge (rabbit/report/shards.h).
  if (s.name == "summary.csv" || s.name == "comparison.csv" || s.name == "targets.csv" ||
      s.name == "members.csv" || s.name == "push_survival.csv" || s.name == "index.html" ||
      s.name == "shards" || s.name[0] == '.') {
    root.Fail("name", "\"" + s.name + "\" is taken by the report's own files");
  }
  s.description = root.String("description", "");
  s.expected_outcome = root.String("expect_outcome", "");
  Outcome expected;
  if (!s.expected_outcome.empty() && !ParseOutcome(s.expected_outcome, &expected)) {
    std::string names;
    for (Outcome o : kAllOutcomes) {
      names += std::string(names.empty() ? "" : ", ") + "\"" + OutcomeName(o) + "\"";
    }
    root.Fail("expect_outcome", "expected one of " + names);
  }
  s.required = root.Bool("required", s.required);
  s.seed = static_cast<std::uint64_t>(root.Integer("seed", 1, 0, std::numeric_limits<long>::max()));
  TomlReader model_table = root.Table("model");
  s.model = ReadModelParams(&model_table, &s.model_file);
  ReadSimulation(root.Table("simulation"), &s);  // may switch gravity off in s.model
  s.contact = ReadContact(root.Table("contact"));
  s.actuator = ReadActuator(root.Table("actuator"));
  s.terrain = ReadTerrain(root.Table("terrain"), &s.model);
  ReadFall(root.Table("fall"), &s.options.fall);
  s.pushes = ReadPushes(&root);
  s.criteria = ReadCriteria(root.Table("criteria"));
  s.has_velocity = root.Has("velocity");
  if (s.has_velocity) s.velocity = ReadVelocity(root.WholeTable("velocity"));
  TomlReader noise = root.Table("noise");
  s.walker.v_m_noise = noise.Double("v_m_std", 0.0);
  s.walker.d_obs_noise = noise.Double("d_obs_std", 0.0);
  noise.Finish();
  if (s.walker.v_m_noise < 0.0) noise.Fail("v_m_std", "must be >= 0");
  if (s.walker.d_obs_noise < 0.0) noise.Fail("d_obs_std", "must be >= 0");
  s.walker.seed = s.seed;
  TomlReader controller = ControllerTable(&root);
  const std::string type = controller.String("type", "passive");
  if (type != "passive" && type != "pd_hold" && type != "pragmatic" && type != "fuzzy_cmac") {
    controller.Fail("type", "unknown controller \"" + type +
                                "\" (expected \"passive\", \"pd_hold\", \"pragmatic\" or "
                                "\"fuzzy_cmac\")");
  }
  if (type == "pragmatic" || type == "fuzzy_cmac") {
    if (type == "pragmatic") {
      ReadPragmatic(&controller, &s);
    } else {
      if (!root.Has("velocity")) {
        root.Fail("velocity", "the fuzzy_cmac controller needs a [velocity] profile");
      }
      ReadFuzzyCmac(&controller, &s, database_override);
    }
    // The walk starts from the documented walking start: [initial] takes no keys.
    TomlReader initial = root.Table("initial");
    initial.Finish();
    WalkingStartState(Model(s.model), s.walking.rules, s.walking.start_speed, s.walking.start_angle,
                      0, &s.q0, &s.qd0);
    ValidateInitialState(initial, Model(s.model), s);
  } else {
    const TomlReader initial = root.Table("initial");
    ReadInitial(initial, Model(s.model), &s);
    ValidateInitialState(initial, Model(s.model), s);
    ReadController(controller, &s);
  }
  root.Finish();
  return s;
}

std::unique_ptr<Controller> MakeController(const Scenario& scenario) {
  switch (scenario.controller) {
    case ControllerKind::kPdHold:
      return std::make_unique<PdHoldController>(scenario.pd_hold);
    case ControllerKind::kPragmatic:
      return std::make_unique<PragmaticController>(scenario.walking.rules, 0);
    case ControllerKind::kFuzzyCmac:
      throw std::invalid_argument(
          "fuzzy_cmac scenarios need their gait pattern: run them with RunScenario (run.h)");
    case ControllerKind::kPassive:
      break;
  }
  return std::make_unique<PassiveController>();
}

SimSetup MakeSimSetup(const Scenario& scenario, const Model* model) {
  SimSetup setup;
  setup.model = model;
  setup.contact = scenario.contact;
  setup.actuator = scenario.actuator;
  setup.terrain = scenario.terrain;
  setup.pushes = scenario.pushes;
  setup.options = scenario.options;
  return setup;
}

}  // namespace rabbit
