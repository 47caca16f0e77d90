#include "rabbit/scenario/controller_keys.h"

#include <filesystem>
#include <string>
#include <vector>

#include "rabbit/gait/gait_database.h"
#include "rabbit/scenario/keys_internal.h"

namespace rabbit {

using keys_internal::kDeg;
using keys_internal::Validate;

const char* ControllerName(ControllerKind kind) {
  switch (kind) {
    case ControllerKind::kPdHold:
      return "pd_hold";
    case ControllerKind::kPragmatic:
      return "pragmatic";
    case ControllerKind::kFuzzyCmac:
      return "fuzzy_cmac";
    case ControllerKind::kPassive:
      break;
  }
  return "passive";
}

// passive or pd_hold (ReadScenario has checked the type).
void ReadController(TomlReader t, Scenario* s) {
  const std::string type = t.String("type", "passive");
  if (type == "passive") {
    s->controller = ControllerKind::kPassive;
  } else if (type == "pd_hold") {
    s->controller = ControllerKind::kPdHold;
    PdHoldParams& p = s->pd_hold;
    // Gains: one number for all four joints, or four [hip1, knee1, hip2, knee2].
    for (const char* key : {"kp", "kd"}) {
      Vec4* out = std::string(key) == "kp" ? &p.kp : &p.kd;
      if (t.IsArray(key)) {
        const std::vector<double> v = t.Doubles(key, {}, 4);
        *out = Vec4(v[0], v[1], v[2], v[3]);
      } else {
        *out = Vec4::Constant(t.Double(key, (*out)[0]));
      }
    }
    const std::vector<double> target = t.Doubles(
        "target_deg",
        {s->q0[kQ11] / kDeg, s->q0[kQ12] / kDeg, s->q0[kQ21] / kDeg, s->q0[kQ22] / kDeg}, 4);
    p.target = Vec4(target[0], target[1], target[2], target[3]) * kDeg;
    Validate(t, p);
  }
  t.Finish();
}

// type = "pragmatic": the five rules, from a gait file (`gait`, relative to the scenario) and/or
// single keys; the walk starts from WalkingStartState.
void ReadPragmatic(TomlReader* t, Scenario* s) {
  s->controller = ControllerKind::kPragmatic;
  GaitSpec& spec = s->walking;
  const std::string gait = t->String("gait", "");
  if (!gait.empty()) {
    spec = ReadGaitFile((std::filesystem::path(t->Directory()) / gait).string()).spec;
  }
  PragmaticParams& r = spec.rules;
  r.qr1_dsw = t->Double("qr1_dsw_deg", r.qr1_dsw / kDeg) * kDeg;
  r.qi2_dsw = t->Double("qi2_dsw_deg", r.qi2_dsw / kDeg) * kDeg;
  r.q0_d = t->Double("q0_d_deg", r.q0_d / kDeg) * kDeg;
  r.pulse_torque = t->Double("pulse_torque", r.pulse_torque);
  r.pulse_start = t->Double("pulse_start", r.pulse_start);
  r.pulse_duration = t->Double("pulse_duration", r.pulse_duration);
  r.hip_kp = t->Double("hip_kp", r.hip_kp);
  r.hip_kd = t->Double("hip_kd", r.hip_kd);
  r.trunk_kp = t->Double("trunk_kp", r.trunk_kp);
  r.trunk_kd = t->Double("trunk_kd", r.trunk_kd);
  r.knee_kp = t->Double("knee_kp", r.knee_kp);
  r.knee_kd = t->Double("knee_kd", r.knee_kd);
  spec.start_speed = t->Double("start_speed", spec.start_speed);
  spec.start_angle = t->Double("start_angle_deg", spec.start_angle / kDeg) * kDeg;
  t->Finish();
  Validate(*t, spec);
}

TomlReader ControllerTable(TomlReader* root) {
  const std::vector<const toml::table*>& layers = root->layers();
  std::string type;
  for (size_t i = 0; i < layers.size(); ++i) {
    const toml::node* table = layers[i]->get("controller");
    const toml::node* node =
        table != nullptr && table->is_table() ? table->as_table()->get("type") : nullptr;
    if (node == nullptr || !node->is_string()) continue;
    const std::string here = node->as_string()->get();
    if (type.empty()) {
      type = here;
    } else if (here != type) {
      return root->TableFromLayers("controller", i);
    }
  }
  return root->Table("controller");
}
}  // namespace rabbit
