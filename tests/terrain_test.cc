// The ground profile (a piecewise-linear slope field) against heights integrated by hand from its
// definition, its segments and its validation; obstacles standing on it.
#include "rabbit/contact/terrain.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

namespace rabbit {
namespace {

constexpr double kDeg = M_PI / 180.0;
const double kTolerance = 1e-12;  // m: the heights are sums of a few products

// The reference: H(x) from the definition (flat before the first breakpoint, dH/dx = -tan(slope)
// of the last breakpoint at or before x, continuous), integrated from the left by summing each
// piece's rise, then shifted so that H(0) = 0. Independent of GroundProfile's segment tables.
double ReferenceHeight(const std::vector<SlopeBreak>& breaks, double x) {
  auto unshifted = [&](double at) {
    double h = 0.0;
    for (size_t i = 0; i < breaks.size(); ++i) {
      const double from = breaks[i].x_start;
      const double to = i + 1 < breaks.size() ? breaks[i + 1].x_start : at;
      const double end = std::min(to, at);
      if (end > from) h -= std::tan(breaks[i].slope) * (end - from);
    }
    return h;
  };
  return unshifted(x) - unshifted(0.0);
}

TEST(GroundProfileTest, DefaultIsFlatZero) {
  const GroundProfile flat;
  std::string error;
  EXPECT_TRUE(flat.IsValid(&error));
  EXPECT_TRUE(flat.is_flat_zero());
  EXPECT_EQ(flat.num_segments(), 1);
  for (double x : {-1e3, -1.0, 0.0, 2.5, 1e3}) {
    EXPECT_EQ(flat.HeightAt(x), 0.0);
    EXPECT_EQ(flat.SlopeAt(x), 0.0);
    EXPECT_EQ(flat.SegmentAt(x), 0);
  }
  // A terrain without a profile: the ground is y = 0 under and between obstacles.
  Terrain t;
  t.obstacles = {{1.0, 0.2, 0.05}};
  EXPECT_EQ(t.GroundHeight(1.1), 0.0);
  EXPECT_EQ(t.ObstacleBase(0), 0.0);
  EXPECT_EQ(t.ObstacleTop(0), 0.05);
}

TEST(GroundProfileTest, HeightsMatchTheDefinition) {
  // Up 3 deg from x = 2 m (negative: the slope_deg convention, positive descending), down 2 deg
  // from 6 m, flat from 9 m.
  const std::vector<SlopeBreak> breaks = {{2.0, -3.0 * kDeg}, {6.0, 2.0 * kDeg}, {9.0, 0.0}};
  const GroundProfile g(breaks);
  std::string error;
  ASSERT_TRUE(g.IsValid(&error)) << error;
  ASSERT_EQ(g.num_segments(), 4);
  EXPECT_EQ(g.HeightAt(0.0), 0.0);
  EXPECT_EQ(g.HeightAt(-5.0), 0.0);  // flat lead-in
  EXPECT_NEAR(g.HeightAt(6.0), 4.0 * std::tan(3.0 * kDeg), kTolerance);
  EXPECT_NEAR(g.HeightAt(20.0), 4.0 * std::tan(3.0 * kDeg) - 3.0 * std::tan(2.0 * kDeg),
              kTolerance);
  for (double x = -3.0; x <= 12.0; x += 0.01) {
    EXPECT_NEAR(g.HeightAt(x), ReferenceHeight(breaks, x), kTolerance) << "x = " << x;
  }
  // Segments: a breakpoint starts its own segment; slopes and frames per segment.
  EXPECT_EQ(g.SegmentAt(1.999), 0);
  EXPECT_EQ(g.SegmentAt(2.0), 1);
  EXPECT_EQ(g.SegmentAt(8.0), 2);
  EXPECT_EQ(g.SegmentAt(9.0), 3);
  EXPECT_EQ(g.SlopeAt(7.0), 2.0 * kDeg);
  const GroundSegment& up = g.segment(1);
  EXPECT_EQ(up.x_start, 2.0);
  EXPECT_EQ(up.x_end, 6.0);
  EXPECT_NEAR(up.grade, std::tan(3.0 * kDeg), 1e-15);
  EXPECT_NEAR(std::hypot(up.cos_slope, up.sin_slope), 1.0, 1e-15);
  EXPECT_TRUE(std::isinf(g.segment(0).x_start) && std::isinf(g.segment(3).x_end));
}

TEST(GroundProfileTest, ContinuousAtBreakpointsAndZeroAtOriginWhateverTheProfile) {
  // Random profiles, some starting before x = 0: H is continuous at every breakpoint (the two
  // segments' lines meet there) and H(0) = 0.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> slope(-25.0, 25.0), gap(0.1, 3.0);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<SlopeBreak> breaks;
    double x = -4.0 + gap(rng);
    for (int i = 0; i < 6; ++i, x += gap(rng)) breaks.push_back({x, slope(rng) * kDeg});
    const GroundProfile g(breaks);
    std::string error;
    ASSERT_TRUE(g.IsValid(&error)) << error;
    EXPECT_NEAR(g.HeightAt(0.0), 0.0, kTolerance);
    for (int k = 1; k < g.num_segments(); ++k) {
      const double xb = g.segment(k).x_start;
      EXPECT_NEAR(g.segment(k - 1).HeightAt(xb), g.segment(k).HeightAt(xb), kTolerance);
      EXPECT_NEAR(g.HeightAt(xb), ReferenceHeight(breaks, xb), 1e-11);
    }
  }
}

TEST(GroundProfileTest, InvalidProfilesAreRefused) {
  std::string error;
  auto refused = [&](std::vector<SlopeBreak> breaks, const std::string& fragment) {
    const GroundProfile g(std::move(breaks));
    error.clear();
    EXPECT_FALSE(g.IsValid(&error));
    EXPECT_NE(error.find(fragment), std::string::npos) << error;
  };
  refused({{1.0, 0.0}, {1.0, 0.1}}, "breakpoint 2: breakpoints must be in increasing x_start");
  refused({{3.0, 0.0}, {1.0, 0.1}}, "increasing x_start");
  refused({{1.0, 30.0 * kDeg}}, "below 30 deg");
  refused({{1.0, -0.6}}, "below 30 deg");
  refused({{NAN, 0.1}}, "finite");
  refused({{1.0, INFINITY}}, "finite");
  refused({{2e4, 0.1}}, "1e4");
  EXPECT_TRUE(GroundProfile({{1.0, 29.9 * kDeg}}).IsValid(&error));
}

TEST(TerrainProfileTest, ObstaclesStandOnFlatPartsOfTheProfile) {
  Terrain t;
  // Up 5 deg over 2-4 m, flat from 4 m (at height 2 tan 5 deg).
  t.ground = GroundProfile({{2.0, -5.0 * kDeg}, {4.0, 0.0}});
  const double plateau = 2.0 * std::tan(5.0 * kDeg);
  t.obstacles = {{0.5, 0.2, 0.05}, {5.0, 0.3, 0.04}};
  std::string error;
  ASSERT_TRUE(t.IsValid(&error)) << error;
  EXPECT_EQ(t.ObstacleBase(0), 0.0);
  EXPECT_NEAR(t.ObstacleBase(1), plateau, kTolerance);
  EXPECT_NEAR(t.ObstacleTop(1), plateau + 0.04, kTolerance);
  EXPECT_NEAR(t.HeightAt(5.1), plateau + 0.04, kTolerance);        // on the top
  EXPECT_NEAR(t.HeightAt(3.0), std::tan(5.0 * kDeg), kTolerance);  // the slope
  // The obstacle's box starts at its base: a shin at the plateau's level beside it hits it, one
  // above its top does not.
  EXPECT_EQ(t.SegmentHitsObstacle(Eigen::Vector2d(4.8, plateau + 0.3),
                                  Eigen::Vector2d(5.05, plateau + 0.02), 0.0),
            1);
  EXPECT_EQ(t.SegmentHitsObstacle(Eigen::Vector2d(4.8, plateau + 0.3),
                                  Eigen::Vector2d(5.05, plateau + 0.05), 0.0),
            -1);
  // An obstacle on the slope, or reaching from the lead-in onto it, is refused.
  for (const Obstacle& o : {Obstacle{2.5, 0.2, 0.05}, Obstacle{1.9, 0.2, 0.05}}) {
    t.obstacles = {o};
    EXPECT_FALSE(t.IsValid(&error));
    EXPECT_NE(error.find("stands on sloped ground"), std::string::npos) << error;
  }
  // Ending exactly where the slope begins is fine.
  t.obstacles = {{1.5, 0.5, 0.05}};
  EXPECT_TRUE(t.IsValid(&error)) << error;
}

}  // namespace
}  // namespace rabbit
