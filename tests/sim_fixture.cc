#include "sim_fixture.h"

#include <algorithm>

namespace rabbit::testing {

Vec7 Stance(const Model& model, double clearance, double half_angle_deg) {
  Vec7 q = Vec7::Zero();
  q[kQ11] = half_angle_deg * kDeg;
  q[kQ21] = -half_angle_deg * kDeg;
  q[kY] = 0.0;
  const double lowest = std::min(FootPosition(model, q, 0).y(), FootPosition(model, q, 1).y());
  q[kY] = clearance - lowest;
  return q;
}

PdHoldParams HoldAt(const Vec7& q) {
  PdHoldParams p;
  p.target = q.tail<4>();
  return p;
}

DropMeasures MeasureDrop(const SimResult& r) {
  DropMeasures m;
  for (const SimSample& s : r.samples) {
    for (int leg = 0; leg < kNumLegs; ++leg) {
      const double y = s.foot_pos[leg].y();
      m.deepest = std::min(m.deepest, y);
      if (s.foot_mode[leg] != ContactMode::kAir) m.landed[leg] = true;
      if (m.landed[leg]) m.rebound = std::max(m.rebound, y);
    }
  }
  return m;
}

}  // namespace rabbit::testing
