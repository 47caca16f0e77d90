// Terrain: flat ground y = 0 plus rectangular obstacles standing on it (DESIGN.md section 1).
#ifndef RABBIT_CONTACT_TERRAIN_H_
#define RABBIT_CONTACT_TERRAIN_H_

#include <Eigen/Core>
#include <string>
#include <vector>

namespace rabbit {

struct Obstacle {
  double x_start = 0.0;  // near edge, m
  double length = 0.0;   // along x, m
  double height = 0.0;   // m
  double x_end() const { return x_start + length; }
};

// A surface index names where a foot stands: kGround, or the index of an obstacle (its top).
constexpr int kGround = -1;

struct Terrain {
  std::vector<Obstacle> obstacles;  // sorted by x_start, not overlapping

  // Finite values, length and height > 0, sorted, no overlap; else names the obstacle in *error.
  bool IsValid(std::string* error) const;
  // The surface below x: the obstacle whose span [x_start, x_end] holds x, else kGround.
  int SurfaceAt(double x) const;
  double SurfaceHeight(int surface) const {
    return surface == kGround ? 0.0 : obstacles[surface].height;
  }
  double HeightAt(double x) const { return SurfaceHeight(SurfaceAt(x)); }
  // Index of the first obstacle whose interior, lowered by top_margin (the contact penetration
  // allowed to a foot standing on it), the segment a-b enters; -1 when none.
  int SegmentHitsObstacle(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                          double top_margin) const;
  // Horizontal distance from x to the near edge of the next obstacle ahead (x_start >= x), or
  // +infinity when there is none.
  double DistanceToNextObstacle(double x) const;
};

}  // namespace rabbit

#endif  // RABBIT_CONTACT_TERRAIN_H_
