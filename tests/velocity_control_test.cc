// The walker's velocity control: the chapter's law (eqs. 19-20) against a hand computation, the
// pitch map's pool-adjacent-violators fit against a brute-force least-squares search, the rate
// limit and feed-forward against hand-computed steps, and [controller.velocity_control]'s keys.
#include "rabbit/control/velocity_control.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "rabbit/io/error.h"
#include "rabbit/scenario/suite.h"
#include "suite_fixture.h"

namespace rabbit {
namespace {

constexpr double kTolerance = 1e-12;

TEST(VelocityControlTest, OffIsTheChaptersLaw) {
  VelocityControlParams p;  // enabled = false
  const double k_p = 0.2, k_v = 0.1;
  VelocityControl c(p, k_p, k_v, -0.1, 0.45, 0.07, PitchMap({{0.4, 0.0}, {0.8, 0.3}}));
  EXPECT_DOUBLE_EQ(c.Command(0.6), 0.6);
  // First update: K_P e only (no previous error): 0.07 + 0.2 * (0.6 - 0.5).
  EXPECT_NEAR(c.Update(0.5, 0.6), 0.07 + 0.02, kTolerance);
  // A jump of V_d is passed through whole (no rate limit, no feed-forward).
  EXPECT_DOUBLE_EQ(c.Command(0.9), 0.9);
  // Second: + K_P e + K_V (e - e_prev) / t_step with e = 0.9 - 0.55 = 0.35, e_prev = 0.1.
  const double expected = 0.09 + 0.2 * 0.35 + 0.1 * (0.35 - 0.1) / 0.5;
  EXPECT_NEAR(c.Update(0.55, 0.5), expected, kTolerance);
  // Clamped to q0_d_max.
  for (int i = 0; i < 20; ++i) c.Update(0.3, 0.5);
  EXPECT_DOUBLE_EQ(c.q0_d(), 0.45);
}

// The least-squares non-decreasing fit, by brute force over a grid for three points.
TEST(PitchMapTest, NonDecreasingFitIsTheLeastSquaresMonotoneSequence) {
  const std::vector<double> y = {0.0, -0.05, 0.1, 0.08};
  const std::vector<double> fit = NonDecreasingFit(y);
  ASSERT_EQ(fit.size(), y.size());
  for (size_t i = 1; i < fit.size(); ++i) EXPECT_LE(fit[i - 1], fit[i]);
  // Pooling by hand: (0, -0.05) -> -0.025 twice, (0.1, 0.08) -> 0.09 twice.
  EXPECT_NEAR(fit[0], -0.025, kTolerance);
  EXPECT_NEAR(fit[1], -0.025, kTolerance);
  EXPECT_NEAR(fit[2], 0.09, kTolerance);
  EXPECT_NEAR(fit[3], 0.09, kTolerance);
  // Brute force: no non-decreasing sequence on a 0.005 grid has a smaller squared error.
  auto sse = [&y](const std::vector<double>& s) {
    double e = 0.0;
    for (size_t i = 0; i < y.size(); ++i) e += (s[i] - y[i]) * (s[i] - y[i]);
    return e;
  };
  double best = std::numeric_limits<double>::infinity();
  for (int a = -20; a <= 30; ++a)
    for (int b = a; b <= 30; ++b)
      for (int c = b; c <= 30; ++c)
        for (int d = c; d <= 30; ++d)
          best = std::min(best, sse({a * 0.005, b * 0.005, c * 0.005, d * 0.005}));
  EXPECT_LE(sse(fit), best + 1e-12);
  EXPECT_EQ(NonDecreasingFit({}).size(), 0u);
}

TEST(PitchMapTest, InterpolatesTheMonotoneGaitPitches) {
  // The shipped database's shape: 0.5 m/s leans less than 0.4 m/s, and is pooled with it.
  const PitchMap map({{0.5, -0.05}, {0.4, 0.0}, {0.6, 0.15}});
  EXPECT_NEAR(map.At(0.4), -0.025, kTolerance);
  EXPECT_NEAR(map.At(0.5), -0.025, kTolerance);
  EXPECT_NEAR(map.At(0.55), -0.025 + 0.5 * (0.15 + 0.025), kTolerance);
  EXPECT_NEAR(map.At(0.2), -0.025, kTolerance);  // constant beyond the ends
  EXPECT_NEAR(map.At(2.0), 0.15, kTolerance);
  EXPECT_DOUBLE_EQ(PitchMap().At(0.7), 0.0);
  EXPECT_THROW(PitchMap({{std::nan(""), 0.0}}), std::invalid_argument);
}

TEST(VelocityControlTest, RateLimitAndFeedForward) {
  VelocityControlParams p;
  p.enabled = true;
  p.v_d_rate = 0.1;
  p.feedforward_gain = 0.5;
  p.start_at_map = false;
  const PitchMap map({{0.4, 0.0}, {0.8, 0.2}});  // 0.5 rad per m/s
  const double k_p = 0.2, k_v = 0.1;
  VelocityControl c(p, k_p, k_v, -0.1, 0.45, 0.05, map);
  EXPECT_DOUBLE_EQ(c.Command(0.4), 0.4);  // the first command is V_d itself
  EXPECT_NEAR(c.Update(0.4, 0.6), 0.05, kTolerance);
  // V_d jumps to 0.8: the command moves by 0.1 per touchdown.
  EXPECT_NEAR(c.Command(0.8), 0.5, kTolerance);
  // q0_d: + K_P (0.5 - 0.42) + gain (P(0.5) - P(0.4)) - K_V (0.42 - 0.4) / t_step.
  double q = 0.05 + 0.2 * 0.08 + 0.5 * 0.05 - 0.1 * 0.02 / 0.5;
  EXPECT_NEAR(c.Update(0.42, 0.5), q, kTolerance);
  EXPECT_NEAR(c.Command(0.8), 0.6, kTolerance);
  EXPECT_NEAR(c.Command(0.8), 0.7, kTolerance);  // two commands before an update: both fed
  q += 0.2 * (0.7 - 0.5) + 0.5 * (0.15 - 0.05) - 0.1 * (0.5 - 0.42) / 0.5;
  EXPECT_NEAR(c.Update(0.5, 0.5), q, kTolerance);
  EXPECT_NEAR(c.Command(0.8), 0.8, kTolerance);
  EXPECT_NEAR(c.Command(0.8), 0.8, kTolerance);    // arrived
  EXPECT_NEAR(c.Command(0.75), 0.75, kTolerance);  // within the rate: at once
}

// feedforward_rise_extra: a rise of V_c leans by (feedforward_gain + extra) times the map's
// change, a fall by feedforward_gain alone; 0 is the shared gain both ways.
TEST(VelocityControlTest, RiseExtraFeedForward) {
  VelocityControlParams p;
  p.enabled = true;
  p.v_d_rate = 0.1;
  p.feedforward_gain = 0.5;
  p.feedforward_rise_extra = 0.25;
  p.start_at_map = false;
  const PitchMap map({{0.4, 0.0}, {0.8, 0.2}});  // 0.5 rad per m/s
  const double k_p = 0.2;
  VelocityControl c(p, k_p, 0.0, -0.1, 0.45, 0.05, map);
  c.Command(0.4);
  EXPECT_NEAR(c.Update(0.4, 0.5), 0.05, kTolerance);
  // Up by 0.1: + K_P (0.5 - 0.4) + 0.75 (P(0.5) - P(0.4)).
  EXPECT_NEAR(c.Command(0.8), 0.5, kTolerance);
  double q = 0.05 + k_p * 0.1 + 0.75 * 0.05;
  EXPECT_NEAR(c.Update(0.4, 0.5), q, kTolerance);
  // Down by 0.1: + K_P (0.4 - 0.4) + 0.5 (P(0.4) - P(0.5)).
  EXPECT_NEAR(c.Command(0.3), 0.4, kTolerance);
  q += 0.5 * -0.05;
  EXPECT_NEAR(c.Update(0.4, 0.5), q, kTolerance);
  // Without the extra the same rise leans by the shared gain.
  p.feedforward_rise_extra = 0.0;
  VelocityControl d(p, k_p, 0.0, -0.1, 0.45, 0.05, map);
  d.Command(0.4);
  d.Update(0.4, 0.5);
  d.Command(0.8);
  EXPECT_NEAR(d.Update(0.4, 0.5), 0.05 + k_p * 0.1 + 0.5 * 0.05, kTolerance);
  // A rise of the terrain's command over a profile that holds (an obstacle's approach speed) is
  // no rise of the profile: the shared gain.
  p.feedforward_rise_extra = 0.25;
  VelocityControl e(p, k_p, 0.0, -0.1, 0.45, 0.05, map);
  e.Command(0.4, 0.4, 0.4);
  e.Update(0.4, 0.5);
  EXPECT_NEAR(e.Command(0.8, 0.4, 0.4), 0.5, kTolerance);
  EXPECT_NEAR(e.Update(0.4, 0.5), 0.05 + k_p * 0.1 + 0.5 * 0.05, kTolerance);
}

// v_d_rate_up: in a rise of the profile's own V_d the command climbs at v_d_rate_up; a rise of
// the terrain's command over a profile that holds, and every decrease, keep v_d_rate; 0 is
// v_d_rate both ways.
TEST(VelocityControlTest, RiseRate) {
  VelocityControlParams p;
  p.enabled = true;
  p.v_d_rate = 0.1;
  p.v_d_rate_up = 0.15;
  const PitchMap map({{0.4, 0.0}, {0.8, 0.2}});
  VelocityControl c(p, 0.2, 0.0, -0.1, 0.45, 0.05, map);
  EXPECT_NEAR(c.Command(0.4, 0.4, 0.4), 0.4, kTolerance);
  EXPECT_NEAR(c.Command(0.8, 0.4, 0.8), 0.55, kTolerance);  // the profile stepped up
  EXPECT_NEAR(c.Command(0.8, 0.5, 0.8), 0.7, kTolerance);   // the rise goes on
  EXPECT_NEAR(c.Command(0.8, 0.6, 0.8), 0.8, kTolerance);   // arrived
  EXPECT_NEAR(c.Command(0.4, 0.8, 0.4), 0.7, kTolerance);   // down: v_d_rate
  // The terrain's command (an approach speed over a profile at 0.4) is no rise of the profile.
  VelocityControl d(p, 0.2, 0.0, -0.1, 0.45, 0.05, map);
  d.Command(0.4, 0.4, 0.4);
  EXPECT_NEAR(d.Command(0.7, 0.4, 0.4), 0.5, kTolerance);
  EXPECT_NEAR(d.Command(0.7, 0.4, 0.4), 0.6, kTolerance);
  // Off: v_d_rate.
  p.v_d_rate_up = 0.0;
  VelocityControl e(p, 0.2, 0.0, -0.1, 0.45, 0.05, map);
  e.Command(0.4, 0.4, 0.4);
  EXPECT_NEAR(e.Command(0.8, 0.4, 0.8), 0.5, kTolerance);
}

TEST(VelocityControlTest, StartsAtTheMap) {
  VelocityControlParams p;
  p.enabled = true;
  const PitchMap map({{0.4, 0.0}, {0.8, 0.2}});
  VelocityControl c(p, 0.2, 0.1, -0.1, 0.45, 0.05, map);
  c.Command(0.7);
  EXPECT_NEAR(c.Update(0.6, 0.5), 0.15, kTolerance);  // P(0.7), not 0.05 + K_P e
  // Then the law: + K_P (0.7 - 0.65) - K_V (0.65 - 0.6) / 0.5.
  c.Command(0.7);
  EXPECT_NEAR(c.Update(0.65, 0.5), 0.15 + 0.2 * 0.05 - 0.1 * 0.05 / 0.5, kTolerance);
}

TEST(VelocityControlTest, ParamsValidation) {
  VelocityControlParams p;
  std::string error;
  EXPECT_TRUE(p.IsValid(&error));
  p.v_d_rate = -0.1;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("v_d_rate"), std::string::npos);
  p = VelocityControlParams();
  p.feedforward_gain = std::nan("");
  EXPECT_FALSE(p.IsValid(&error));
  p = VelocityControlParams();
  p.pitch_map = {{0.5, 1.0}};  // 57 deg
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("pitch_map_deg"), std::string::npos);
}

// Every ranged key: a value just past either end is refused with a message naming the key and
// its range; the ends themselves are accepted.
TEST(VelocityControlTest, EachRangedKeyIsCheckedAtBothEnds) {
  struct Case {
    const char* message;
    double VelocityControlParams::*field;
    double lo, hi;
  };
  const Case cases[] = {
      {"velocity_control.v_d_rate must be in [0, 3] m/s per step", &VelocityControlParams::v_d_rate,
       0.0, 3.0},
      {"velocity_control.feedforward_gain must be in [0, 2]",
       &VelocityControlParams::feedforward_gain, 0.0, 2.0},
      {"velocity_control.feedforward_rise_extra must be in [0, 2]",
       &VelocityControlParams::feedforward_rise_extra, 0.0, 2.0},
      {"velocity_control.gait_shift_gain must be in [0, 10] m/s per rad",
       &VelocityControlParams::gait_shift_gain, 0.0, 10.0},
      {"velocity_control.gait_shift_max must be in [0, 0.5] m/s",
       &VelocityControlParams::gait_shift_max, 0.0, 0.5},
      {"velocity_control.gait_shift_below must be in [0, 3] m/s",
       &VelocityControlParams::gait_shift_below, 0.0, 3.0},
      {"velocity_control.v_d_rate_up must be in [0, 3] m/s per step",
       &VelocityControlParams::v_d_rate_up, 0.0, 3.0},
      {"velocity_control.v_d_rate_down must be in [0, 3] m/s per step",
       &VelocityControlParams::v_d_rate_down, 0.0, 3.0},
      {"velocity_control.v_d_rate_down_below must be in [0, 3] m/s",
       &VelocityControlParams::v_d_rate_down_below, 0.0, 3.0},
      {"velocity_control.drop_min must be in [0, 3] m/s", &VelocityControlParams::drop_min, 0.0,
       3.0},
      {"velocity_control.drop_gap must be in [0, 3] m/s", &VelocityControlParams::drop_gap, 0.0,
       3.0},
      {"velocity_control.settled_start_clear must be in [0, 100] m",
       &VelocityControlParams::settled_start_clear, 0.0, 100.0},
      {"velocity_control.settled_feedforward_gain must be in [0, 2]",
       &VelocityControlParams::settled_feedforward_gain, 0.0, 2.0},
      {"velocity_control.settled_rise_extra must be in [0, 2]",
       &VelocityControlParams::settled_rise_extra, 0.0, 2.0},
  };
  for (const Case& c : cases) {
    for (double value : {c.lo, c.hi}) {
      VelocityControlParams p;
      p.*c.field = value;
      std::string error;
      EXPECT_TRUE(p.IsValid(&error)) << c.message << " at " << value << ": " << error;
    }
    for (double value : {c.lo - 1e-9, c.hi + 1e-9, std::nan("")}) {
      VelocityControlParams p;
      p.*c.field = value;
      std::string error;
      EXPECT_FALSE(p.IsValid(&error)) << c.message << " at " << value;
      EXPECT_EQ(error.rfind(c.message, 0), 0u) << error;
    }
  }
}

// [controller.velocity_control] keys: read, in degrees at the edge, errors naming file, line, key.
// The walker suite with `keys` in [defaults.controller.velocity_control] (line 12).
class VelocityControlKeysTest : public testing::WalkerKeysTest {
 protected:
  VelocityControlKeysTest() : WalkerKeysTest("rabbit_velocity_control_test", "velocity_control") {}
};

TEST_F(VelocityControlKeysTest, ReadAndValidated) {
  const Suite off = LoadSuite(Write(""));
  EXPECT_TRUE(off.scenarios[0].walker.velocity_control.enabled);  // the adaptive preset's
  EXPECT_DOUBLE_EQ(off.scenarios[0].walker.velocity_control.v_d_rate_up, 0.15);
  EXPECT_DOUBLE_EQ(off.scenarios[0].walker.velocity_control.feedforward_gain, 0.565);
  const Suite suite = LoadSuite(
      Write("enabled = true\nv_d_rate = 0.2\nfeedforward_gain = 0.25\nstart_at_map = false\n"
            "pitch_map_deg = [[0.4, 0.0], [0.8, 18.0]]\nv_d_rate_up = 0.12\n"));
  const VelocityControlParams& v = suite.scenarios[0].walker.velocity_control;
  EXPECT_TRUE(v.enabled);
  EXPECT_DOUBLE_EQ(v.v_d_rate, 0.2);
  EXPECT_DOUBLE_EQ(v.v_d_rate_up, 0.12);
  EXPECT_DOUBLE_EQ(v.feedforward_gain, 0.25);
  EXPECT_FALSE(v.start_at_map);
  ASSERT_EQ(v.pitch_map.size(), 2u);
  EXPECT_NEAR(v.pitch_map[1].second, 18.0 * M_PI / 180.0, kTolerance);
  ExpectError("v_d_rate = -1.0\n", "scenario[1].controller.velocity_control.v_d_rate");
  ExpectError("feedforward_gain = 3.0\n",
              "scenario[1].controller.velocity_control.feedforward_gain");
  ExpectError("v_d_rate_up = 3.5\n", "scenario[1].controller.velocity_control.v_d_rate_up");
  ExpectError("feedforward_rise_extra = -0.5\n",
              "scenario[1].controller.velocity_control.feedforward_rise_extra");
  ExpectError("pitch_map_deg = [[0.4, 60.0]]\n",
              "scenario[1].controller.velocity_control.pitch_map_deg");
  ExpectError("enabld = true\n", "scenario[1].controller.velocity_control.enabld");
}

// The training suite loads, with the velocity control enabled and its walker's own pitch map.
TEST(VelocityControlTrainingSuiteTest, Loads) {
  const Suite suite = LoadSuite(std::string(RABBIT_SOURCE_DIR) + "/scenarios/train/speed.toml");
  ASSERT_FALSE(suite.scenarios.empty());
  for (const Scenario& s : suite.scenarios) {
    const VelocityControlParams& v = s.walker.velocity_control;
    EXPECT_TRUE(v.enabled) << s.name;
    ASSERT_GE(v.pitch_map.size(), 2u) << s.name;
    // Made non-decreasing by the map, the points as written already are.
    for (size_t i = 1; i < v.pitch_map.size(); ++i) {
      EXPECT_LT(v.pitch_map[i - 1].first, v.pitch_map[i].first);
      EXPECT_LE(v.pitch_map[i - 1].second, v.pitch_map[i].second);
    }
  }
}

}  // namespace
}  // namespace rabbit
