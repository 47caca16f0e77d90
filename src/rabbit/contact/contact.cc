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

double FootHeight(const Terrain& terrain, const FootContactState& state,
                  const Eigen::Vector2d& pos) {
  return pos.y() - terrain.SurfaceHeight(state.surface);
}

namespace {

double NormalForce(const ContactParams& p, double y, double yd) {
  if (y > 0.0) return 0.0;
  const double depth = -y;
  return std::max(0.0, p.k_n * depth - p.lambda_n * depth * yd);
}
double StickForce(const ContactParams& p, const FootContactState& s, double x, double xd) {
  return -p.k_t * (x - s.anchor_x) - p.lambda_t * xd;
}
double SlideForce(const ContactParams& p, const FootContactState& s, double fn, double xd) {
  return -s.slide_dir * p.lambda_g * fn - p.mu_g * xd;
}
double Sign(double v) { return v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0); }

}  // namespace

FootForce ComputeFootForce(const ContactParams& params, const Terrain& terrain,
                           const FootContactState& state, const Eigen::Vector2d& pos,
                           const Eigen::Vector2d& vel) {
  FootForce f;
  if (state.mode == ContactMode::kAir) return f;
  f.fn = NormalForce(params, FootHeight(terrain, state, pos), vel.y());
  f.ft = state.mode == ContactMode::kStick ? StickForce(params, state, pos.x(), vel.x())
                                           : SlideForce(params, state, f.fn, vel.x());
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
      const double fn = NormalForce(params, FootHeight(terrain, state, pos), vel.y());
      return params.mu_s * fn - std::abs(StickForce(params, state, pos.x(), vel.x()));
    }
    case ContactMode::kSlide:
      return state.slide_dir * vel.x();
  }
  return 1.0;
}

double ResumeGuard(const ContactParams& params, const Terrain& terrain,
                   const FootContactState& state, const Eigen::Vector2d& pos,
                   const Eigen::Vector2d& vel) {
  if (state.mode != ContactMode::kSlide) return 1.0;
  const double fn = NormalForce(params, FootHeight(terrain, state, pos), vel.y());
  return (params.mu_g + params.lambda_t) * std::abs(vel.x()) -
         params.resume_fraction * (params.mu_s - params.lambda_g) * fn;
}

double SpanGuard(const Terrain& terrain, const FootContactState& state, const Eigen::Vector2d& pos,
                 int obstacle) {
  const Obstacle& o = terrain.obstacles[obstacle];
  const double inside = std::min(pos.x() - o.x_start, o.x_end() - pos.x());
  return state.surface == obstacle ? inside : -inside;
}

void OnTouchEvent(const Eigen::Vector2d& pos, const Eigen::Vector2d& vel, FootContactState* state) {
  if (state->mode != ContactMode::kAir) {
    state->mode = ContactMode::kAir;
    return;
  }
  state->anchor_x = pos.x();
  state->slide_dir = Sign(vel.x());
  state->mode = state->slide_dir == 0.0 ? ContactMode::kStick : ContactMode::kSlide;
}

void OnFrictionEvent(const ContactParams& params, const Terrain& terrain,
                     const Eigen::Vector2d& pos, const Eigen::Vector2d& vel,
                     FootContactState* state) {
  const double fn = NormalForce(params, FootHeight(terrain, *state, pos), vel.y());
  if (state->mode == ContactMode::kStick) {
    // Slip follows the velocity; a foot still at rest slips away from the restoring force.
    const double ft = StickForce(params, *state, pos.x(), vel.x());
    state->slide_dir = vel.x() != 0.0 ? Sign(vel.x()) : -Sign(ft);
    if (state->slide_dir == 0.0) state->slide_dir = 1.0;
    state->mode = ContactMode::kSlide;
  } else if (state->mode == ContactMode::kSlide) {
    // The slip stopped or slowed enough: re-anchor so that the spring carries the sliding force.
    state->anchor_x = pos.x() + SlideForce(params, *state, fn, vel.x()) / params.k_t;
    state->mode = ContactMode::kStick;
  }
}

bool UpdateFootSurface(const Terrain& terrain, const Eigen::Vector2d& pos,
                       FootContactState* state) {
  const int surface = terrain.SurfaceAt(pos.x());
  if (surface == state->surface) return true;
  if (surface != kGround && pos.y() < terrain.SurfaceHeight(surface)) return false;  // trip
  state->surface = surface;
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
  if (FootHeight(terrain, state, pos) <= kOnSurfaceTolerance) {
    state.mode = ContactMode::kStick;
    state.anchor_x = pos.x();
  }
  return state;
}

double ContactElasticEnergy(const ContactParams& params, const Terrain& terrain,
                            const FootContactState& state, const Eigen::Vector2d& pos) {
  if (state.mode == ContactMode::kAir) return 0.0;
  const double y = std::min(0.0, FootHeight(terrain, state, pos));
  const double dx = state.mode == ContactMode::kStick ? pos.x() - state.anchor_x : 0.0;
  return 0.5 * params.k_n * y * y + 0.5 * params.k_t * dx * dx;
}

}  // namespace rabbit
