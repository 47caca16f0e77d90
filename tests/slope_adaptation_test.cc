// The walker's slope adaptation (slope_adaptation.h): the grade of two contact points against the
// terrain's own ground profile, the filter's convergence against its closed form, the reactions'
// laws and bounds, nothing when disabled, invalid parameters refused, and the [controller.slope]
// keys read from a suite (a bad value names its key and line).
#include "rabbit/control/slope_adaptation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "rabbit/contact/terrain.h"
#include "rabbit/scenario/scenario.h"
#include "rabbit/scenario/suite.h"
#include "suite_fixture.h"

namespace rabbit {
namespace {

constexpr double kTolerance = 1e-12;
constexpr double kDeg = M_PI / 180.0;

TEST(SlopeAdaptationTest, GradeOfTwoFeetOnTheTerrainsProfile) {
  // Feet placed on a 3 deg downhill and a 4 deg uphill of the terrain's ground profile: the
  // measured grade is the profile's slope (same sign convention), whichever foot is ahead.
  const GroundProfile ground({{1.0, 3.0 * kDeg}, {5.0, -4.0 * kDeg}});
  for (const double x : {2.0, 6.0}) {
    const Vec2 back(x, ground.HeightAt(x)), front(x + 0.4, ground.HeightAt(x + 0.4));
    EXPECT_NEAR(MeasuredGrade(front, back, 0.1), ground.SlopeAt(x), kTolerance);
    EXPECT_NEAR(MeasuredGrade(back, front, 0.1), ground.SlopeAt(x), kTolerance);
  }
  // Flat ground: 0; feet closer than the baseline: no grade.
  EXPECT_NEAR(MeasuredGrade(Vec2(0.4, 0.0), Vec2(0.0, 0.0), 0.1), 0.0, kTolerance);
  EXPECT_TRUE(std::isnan(MeasuredGrade(Vec2(0.05, 0.0), Vec2(0.0, 0.01), 0.1)));
}

TEST(SlopeAdaptationTest, GradeAheadIsTheProfilesChordWithoutSteps) {
  // Within one piece the chord's grade is the piece's slope; across a change of grade it is the
  // angle of the chord between the two heights (closed form); a vertical step's rise is removed.
  const GroundProfile ground({{1.0, -3.0 * kDeg, 0.0}, {2.0, 2.0 * kDeg, 0.04}});
  EXPECT_NEAR(GradeAhead(ground, 1.2, 1.6), -3.0 * kDeg, kTolerance);
  EXPECT_NEAR(GradeAhead(ground, 2.2, 2.6), 2.0 * kDeg, kTolerance);
  EXPECT_NEAR(GradeAhead(ground, 0.0, 0.5), 0.0, kTolerance);
  const double rise = 0.4 * std::tan(3.0 * kDeg) - 0.2 * std::tan(2.0 * kDeg);  // up, then down
  EXPECT_NEAR(GradeAhead(ground, 1.6, 2.2), std::atan(-rise / 0.6), kTolerance);
  EXPECT_TRUE(std::isnan(GradeAhead(ground, 1.0, 1.005)));
}

TEST(SlopeAdaptationTest, PreviewAddsTheKnownChangeOfGrade) {
  SlopeParams p;
  p.enabled = true;
  p.filter = 1.0;
  p.preview = 0.5;
  SlopeAdaptation a(p);
  const double feet = 1.0 * kDeg, change = -4.0 * kDeg;
  a.OnTouchdown(Vec2(0.4, -0.4 * std::tan(feet)), Vec2(0.0, 0.0), change);
  EXPECT_NEAR(a.slope(), feet + 0.5 * change, kTolerance);
  // No change known: the feet alone; feet too close for a line: no reading at all.
  a.OnTouchdown(Vec2(0.4, -0.4 * std::tan(feet)), Vec2(0.0, 0.0));
  EXPECT_NEAR(a.slope(), feet, kTolerance);
  a.OnTouchdown(Vec2(0.05, 0.0), Vec2(0.0, 0.0), change);
  EXPECT_NEAR(a.slope(), feet, kTolerance);
  // preview = 0 ignores it; a zero change leaves the reading bit for bit.
  p.preview = 0.0;
  SlopeAdaptation b(p);
  b.OnTouchdown(Vec2(0.4, -0.4 * std::tan(feet)), Vec2(0.0, 0.0), change);
  p.preview = 1.0;
  SlopeAdaptation c(p);
  c.OnTouchdown(Vec2(0.4, -0.4 * std::tan(feet)), Vec2(0.0, 0.0), 0.0);
  EXPECT_EQ(b.slope(), c.slope());
  EXPECT_EQ(b.slope(), MeasuredGrade(Vec2(0.4, -0.4 * std::tan(feet)), Vec2(0.0, 0.0), 0.1));
}

TEST(SlopeAdaptationTest, FilterConvergesGeometrically) {
  SlopeParams p;
  p.enabled = true;
  p.filter = 0.4;
  SlopeAdaptation a(p);
  const double s = 2.5 * kDeg;  // downhill
  for (int n = 1; n <= 6; ++n) {
    const double x = 0.45 * n;
    a.OnTouchdown(Vec2(x, -std::tan(s) * x), Vec2(x - 0.45, -std::tan(s) * (x - 0.45)));
    // s_n = s (1 - (1 - f)^n) from s_0 = 0.
    EXPECT_NEAR(a.slope(), s * (1.0 - std::pow(1.0 - p.filter, n)), 1e-12) << n;
  }
  // A step whose feet are too close leaves the estimate as it was.
  const double before = a.slope();
  a.OnTouchdown(Vec2(3.0, 0.5), Vec2(2.99, 0.0));
  EXPECT_EQ(a.slope(), before);
}

TEST(SlopeAdaptationTest, ReactionsFollowTheirLaws) {
  SlopeParams p;
  p.enabled = true;
  p.filter = 1.0;
  p.trunk_gain = 3.0;
  p.trunk_max = 0.15;
  p.frame_gain = 1.5;
  p.fis_gain = -2.0;
  p.overshoot_margin = 0.1;
  p.overshoot_gain = 0.4;
  SlopeAdaptation a(p);
  const double up = -2.0 * kDeg;  // ground rising toward +x
  a.OnTouchdown(Vec2(0.4, -std::tan(up) * 0.4), Vec2(0.0, 0.0));
  EXPECT_NEAR(a.slope(), up, kTolerance);
  EXPECT_NEAR(a.TrunkOffset(), -3.0 * up, kTolerance);
  EXPECT_LE(a.TrunkOffset(), p.trunk_max);
  EXPECT_NEAR(a.FrameAngle(), -1.5 * up, kTolerance);  // the normal's tilt: foot forward
  EXPECT_NEAR(a.FisVelocityOffset(), -2.0 * up, kTolerance);
  // The speed cap: nothing within the margin, the gain times the excess beyond it.
  EXPECT_EQ(a.OvershootCorrection(0.69, 0.6), 0.0);
  EXPECT_NEAR(a.OvershootCorrection(0.9, 0.6), -0.4 * 0.2, kTolerance);
  // A steep uphill: the trunk lean stops at its bound; the measured grade at slope_max.
  a.OnTouchdown(Vec2(0.4, 0.4), Vec2(0.0, 0.0));  // 45 deg up
  EXPECT_NEAR(a.slope(), -p.slope_max, kTolerance);
  EXPECT_NEAR(a.TrunkOffset(), p.trunk_max, kTolerance);
}

TEST(SlopeAdaptationTest, DisabledDoesNothing) {
  SlopeParams p;
  p.enabled = false;
  p.trunk_gain = p.frame_gain = p.fis_gain = p.overshoot_gain = 1.0;
  SlopeAdaptation a(p);
  a.OnTouchdown(Vec2(0.4, -0.05), Vec2(0.0, 0.0));
  EXPECT_EQ(a.slope(), 0.0);
  EXPECT_EQ(a.TrunkOffset(), 0.0);
  EXPECT_EQ(a.FrameAngle(), 0.0);
  EXPECT_EQ(a.FisVelocityOffset(), 0.0);
  EXPECT_EQ(a.OvershootCorrection(2.0, 0.5), 0.0);
}

TEST(SlopeAdaptationTest, InvalidParametersAreRefused) {
  std::string error;
  SlopeParams p;
  EXPECT_TRUE(p.IsValid(&error)) << error;
  p.filter = 0.0;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("filter"), std::string::npos);
  p = SlopeParams();
  p.trunk_max = 0.8;
  EXPECT_FALSE(p.IsValid(&error));
  p = SlopeParams();
  p.frame_gain = std::nan("");
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("frame_gain"), std::string::npos);
  p = SlopeParams();
  p.preview = 2.5;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("preview"), std::string::npos);
}

class SlopeKeysTest : public testing::WalkerKeysTest {
 protected:
  SlopeKeysTest() : WalkerKeysTest("rabbit_slope_keys_test", "slope") {}
};

TEST_F(SlopeKeysTest, KeysAreRead) {
  const Scenario s =
      LoadSuite(Write("enabled = true\nfilter = 0.7\ntrunk_gain = 2.0\nframe_gain = 1.5\n"
                      "trunk_max_deg = 10\nslope_max_deg = 8\npreview = 0.5\n"))
          .scenarios[0];
  EXPECT_TRUE(s.walker.slope.enabled);
  EXPECT_EQ(s.walker.slope.filter, 0.7);
  EXPECT_EQ(s.walker.slope.trunk_gain, 2.0);
  EXPECT_EQ(s.walker.slope.frame_gain, 1.5);
  EXPECT_NEAR(s.walker.slope.trunk_max, 10.0 * kDeg, kTolerance);
  EXPECT_NEAR(s.walker.slope.slope_max, 8.0 * kDeg, kTolerance);
  EXPECT_EQ(s.walker.slope.preview, 0.5);
}

TEST_F(SlopeKeysTest, BadValueNamesItsKey) {
  ExpectError("filter = 1.5\n", "scenario[1].controller.slope.filter");
  ExpectError("no_such_key = 1\n", "scenario[1].controller.slope.no_such_key");
}

}  // namespace
}  // namespace rabbit
