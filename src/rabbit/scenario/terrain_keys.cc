#include "rabbit/scenario/terrain_keys.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <utility>

#include "rabbit/scenario/keys_internal.h"

namespace rabbit {

using keys_internal::kDeg;
using keys_internal::Validate;

Terrain ReadTerrain(TomlReader t, ModelParams* model) {
  Terrain terrain;
  model->slope = t.Double("slope_deg", model->slope / kDeg) * kDeg;
  Validate(t, *model);
  std::vector<SlopeBreak> breaks;
  std::vector<TomlReader> rows = t.TableArray("slopes");
  for (size_t i = 0; i < rows.size(); ++i) {
    TomlReader& b = rows[i];
    SlopeBreak brk;
    brk.x_start = b.RequiredDouble("x_start");
    const double slope_deg = b.RequiredDouble("slope_deg");
    b.Finish();
    if (std::abs(brk.x_start) > GroundProfile::kMaxAbsX) b.Fail("x_start", "beyond +-1e4 m");
    if (!(std::abs(slope_deg * kDeg) < GroundProfile::kMaxSlope)) {
      b.Fail("slope_deg", "must be below 30 deg in magnitude");
    }
    if (i > 0 && !(brk.x_start > breaks.back().x_start)) {
      char message[120];
      std::snprintf(message, sizeof message,
                    "breakpoints must be in increasing x_start (the previous one is at %g m)",
                    breaks.back().x_start);
      b.Fail("x_start", message);
    }
    brk.slope = slope_deg * kDeg;
    breaks.push_back(brk);
  }
  if (!breaks.empty() && model->slope != 0.0) {
    t.Fail("slopes",
           "a ground profile does not combine with a uniform slope_deg (the tilted-gravity frame): "
           "give one of them (a profile with one breakpoint before the walk is a uniform slope)");
  }
  // Vertical steps: breakpoints with a rise, on whatever slope the profile has there (one at a
  // slope breakpoint's x_start joins it).
  std::vector<TomlReader> steps = t.TableArray("steps");
  double previous_step = -std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < steps.size(); ++i) {
    TomlReader& st = steps[i];
    const double x = st.RequiredDouble("x_start");
    const double rise = st.RequiredDouble("rise");
    st.Finish();
    if (std::abs(x) > GroundProfile::kMaxAbsX) st.Fail("x_start", "beyond +-1e4 m");
    if (!(x > previous_step)) {
      char message[120];
      std::snprintf(message, sizeof message,
                    "steps must be in increasing x_start (the previous one is at %g m)",
                    previous_step);
      st.Fail("x_start", message);
    }
    previous_step = x;
    if (rise == 0.0 || std::abs(rise) > GroundProfile::kMaxRise) {
      st.Fail("rise", "a step's rise is nonzero and within +-1 m (+ up, - down)");
    }
    if (model->slope != 0.0) {
      st.Fail("x_start",
              "steps do not combine with a uniform slope_deg (the tilted-gravity frame): give the "
              "slope as a ground profile ([[terrain.slopes]])");
    }
    auto at = std::lower_bound(breaks.begin(), breaks.end(), x,
                               [](const SlopeBreak& b, double v) { return b.x_start < v; });
    if (at != breaks.end() && at->x_start == x) {
      at->rise = rise;
    } else {
      SlopeBreak brk;
      brk.x_start = x;
      brk.slope = at == breaks.begin() ? 0.0 : std::prev(at)->slope;
      brk.rise = rise;
      breaks.insert(at, brk);
    }
  }
  if (!breaks.empty()) terrain.ground = GroundProfile(std::move(breaks));
  std::vector<TomlReader> obstacles = t.TableArray("obstacles");
  for (size_t i = 0; i < obstacles.size(); ++i) {
    TomlReader& o = obstacles[i];
    Obstacle obstacle;
    obstacle.x_start = o.RequiredDouble("x_start");
    obstacle.length = o.RequiredDouble("length");
    obstacle.height = o.RequiredDouble("height");
    o.Finish();
    if (obstacle.length <= 0.0) o.Fail("length", "must be > 0");
    if (obstacle.height <= 0.0) o.Fail("height", "must be > 0");
    const GroundProfile& ground = terrain.ground;
    const GroundSegment& under = ground.segment(ground.SegmentAt(obstacle.x_start));
    if (under.slope != 0.0 || obstacle.x_end() > under.x_end) {
      o.Fail("x_start",
             "the obstacle stands on sloped ground (its span must lie on one flat part of "
             "[terrain] slopes; its base is the ground's height there)");
    }
    terrain.obstacles.push_back(obstacle);
  }
  t.Finish();
  Validate(t, terrain);
  return terrain;
}

std::vector<TrunkPush> ReadPushes(TomlReader* root) {
  std::vector<TrunkPush> pushes;
  for (TomlReader& t : root->TableArray("push")) {
    TrunkPush p;
    // When: a start time, or an event (a touchdown, the hip passing a point, or both).
    const bool on_event = t.Has("after_touchdown") || t.Has("at_hip_x");
    if (on_event && t.Has("start")) {
      t.Fail("start",
             "a push starts at `start` or on an event (after_touchdown, at_hip_x), "
             "not both");
    }
    if (!on_event) p.start = t.RequiredDouble("start");
    constexpr long kMaxTouchdown = 100000;
    p.after_touchdown = static_cast<int>(t.Integer("after_touchdown", 0, 1, kMaxTouchdown));
    if (t.Has("phase") && p.after_touchdown == 0) {
      t.Fail("phase", "phase times a push after a touchdown: give after_touchdown = k too");
    }
    p.phase = t.Double("phase", 0.0);
    if (!(p.phase >= 0.0 && p.phase <= 1.0)) t.Fail("phase", "a fraction of the step in [0, 1]");
    if (t.Has("at_hip_x")) {
      p.at_hip_x = t.Double("at_hip_x", 0.0);
      if (std::abs(p.at_hip_x) > 1e4) t.Fail("at_hip_x", "beyond +-1e4 m");
    }
    p.duration = t.Double("duration", p.duration);
    if (!(p.duration > 0.0)) t.Fail("duration", "must be > 0 s");
    // How much: a force, or an impulse over the duration (force_x = impulse_n_s / duration).
    if (t.Has("impulse_n_s")) {
      if (t.Has("force_x")) t.Fail("impulse_n_s", "give force_x or impulse_n_s, not both");
      p.force.x() = t.Double("impulse_n_s", 0.0) / p.duration;
    } else {
      p.force.x() = t.Double("force_x", 0.0);
    }
    p.force.y() = t.Double("force_y", 0.0);
    p.height = t.Double("height", p.height);
    t.Finish();
    std::string error;
    if (!p.IsValid(&error)) t.Fail("", error);
    pushes.push_back(p);
  }
  return pushes;
}
}  // namespace rabbit
