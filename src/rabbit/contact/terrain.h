// Terrain: the ground, a piecewise-linear height profile (flat y = 0 by default) with vertical
// steps, plus rectangular obstacles standing on flat parts of it (docs/design/model.md, "Contact").
#ifndef RABBIT_CONTACT_TERRAIN_H_
#define RABBIT_CONTACT_TERRAIN_H_

#include <Eigen/Core>
#include <cmath>
#include <string>
#include <vector>

namespace rabbit {

struct Obstacle {
  double x_start = 0.0;  // near edge, m
  double length = 0.0;   // along x, m
  double height = 0.0;   // m, above the ground it stands on
  double x_end() const { return x_start + length; }
};

// A breakpoint of the ground profile: from x_start on (up to the next breakpoint) the ground has
// this slope; with a rise, the ground jumps there by `rise` (a vertical step, its face at x_start).
struct SlopeBreak {
  double x_start = 0.0;  // m
  // rad, positive when the ground descends toward +x: the sign of the uniform slope
  // (ModelParams::slope), so that a breakpoint's slope means what `slope_deg` means.
  double slope = 0.0;
  double rise = 0.0;  // m, + up (toward +x), - down; 0: the ground is continuous here
};

// A straight piece of ground, y = height + grade (x - x_ref) for x in [x_start, x_end). The
// surface's unit tangent is t = (cos_slope, -sin_slope) (toward +x), its unit normal
// n = (sin_slope, cos_slope) (out of the ground).
struct GroundSegment {
  double x_start = 0.0, x_end = 0.0;  // m; -inf and +inf at the ends of the profile
  double x_ref = 0.0, height = 0.0;   // m, a point (x_ref, height) of the segment
  double slope = 0.0;                 // rad, positive descending toward +x
  double grade = 0.0;                 // dy/dx = -tan(slope)
  double cos_slope = 1.0, sin_slope = 0.0;
  double HeightAt(double x) const { return height + grade * (x - x_ref); }
};

// The ground's height profile y = H(x): piecewise linear, continuous but at steps (breakpoints
// with a rise, where H jumps; H(x_start) is the new level), flat before the first breakpoint,
// with H(0) = 0 (at a step at 0: the level before it). Segment 0 is the flat lead-in before the
// first breakpoint, segment i > 0 starts at breakpoint i - 1. No breakpoints: flat ground y = 0
// (one segment).
class GroundProfile {
 public:
  GroundProfile();
  // Breakpoints in increasing x_start (IsValid checks them and their bounds).
  explicit GroundProfile(std::vector<SlopeBreak> breaks);

  // Finite breakpoints, strictly increasing x_start within +-1e4 m, |slope| < kMaxSlope,
  // |rise| <= kMaxRise; else names the breakpoint (1-based) in *error.
  bool IsValid(std::string* error) const;
  const std::vector<SlopeBreak>& breaks() const { return breaks_; }
  // True when the ground is the default y = 0 (no breakpoint).
  bool is_flat_zero() const { return breaks_.empty(); }

  int num_segments() const { return static_cast<int>(segments_.size()); }
  const GroundSegment& segment(int i) const { return segments_[i]; }
  // The segment holding x (a breakpoint belongs to the segment it starts).
  int SegmentAt(double x) const;
  double HeightAt(double x) const { return segments_[SegmentAt(x)].HeightAt(x); }
  double SlopeAt(double x) const { return segments_[SegmentAt(x)].slope; }
  // Whether the boundary between segments a and b (any order) holds a step: a foot crossing it
  // below the new segment hits the step's face.
  bool StepBetween(int a, int b) const;
  // The ground's outline over [x_lo, x_hi] as a polyline for drawing: the ends, every breakpoint
  // inside, and at a step both levels (a vertical face).
  std::vector<Eigen::Vector2d> Outline(double x_lo, double x_hi) const;

  static constexpr double kMaxSlope = 30.0 * M_PI / 180.0;  // rad
  static constexpr double kMaxAbsX = 1e4;                   // m
  static constexpr double kMaxRise = 1.0;                   // m, a step's |rise|

 private:
  std::vector<SlopeBreak> breaks_;
  std::vector<GroundSegment> segments_;
};

// A surface index names where a foot stands: kGround, or the index of an obstacle (its top).
constexpr int kGround = -1;

struct Terrain {
  std::vector<Obstacle> obstacles;  // sorted by x_start, not overlapping, on flat ground
  GroundProfile ground;             // default: flat y = 0

  // The profile is valid; obstacles have finite values, length and height > 0, are sorted, do not
  // overlap, and each stands on one flat segment of the ground; else names the problem in *error.
  bool IsValid(std::string* error) const;
  // The surface below x: the obstacle whose span [x_start, x_end] holds x, else kGround.
  int SurfaceAt(double x) const;
  // Height of the ground at x (obstacles aside).
  double GroundHeight(double x) const { return ground.HeightAt(x); }
  // Obstacle i stands on the ground's height at its near edge (a flat part: the same all along).
  double ObstacleBase(int i) const { return ground.HeightAt(obstacles[i].x_start); }
  double ObstacleTop(int i) const { return ObstacleBase(i) + obstacles[i].height; }
  // Height of the surface at x: an obstacle's top over its span, else the ground.
  double HeightAt(double x) const {
    const int surface = SurfaceAt(x);
    return surface == kGround ? GroundHeight(x) : ObstacleTop(surface);
  }
  // Index of the first obstacle whose interior, lowered by top_margin (the contact penetration
  // allowed to a foot standing on it), the segment a-b enters; -1 when none.
  int SegmentHitsObstacle(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                          double top_margin) const;
  // Index of the first breakpoint with a step whose face (the vertical from the lower level to
  // the upper one lowered by top_margin) the segment a-b crosses; -1 when none.
  int SegmentHitsStepFace(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                          double top_margin) const;
  // Horizontal distance from x to the near edge of the next obstacle ahead (x_start >= x), or
  // +infinity when there is none.
  double DistanceToNextObstacle(double x) const;
};

}  // namespace rabbit

#endif  // RABBIT_CONTACT_TERRAIN_H_
