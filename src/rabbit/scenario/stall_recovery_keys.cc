#include "rabbit/scenario/stall_recovery_keys.h"

#include <cmath>
#include <string>

namespace rabbit {

void ReadStallRecovery(TomlReader r, StallRecoveryParams* p) {
  p->enabled = r.Bool("enabled", p->enabled);
  const auto in = [&r](const char* key, double value, double lo, double hi, const char* range) {
    const double v = r.Double(key, value);
    if (!(v >= lo && v <= hi)) r.Fail(key, std::string("must be in ") + range);
    return v;
  };
  p->speed = in("speed", p->speed, -2.0, 2.0, "[-2, 2] m/s");
  p->hold_s = in("hold_s", p->hold_s, 0.0, 10.0, "[0, 10] s");
  p->pulse_s = in("pulse_s", p->pulse_s, 0.0, 10.0, "[0, 10] s");
  p->ramp_s = in("ramp_s", p->ramp_s, 0.0, 10.0, "[0, 10] s");
  p->push_off = in("push_off", p->push_off, -1.0, 1.0, "[-1, 1] rad");
  p->trunk_lean = in("trunk_lean", p->trunk_lean, -1.0, 1.0, "[-1, 1] rad");
  p->knee_dip = in("knee_dip", p->knee_dip, 0.0, 1.0, "[0, 1] rad");
  p->catch_speed = in("catch_speed", p->catch_speed, 0.0, 2.0, "[0, 2] m/s");
  p->catch_margin = in("catch_margin", p->catch_margin, -0.5, 0.5, "[-0.5, 0.5] m");
  p->catch_max = in("catch_max", p->catch_max, 0.0, 1.2, "[0, 1.2] rad");
  p->catch_knee = in("catch_knee", p->catch_knee, 0.0, 1.5, "[0, 1.5] rad");
  r.Finish();
  std::string error;
  if (!p->IsValid(&error)) r.Fail("", error);
}

}  // namespace rabbit
