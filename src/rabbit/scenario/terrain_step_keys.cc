#include "rabbit/scenario/terrain_step_keys.h"

#include <string>

namespace rabbit {

void ReadTerrainStepKeys(TomlReader r, TerrainStepParams* p) {
  p->enabled = r.Bool("enabled", p->enabled);
  const auto in = [&r](const char* key, double value, double lo, double hi, const char* range) {
    const double v = r.Double(key, value);
    if (!(v >= lo && v <= hi)) r.Fail(key, std::string("must be in ") + range);
    return v;
  };
  p->reach = in("reach", p->reach, 0.0, 2.0, "[0, 2] m");
  p->clearance = in("clearance", p->clearance, 0.0, 2.0, "[0, 2] m");
  p->lead = in("lead", p->lead, 0.0, 2.0, "[0, 2] m");
  p->trail = in("trail", p->trail, 0.0, 2.0, "[0, 2] m");
  p->ramp = in("ramp", p->ramp, 0.0, 2.0, "[0, 2] m");
  p->release = in("release", p->release, 0.0, 2.0, "[0, 2] m");
  p->placement = r.Bool("placement", p->placement);
  p->face_before = in("face_before", p->face_before, 0.0, 2.0, "[0, 2] m");
  p->face_after = in("face_after", p->face_after, 0.0, 2.0, "[0, 2] m");
  p->up_lean = in("up_lean", p->up_lean, -20.0, 20.0, "[-20, 20] rad/m");
  p->down_lean = in("down_lean", p->down_lean, -20.0, 20.0, "[-20, 20] rad/m");
  p->lean_steps = static_cast<int>(r.Integer("lean_steps", p->lean_steps, 0, 100));
  p->knee_share = in("knee_share", p->knee_share, 0.0, 1.0, "[0, 1]");
  p->knee_ramp_s = in("knee_ramp_s", p->knee_ramp_s, 0.0, 2.0, "[0, 2] s");
  p->up_knee_share = in("up_knee_share", p->up_knee_share, 0.0, 1.0, "[0, 1]");
  p->up_knee_ramp_s = in("up_knee_ramp_s", p->up_knee_ramp_s, 0.0, 2.0, "[0, 2] s");
  p->up_knee_by_hip = r.Bool("up_knee_by_hip", p->up_knee_by_hip);
  p->up_knee_at = in("up_knee_at", p->up_knee_at, -1.0, 1.0, "[-1, 1] m");
  p->up_speed = in("up_speed", p->up_speed, 0.0, 2.0, "[0, 2] m/s");
  p->down_speed = in("down_speed", p->down_speed, 0.0, 2.0, "[0, 2] m/s");
  p->speed_before = in("speed_before", p->speed_before, 0.0, 5.0, "[0, 5] m");
  p->hold_steps = static_cast<int>(r.Integer("hold_steps", p->hold_steps, 0, 100));
  r.Finish();
  std::string error;
  if (!p->IsValid(&error)) r.Fail("", error);
}

}  // namespace rabbit
