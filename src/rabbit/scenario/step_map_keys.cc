#include "rabbit/scenario/step_map_keys.h"

#include <cmath>
#include <string>
#include <vector>

namespace rabbit {
namespace {
constexpr double kDeg = M_PI / 180.0;
}  // namespace

void ReadStepMapKeys(TomlReader r, StepMapParams* p) {
  // Absent or empty: the shipped bands. Rows [V_m_s, q_star_deg, a, b_m_s_per_deg].
  const std::vector<std::vector<double>> rows = r.DoubleRows("bands", 4);
  if (!rows.empty()) {
    p->bands.clear();
    for (const std::vector<double>& row : rows) {
      p->bands.push_back({row[0], row[1] * kDeg, row[2], row[3] / kDeg});
    }
  }
  p->decay = r.Double("decay", p->decay);
  if (!(p->decay >= 0.0 && p->decay < 1.0)) r.Fail("decay", "must be in [0, 1)");
  p->offset_gain = r.Double("offset_gain", p->offset_gain);
  if (!(p->offset_gain >= 0.0 && p->offset_gain <= 1.0)) r.Fail("offset_gain", "must be in [0, 1]");
  p->offset_max = r.Double("offset_max", p->offset_max);
  if (!(p->offset_max >= 0.0 && p->offset_max <= 1.0))
    r.Fail("offset_max", "must be in [0, 1] m/s");
  p->max_change = r.Double("max_change_deg", p->max_change / kDeg) * kDeg;
  if (!(p->max_change > 0.0 && p->max_change <= M_PI / 4)) {
    r.Fail("max_change_deg", "must be in (0, 45]");
  }
  p->fis_gain = r.Double("fis_gain", p->fis_gain);
  if (!(p->fis_gain >= 0.0 && p->fis_gain <= 2.0)) r.Fail("fis_gain", "must be in [0, 2]");
  p->fis_max = r.Double("fis_max", p->fis_max);
  if (!(p->fis_max >= 0.0 && p->fis_max <= 1.0)) r.Fail("fis_max", "must be in [0, 1] m/s");
  r.Finish();
  std::string error;
  if (!p->IsValid(&error)) r.Fail("bands", error);
}

}  // namespace rabbit
