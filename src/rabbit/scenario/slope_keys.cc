#include "rabbit/scenario/slope_keys.h"

#include <cmath>
#include <string>

namespace rabbit {
namespace {
constexpr double kDeg = M_PI / 180.0;
}  // namespace

void ReadSlopeKeys(TomlReader r, SlopeParams* p) {
  p->enabled = r.Bool("enabled", p->enabled);
  const auto bounded = [&r](const char* key, double value, double lo, double hi) {
    const double v = r.Double(key, value);
    if (!(v >= lo && v <= hi)) {
      r.Fail(key, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    return v;
  };
  p->filter = r.Double("filter", p->filter);
  if (!(p->filter > 0.0 && p->filter <= 1.0)) r.Fail("filter", "must be in (0, 1]");
  p->slope_max = bounded("slope_max_deg", p->slope_max / kDeg, 0.0, 28.0) * kDeg;
  p->min_baseline = bounded("min_baseline", p->min_baseline, 0.0, 1.0);
  p->trunk_gain = bounded("trunk_gain", p->trunk_gain, -10.0, 10.0);
  p->trunk_max = bounded("trunk_max_deg", p->trunk_max / kDeg, 0.0, 28.0) * kDeg;
  p->frame_gain = bounded("frame_gain", p->frame_gain, -10.0, 10.0);
  p->fis_gain = bounded("fis_gain", p->fis_gain, -10.0, 10.0);
  p->overshoot_margin = bounded("overshoot_margin", p->overshoot_margin, 0.0, 10.0);
  p->overshoot_gain = bounded("overshoot_gain", p->overshoot_gain, 0.0, 10.0);
  p->preview = bounded("preview", p->preview, 0.0, 2.0);
  p->touchdown_heights = r.Bool("touchdown_heights", p->touchdown_heights);
  p->uphill_boost = bounded("uphill_boost", p->uphill_boost, 0.0, 10.0);
  p->downhill_brake = bounded("downhill_brake", p->downhill_brake, 0.0, 10.0);
  p->speed_lookahead = bounded("speed_lookahead", p->speed_lookahead, 0.0, 10.0);
  p->speed_floor = bounded("speed_floor", p->speed_floor, 0.0, 2.0);
  r.Finish();
  std::string error;
  if (!p->IsValid(&error)) r.Fail("", error);
}

}  // namespace rabbit
