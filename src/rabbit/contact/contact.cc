#include "rabbit/contact/contact.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace rabbit {

bool ContactParams::IsValid(std::string* error) const {
  const std::vector<std::pair<const char*, double>> values = {
      {"k_n", k_n},   {"lambda_n", lambda_n}, {"k_t", k_t},  {"lambda_t", lambda_t},
      {"mu_s", mu_s}, {"lambda_g", lambda_g}, {"mu_g", mu_g}};
  for (const auto& [name, value] : values) {
    if (!std::isfinite(value) || value < 0.0) {
      *error = std::string(name) + " must be a finite number >= 0";
      return false;
    }
  }
  if (k_n <= 0.0 || k_t <= 0.0) {
    *error = "k_n and k_t must be > 0";
    return false;
  }
  if (!(resume_fraction >= 0.0 && resume_fraction <= 1.0)) {
    *error = "resume_fraction must be in [0, 1]";
    return false;
  }
  if (lambda_g > mu_s) {
    *error = "lambda_g (dynamic friction) must not exceed mu_s (static friction)";
    return false;
  }
  return true;
}

const char* ContactModeName(ContactMode mode) {
  switch (mode) {
    case ContactMode::kAir:
      return "air";
    case ContactMode::kStick:
      return "stick";
    case ContactMode::kSlide:
      return "slide";
  }
  return "?";
}

namespace {

// A foot's position and velocity in the frame of the straight surface under it (see contact.h):
// y, yd along the normal, stretch (the sticking spring's, from its anchor) and xd along the
// tangent, and the frame's direction (cos, sin of the slope).
struct LocalFoot {
  double y = 0.0, yd = 0.0, stretch = 0.0, xd = 0.0;
  double cos_slope = 1.0, sin_slope = 0.0;
};

LocalFoot ToSurface(const Terrain& terrain, const FootContactState& state,
                    const Eigen::Vector2d& pos, const Eigen::Vector2d& vel) {
  LocalFoot l;
  if (state.surface != kGround) {  // an obstacle's top: flat
    l.y = pos.y() - terrain.ObstacleTop(state.surface);
    l.yd = vel.y();
    l.stretch = pos.x() - state.anchor_x;
    l.xd = vel.x();
    return l;
  }
  const GroundSegment& g = terrain.ground.segment(state.segment);
  const double gap = pos.y() - g.HeightAt(pos.x());  // vertical
  if (g.sin_slope == 0.0) {                          // flat: the world frame (exactly)
    l.y = gap;
    l.yd = vel.y();
    l.stretch = pos.x() - state.anchor_x;
    l.xd = vel.x();
    return l;
  }
  const double c = g.cos_slope, s = g.sin_slope;
  l.cos_slope = c;
  l.sin_slope = s;
  l.y = gap * c;
  l.yd = vel.x() * s + vel.y() * c;
  l.stretch = (pos.x() - state.anchor_x) / c - gap * s;
  l.xd = vel.x() * c - vel.y() * s;
  return l;
}

double NormalForce(const ContactParams& p, double y, double yd) {
  if (y > 0.0) return 0.0;
  const double depth = -y;
  return std::max(0.0, p.k_n * depth - p.lambda_n * depth * yd);
}
double StickForce(const ContactParams& p, const LocalFoot& l) {
  return -p.k_t * l.stretch - p.lambda_t * l.xd;
}
double SlideForce(const ContactParams& p, const FootContactState& s, double fn, double xd) {
  return -s.slide_dir * p.lambda_g * fn - p.mu_g * xd;
}
double Sign(double v) { return v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0); }

// Touchdown with tangential velocity xd (see OnTouchEvent).
void TouchTransition(const Eigen::Vector2d& pos, double xd, FootContactState* state) {
  if (state->mode != ContactMode::kAir) {
    state->mode = ContactMode::kAir;
    return;
  }
  state->anchor_x = pos.x();
  state->slide_dir = Sign(xd);
  state->mode = state->slide_dir == 0.0 ? ContactMode::kStick : ContactMode::kSlide;
}

}  // namespace

double FootHeight(const Terrain& terrain, const FootContactState& state,
                  const Eigen::Vector2d& pos) {
  return ToSurface(terrain, state, pos, Eigen::Vector2d::Zero()).y;
}

FootForce ComputeFootForce(const ContactParams& params, const Terrain& terrain,
                           const FootContactState& state, const Eigen::Vector2d& pos,
                           const Eigen::Vector2d& vel) {
  FootForce f;
  if (state.mode == ContactMode::kAir) return f;
  const LocalFoot l = ToSurface(terrain, state, pos, vel);
  f.fn = NormalForce(params, l.y, l.yd);
  f.ft = state.mode == ContactMode::kStick ? StickForce(params, l)
                                           : SlideForce(params, state, f.fn, l.xd);
  if (l.sin_slope == 0.0) {
    f.fx = f.ft;
    f.fy = f.fn;
  } else {
    f.fx = f.ft * l.cos_slope + f.fn * l.sin_slope;
    f.fy = f.fn * l.cos_slope - f.ft * l.sin_slope;
  }
  return f;
}

double TouchGuard(const Terrain& terrain, const FootContactState& state,
                  const Eigen::Vector2d& pos) {
  const double y = FootHeight(terrain, state, pos);
  return state.mode == ContactMode::kAir ? y : -y;
}

double SlipGuard(const ContactParams& params, const Terrain& terrain, const FootContactState& state,
                 const Eigen::Vector2d& pos, const Eigen::Vector2d& vel) {
  switch (state.mode) {
    case ContactMode::kAir:
      return 1.0;
    case ContactMode::kStick: {
      const LocalFoot l = ToSurface(terrain, state, pos, vel);
      const double fn = NormalForce(params, l.y, l.yd);
      return params.mu_s * fn - std::abs(StickForce(params, l));
    }
    case ContactMode::kSlide:
      return state.slide_dir * ToSurface(terrain, state, pos, vel).xd;
  }
  return 1.0;
}

double ResumeGuard(const ContactParams& params, const Terrain& terrain,
                   const FootContactState& state, const Eigen::Vector2d& pos,
                   const Eigen::Vector2d& vel) {
  if (state.mode != ContactMode::kSlide) return 1.0;
  const LocalFoot l = ToSurface(terrain, state, pos, vel);
  const double fn = NormalForce(params, l.y, l.yd);
  return (params.mu_g + params.lambda_t) * std::abs(l.xd) -
         params.resume_fraction * (params.mu_s - params.lambda_g) * fn;
}

double SpanGuard(const Terrain& terrain, const FootContactState& state, const Eigen::Vector2d& pos,
                 int obstacle) {
  const Obstacle& o = terrain.obstacles[obstacle];
  const double inside = std::min(pos.x() - o.x_start, o.x_end() - pos.x());
  return state.surface == obstacle ? inside : -inside;
}

double SegmentGuard(const Terrain& terrain, const FootContactState& state,
                    const Eigen::Vector2d& pos) {
  const GroundSegment& g = terrain.ground.segment(state.segment);
  return std::min(pos.x() - g.x_start, g.x_end - pos.x());
}

void OnTouchEvent(const Terrain& terrain, const Eigen::Vector2d& pos, const Eigen::Vector2d& vel,
                  FootContactState* state) {
  TouchTransition(pos, ToSurface(terrain, *state, pos, vel).xd, state);
}

void OnTouchEvent(const Eigen::Vector2d& pos, const Eigen::Vector2d& vel, FootContactState* state) {
  TouchTransition(pos, vel.x(), state);
}

void OnFrictionEvent(const ContactParams& params, const Terrain& terrain,
                     const Eigen::Vector2d& pos, const Eigen::Vector2d& vel,
                     FootContactState* state) {
  const LocalFoot l = ToSurface(terrain, *state, pos, vel);
  const double fn = NormalForce(params, l.y, l.yd);
  if (state->mode == ContactMode::kStick) {
    // Slip follows the velocity; a foot still at rest slips away from the restoring force.
    const double ft = StickForce(params, l);
    state->slide_dir = l.xd != 0.0 ? Sign(l.xd) : -Sign(ft);
    if (state->slide_dir == 0.0) state->slide_dir = 1.0;
    state->mode = ContactMode::kSlide;
  } else if (state->mode == ContactMode::kSlide) {
    // The slip stopped or slowed enough: re-anchor so that the spring carries the sliding force,
    // at the surface point Ft2 / k_t along the tangent from the foot's projection onto it.
    const double shift = SlideForce(params, *state, fn, l.xd) / params.k_t;
    state->anchor_x =
        l.sin_slope == 0.0 ? pos.x() + shift : pos.x() - l.y * l.sin_slope + shift * l.cos_slope;
    state->mode = ContactMode::kStick;
  }
}

bool UpdateFootSurface(const Terrain& terrain, const Eigen::Vector2d& pos,
                       FootContactState* state) {
  const int surface = terrain.SurfaceAt(pos.x());
  const int segment = terrain.ground.SegmentAt(pos.x());
  if (surface == state->surface && segment == state->segment) return true;
  if (surface != state->surface && surface != kGround && pos.y() < terrain.ObstacleTop(surface)) {
    return false;  // trip
  }
  // Onto the ground across a step, below the level beyond it: the foot hit the step's face.
  if (surface == kGround && segment != state->segment &&
      terrain.ground.StepBetween(segment, state->segment) &&
      pos.y() < terrain.ground.segment(segment).HeightAt(pos.x())) {
    return false;  // trip
  }
  // A sticking foot crossing a breakpoint of the ground keeps its spring's stretch: the anchor
  // moves onto the new segment's line (re-measured there, the foot's depth along the old normal
  // would turn into a stretch along the new tangent, a jump in the friction force).
  const bool keep_stretch = state->mode == ContactMode::kStick && surface == kGround &&
                            state->surface == kGround && segment != state->segment;
  const double stretch =
      keep_stretch ? ToSurface(terrain, *state, pos, Eigen::Vector2d::Zero()).stretch : 0.0;
  state->surface = surface;
  state->segment = segment;
  if (keep_stretch) {
    const GroundSegment& g = terrain.ground.segment(segment);
    const double gap = pos.y() - g.HeightAt(pos.x());
    state->anchor_x = pos.x() - g.cos_slope * (stretch + gap * g.sin_slope);
  }
  if (state->mode != ContactMode::kAir && FootHeight(terrain, *state, pos) > 0.0) {
    state->mode = ContactMode::kAir;
  }
  return true;
}

FootContactState InitialFootState(const Terrain& terrain, const Eigen::Vector2d& pos) {
  // A foot placed "on" the ground by a computed pose may sit a rounding error above it.
  constexpr double kOnSurfaceTolerance = 1e-9;  // m
  FootContactState state;
  state.surface = terrain.SurfaceAt(pos.x());
  state.segment = terrain.ground.SegmentAt(pos.x());
  if (FootHeight(terrain, state, pos) <= kOnSurfaceTolerance) {
    state.mode = ContactMode::kStick;
    state.anchor_x = pos.x();
  }
  return state;
}

double ContactElasticEnergy(const ContactParams& params, const Terrain& terrain,
                            const FootContactState& state, const Eigen::Vector2d& pos) {
  if (state.mode == ContactMode::kAir) return 0.0;
  const LocalFoot l = ToSurface(terrain, state, pos, Eigen::Vector2d::Zero());
  const double y = std::min(0.0, l.y);
  const double dx = state.mode == ContactMode::kStick ? l.stretch : 0.0;
  return 0.5 * params.k_n * y * y + 0.5 * params.k_t * dx * dx;
}

}  // namespace rabbit
