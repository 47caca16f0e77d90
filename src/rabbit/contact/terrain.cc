#include "rabbit/contact/terrain.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

namespace rabbit {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string Metres(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g m", x);
  return text;
}

}  // namespace

GroundProfile::GroundProfile() : segments_(1) {
  segments_[0].x_start = -kInf;
  segments_[0].x_end = kInf;
}

GroundProfile::GroundProfile(std::vector<SlopeBreak> breaks) : breaks_(std::move(breaks)) {
  const size_t n = breaks_.size();
  segments_.resize(n + 1);
  // The flat lead-in, then one segment per breakpoint; heights first relative to the lead-in's.
  GroundSegment& lead = segments_[0];
  lead.x_start = -kInf;
  lead.x_end = n > 0 ? breaks_[0].x_start : kInf;
  lead.x_ref = n > 0 ? breaks_[0].x_start : 0.0;
  for (size_t k = 1; k <= n; ++k) {
    const SlopeBreak& b = breaks_[k - 1];
    const GroundSegment& before = segments_[k - 1];
    GroundSegment& s = segments_[k];
    s.x_start = b.x_start;
    s.x_end = k < n ? breaks_[k].x_start : kInf;
    s.x_ref = b.x_start;
    s.height = before.HeightAt(b.x_start) + b.rise;  // continuous but at a step
    s.slope = b.slope;
    s.grade = -std::tan(b.slope);
    s.cos_slope = std::cos(b.slope);
    s.sin_slope = std::sin(b.slope);
  }
  // Then shifted so that H(0) = 0 (a linear search: the breakpoints are not checked yet).
  size_t at_zero = 0;
  while (at_zero < n && breaks_[at_zero].x_start < 0.0) ++at_zero;
  const double offset = segments_[at_zero].HeightAt(0.0);  // at a step at 0: the level before
  if (offset != 0.0) {
    for (GroundSegment& s : segments_) s.height -= offset;
  }
}

bool GroundProfile::IsValid(std::string* error) const {
  for (size_t i = 0; i < breaks_.size(); ++i) {
    const SlopeBreak& b = breaks_[i];
    const std::string name = "slope breakpoint " + std::to_string(i + 1);
    if (!std::isfinite(b.x_start) || !std::isfinite(b.slope) || !std::isfinite(b.rise)) {
      *error = name + ": values must be finite";
      return false;
    }
    if (std::abs(b.x_start) > kMaxAbsX) {
      *error = name + ": x_start beyond +-1e4 m";
      return false;
    }
    if (!(std::abs(b.slope) < kMaxSlope)) {
      *error = name + ": the slope must be below 30 deg in magnitude";
      return false;
    }
    if (std::abs(b.rise) > kMaxRise) {
      *error = name + ": a step's rise must be within +-1 m";
      return false;
    }
    if (i > 0 && !(b.x_start > breaks_[i - 1].x_start)) {
      *error = name + ": breakpoints must be in increasing x_start (the previous one is at x = " +
               Metres(breaks_[i - 1].x_start) + ")";
      return false;
    }
  }
  return true;
}

int GroundProfile::SegmentAt(double x) const {
  // Segment i > 0 starts at breaks_[i - 1]: the count of breakpoints at or before x.
  const auto after = std::upper_bound(breaks_.begin(), breaks_.end(), x,
                                      [](double v, const SlopeBreak& b) { return v < b.x_start; });
  return static_cast<int>(after - breaks_.begin());
}

bool GroundProfile::StepBetween(int a, int b) const {
  // Segment i > 0 starts at breaks_[i - 1]: crossing from a to b passes breaks_[min..max - 1].
  for (int i = std::min(a, b); i < std::max(a, b); ++i) {
    if (breaks_[i].rise != 0.0) return true;
  }
  return false;
}

std::vector<Eigen::Vector2d> GroundProfile::Outline(double x_lo, double x_hi) const {
  std::vector<Eigen::Vector2d> points = {{x_lo, HeightAt(x_lo)}};
  for (size_t i = 0; i < breaks_.size(); ++i) {
    const double x = breaks_[i].x_start;
    if (!(x > x_lo && x < x_hi)) continue;
    if (breaks_[i].rise != 0.0) points.emplace_back(x, segments_[i].HeightAt(x));
    points.emplace_back(x, segments_[i + 1].HeightAt(x));
  }
  points.emplace_back(x_hi, HeightAt(x_hi));
  return points;
}

bool Terrain::IsValid(std::string* error) const {
  if (!ground.IsValid(error)) return false;
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
    const GroundSegment& under = ground.segment(ground.SegmentAt(o.x_start));
    if (under.slope != 0.0 || o.x_end() > under.x_end) {
      *error = name + " (x = " + Metres(o.x_start) + " to " + Metres(o.x_end()) +
               ") stands on sloped ground: obstacles must stand on a flat part of the ground "
               "profile (their base is the ground's height there)";
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
    const double base = ObstacleBase(static_cast<int>(i));
    double t0 = 0.0, t1 = 1.0;
    const double dx = b.x() - a.x(), dy = b.y() - a.y();
    const double p[4] = {-dx, dx, -dy, dy};
    const double r[4] = {a.x() - o.x_start, o.x_end() - a.x(), a.y() - base,
                         base + o.height - top_margin - a.y()};
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

int Terrain::SegmentHitsStepFace(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                 double top_margin) const {
  const std::vector<SlopeBreak>& breaks = ground.breaks();
  const double lo_x = std::min(a.x(), b.x()), hi_x = std::max(a.x(), b.x());
  for (size_t i = 0; i < breaks.size(); ++i) {
    const double x = breaks[i].x_start;
    if (breaks[i].rise == 0.0 || x < lo_x || x > hi_x || lo_x == hi_x) continue;
    const double before = ground.segment(static_cast<int>(i)).HeightAt(x);
    const double after = ground.segment(static_cast<int>(i) + 1).HeightAt(x);
    const double y = a.y() + (b.y() - a.y()) * (x - a.x()) / (b.x() - a.x());
    if (y > std::min(before, after) && y < std::max(before, after) - top_margin) {
      return static_cast<int>(i);
    }
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
