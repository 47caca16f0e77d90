#include "rabbit/contact/terrain.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rabbit {

bool Terrain::IsValid(std::string* error) const {
  for (size_t i = 0; i < obstacles.size(); ++i) {
    const Obstacle& o = obstacles[i];
    const std::string name = "obstacle " + std::to_string(i + 1);
    if (!std::isfinite(o.x_start) || !std::isfinite(o.length) || !std::isfinite(o.height)) {
      *error = name + ": values must be finite";
      return false;
    }
    if (o.length <= 0.0) {
      *error = name + ": length must be > 0";
      return false;
    }
    if (o.height <= 0.0) {
      *error = name + ": height must be > 0";
      return false;
    }
    if (i > 0 && o.x_start < obstacles[i - 1].x_end()) {
      *error = name + ": obstacles must be sorted by x and must not overlap";
      return false;
    }
  }
  return true;
}

int Terrain::SurfaceAt(double x) const {
  for (size_t i = 0; i < obstacles.size(); ++i) {
    if (x >= obstacles[i].x_start && x <= obstacles[i].x_end()) return static_cast<int>(i);
  }
  return kGround;
}

int Terrain::SegmentHitsObstacle(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                 double top_margin) const {
  // Liang-Barsky clipping of the segment against each rectangle's open interior.
  for (size_t i = 0; i < obstacles.size(); ++i) {
    const Obstacle& o = obstacles[i];
    double t0 = 0.0, t1 = 1.0;
    const double dx = b.x() - a.x(), dy = b.y() - a.y();
    const double p[4] = {-dx, dx, -dy, dy};
    const double r[4] = {a.x() - o.x_start, o.x_end() - a.x(), a.y() - 0.0,
                         o.height - top_margin - a.y()};
    bool outside = false;
    for (int k = 0; k < 4 && !outside; ++k) {
      if (p[k] == 0.0) {
        if (r[k] <= 0.0) outside = true;
      } else {
        const double t = r[k] / p[k];
        if (p[k] < 0.0) {
          t0 = std::max(t0, t);
        } else {
          t1 = std::min(t1, t);
        }
        if (t0 >= t1) outside = true;
      }
    }
    if (!outside) return static_cast<int>(i);
  }
  return -1;
}

double Terrain::DistanceToNextObstacle(double x) const {
  for (const Obstacle& o : obstacles) {
    if (o.x_start >= x) return o.x_start - x;
  }
  return std::numeric_limits<double>::infinity();
}

}  // namespace rabbit
