// The step-to-step speed law: the identification recovers a known map from samples it generates
// (pooled and per band), the deadbeat and decaying choices against the map's own dynamics
// computed by hand, the offset estimate removing a constant disturbance, the limits, and the
// keys of [controller.velocity_control.step_map].
#include "rabbit/control/step_map_control.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "rabbit/control/velocity_control.h"
#include "rabbit/scenario/suite.h"
#include "suite_fixture.h"

namespace rabbit {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kTolerance = 1e-12;
constexpr double kFitTolerance = 1e-9;  // exact data: least squares to rounding

// A map with a and b per band and q* rising with speed.
std::vector<StepMapBand> KnownBands(bool same_ab) {
  std::vector<StepMapBand> bands;
  for (int i = 0; i < 4; ++i) {
    const double v = 0.4 + 0.2 * i;
    bands.push_back({v, (-4.0 + 9.0 * i) * kDeg, same_ab ? 0.55 : 0.45 + 0.05 * i,
                     (same_ab ? 0.006 : 0.004 + 0.001 * i) / kDeg});
  }
  return bands;
}

// Samples of the map itself around each band's centre (no noise), pitches and strides spread.
std::vector<StepMapSample> Samples(const std::vector<StepMapBand>& bands) {
  std::vector<StepMapSample> samples;
  unsigned state = 12345;
  auto uniform = [&state] {
    state = state * 1103515245u + 12345u;
    return static_cast<double>((state >> 8) & 0xffff) / 65535.0;
  };
  for (const StepMapBand& m : bands) {
    for (int j = 0; j < 50; ++j) {
      StepMapSample x;
      x.v_c = m.v + 0.04 * (uniform() - 0.5);  // nearest this band's centre
      x.s = m.v + 0.3 * (uniform() - 0.5);
      x.q0_d = m.q_star + 10.0 * kDeg * (uniform() - 0.5);
      x.s_next = m.v + m.a * (x.s - m.v) + m.b * (x.q0_d - m.q_star);
      samples.push_back(x);
    }
  }
  return samples;
}

TEST(StepMapIdentifyTest, PerBandRecoversTheMap) {
  const std::vector<StepMapBand> truth = KnownBands(false);
  StepMapFit fit;
  std::string error;
  ASSERT_TRUE(IdentifyStepMap(Samples(truth), {0.4, 0.6, 0.8, 1.0}, 20, false, &fit, &error))
      << error;
  ASSERT_EQ(fit.bands.size(), truth.size());
  for (size_t i = 0; i < truth.size(); ++i) {
    EXPECT_NEAR(fit.bands[i].a, truth[i].a, kFitTolerance);
    EXPECT_NEAR(fit.bands[i].b, truth[i].b, kFitTolerance);
    EXPECT_NEAR(fit.bands[i].q_star, truth[i].q_star, kFitTolerance);
    EXPECT_EQ(fit.samples[i], 50);
    EXPECT_LT(fit.rms[i], kFitTolerance);
  }
}

TEST(StepMapIdentifyTest, PooledRecoversACommonMap) {
  const std::vector<StepMapBand> truth = KnownBands(true);
  StepMapFit fit;
  std::string error;
  ASSERT_TRUE(IdentifyStepMap(Samples(truth), {0.4, 0.6, 0.8, 1.0}, 20, true, &fit, &error))
      << error;
  for (size_t i = 0; i < truth.size(); ++i) {
    EXPECT_NEAR(fit.bands[i].a, 0.55, kFitTolerance);
    EXPECT_NEAR(fit.bands[i].b, 0.006 / kDeg, kFitTolerance);
    EXPECT_NEAR(fit.bands[i].q_star, truth[i].q_star, kFitTolerance);
  }
}

TEST(StepMapIdentifyTest, RefusesThinOrUnexcitedBands) {
  StepMapFit fit;
  std::string error;
  // A centre no sample is nearest: too few samples, named.
  EXPECT_FALSE(IdentifyStepMap(Samples(KnownBands(false)), {0.4, 0.6, 0.8, 1.0, 2.0}, 20, false,
                               &fit, &error));
  EXPECT_NE(error.find("band 5"), std::string::npos) << error;
  // A pitch that never varies: b cannot be identified.
  std::vector<StepMapSample> flat = Samples(KnownBands(false));
  for (StepMapSample& x : flat) x.q0_d = 0.0;
  EXPECT_FALSE(IdentifyStepMap(flat, {0.4, 0.6, 0.8, 1.0}, 20, false, &fit, &error));
  EXPECT_FALSE(IdentifyStepMap(flat, {0.6, 0.4}, 20, false, &fit, &error));
  EXPECT_NE(error.find("ascend"), std::string::npos);
}

TEST(StepMapAtTest, InterpolatesAndHoldsTheEnds) {
  const std::vector<StepMapBand> bands = KnownBands(false);
  const StepMapBand mid = StepMapAt(bands, 0.5);
  EXPECT_NEAR(mid.a, 0.5 * (bands[0].a + bands[1].a), kTolerance);
  EXPECT_NEAR(mid.b, 0.5 * (bands[0].b + bands[1].b), kTolerance);
  EXPECT_NEAR(mid.q_star, 0.5 * (bands[0].q_star + bands[1].q_star), kTolerance);
  EXPECT_NEAR(StepMapAt(bands, 0.1).q_star, bands.front().q_star, kTolerance);
  EXPECT_NEAR(StepMapAt(bands, 2.0).q_star, bands.back().q_star, kTolerance);
}

// The plant is the map itself: S[k+1] = V + a (S[k] - V) + b (pitch in force - q*) + d.
struct MapPlant {
  StepMapBand m;
  double d = 0.0;
  double Next(double s, double pitch_in_force) const {
    return m.v + m.a * (s - m.v) + m.b * (pitch_in_force - m.q_star) + d;
  }
};

StepMapParams OneBand(const StepMapBand& m, double decay) {
  StepMapParams p;
  p.bands = {m};
  p.decay = decay;
  p.offset_gain = 0.0;
  p.max_change = M_PI / 4;
  return p;
}

TEST(StepMapControlTest, DeadbeatRemovesTheErrorTwoStridesAhead) {
  const StepMapBand m{0.6, 8.0 * kDeg, 0.55, 0.006 / kDeg};
  StepMapControl law(OneBand(m, 0.0));
  const MapPlant plant{m};
  // Off the command by 0.1 m/s, the pitch in force 2 deg off q*.
  double s = 0.5, in_force = m.q_star + 2.0 * kDeg;
  const double q = law.Update(s, 0.6, in_force, -1.0, 1.0);
  // By hand: e1 = a (S - V) + b (in_force - q*); q = q* - a e1 / b.
  const double e1 = m.a * (s - 0.6) + m.b * 2.0 * kDeg;
  EXPECT_NEAR(q, m.q_star - m.a * e1 / m.b, kTolerance);
  EXPECT_NEAR(law.predicted(), 0.6 + e1, kTolerance);
  s = plant.Next(s, in_force);  // the stride the pitch in force gives
  EXPECT_NEAR(s, law.predicted(), kTolerance);
  in_force = q;
  const double q2 = law.Update(s, 0.6, in_force, -1.0, 1.0);
  s = plant.Next(s, in_force);
  EXPECT_NEAR(s, 0.6, kTolerance);  // removed
  in_force = q2;
  s = plant.Next(s, in_force);
  EXPECT_NEAR(s, 0.6, kTolerance);  // and held (q2 = q*)
  EXPECT_NEAR(q2, m.q_star, kTolerance);
}

TEST(StepMapControlTest, DecayShrinksTheErrorByItsRatio) {
  const StepMapBand m{0.6, 8.0 * kDeg, 0.55, 0.006 / kDeg};
  const double decay = 0.6;
  StepMapControl law(OneBand(m, decay));
  const MapPlant plant{m};
  double s = 0.8, in_force = m.q_star;
  double e_prev = std::nan("");
  for (int k = 0; k < 6; ++k) {
    const double q = law.Update(s, 0.6, in_force, -1.0, 1.0);
    s = plant.Next(s, in_force);
    in_force = q;
    if (k >= 1) {
      EXPECT_NEAR((s - 0.6) / e_prev, decay, 1e-9) << k;
    }
    e_prev = s - 0.6;
  }
}

TEST(StepMapControlTest, OffsetEstimateRemovesAConstantDisturbance) {
  const StepMapBand m{0.6, 8.0 * kDeg, 0.55, 0.006 / kDeg};
  StepMapParams p = OneBand(m, 0.5);
  p.offset_gain = 0.3;
  StepMapControl law(p);
  MapPlant plant{m};
  plant.d = -0.04;  // a 4 cm/s slow-down per stride the map does not know
  double s = 0.6, in_force = m.q_star;
  for (int k = 0; k < 80; ++k) {
    const double q = law.Update(s, 0.6, in_force, -1.0, 1.0);
    s = plant.Next(s, in_force);
    in_force = q;
  }
  EXPECT_NEAR(s, 0.6, 1e-6);
  EXPECT_NEAR(law.offset(), -0.04, 1e-6);
  // Without the estimate the error stays: d / (1 - a) at q* would be -0.089 m/s.
  StepMapControl blind(OneBand(m, 0.5));
  s = 0.6;
  in_force = m.q_star;
  for (int k = 0; k < 80; ++k) {
    const double q = blind.Update(s, 0.6, in_force, -1.0, 1.0);
    s = plant.Next(s, in_force);
    in_force = q;
  }
  EXPECT_LT(s, 0.59);
}

TEST(StepMapControlTest, LimitsAndTheFisShift) {
  const StepMapBand m{0.6, 8.0 * kDeg, 0.55, 0.006 / kDeg};
  StepMapParams p = OneBand(m, 0.0);
  p.max_change = 2.0 * kDeg;
  p.fis_gain = 1.0;
  StepMapControl law(p);
  // Far too slow: the pitch rises by max_change only.
  EXPECT_NEAR(law.Update(0.3, 0.6, m.q_star, -1.0, 1.0), m.q_star + 2.0 * kDeg, kTolerance);
  EXPECT_DOUBLE_EQ(law.fis_offset(), 0.0);  // the step limit is not the range: no shift
  // The range clamps: the FIS is asked for the withheld speed, b / (1 - a) per rad, capped.
  StepMapParams wide = OneBand(m, 0.0);
  wide.fis_gain = 1.0;
  wide.fis_max = 1.0;
  StepMapControl ranged(wide);
  const double q_max = m.q_star + 1.0 * kDeg;
  const double e1 = m.a * (0.55 - 0.6);
  const double wanted = m.q_star - m.a * e1 / m.b;
  EXPECT_NEAR(ranged.Update(0.55, 0.6, m.q_star, -1.0, q_max), q_max, kTolerance);
  EXPECT_NEAR(ranged.fis_offset(), m.b / (1.0 - m.a) * (wanted - q_max), kTolerance);
}

TEST(StepMapControlTest, ParamsValidation) {
  std::string error;
  StepMapParams p;
  EXPECT_TRUE(p.IsValid(&error)) << error;
  p.bands[1].v = p.bands[0].v;  // not ascending
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("band 2"), std::string::npos);
  p = StepMapParams();
  p.bands[0].b = 0.0;
  EXPECT_FALSE(p.IsValid(&error));
  p = StepMapParams();
  p.decay = 1.0;
  EXPECT_FALSE(p.IsValid(&error));
  p = StepMapParams();
  p.max_change = 0.0;
  EXPECT_FALSE(p.IsValid(&error));
  p = StepMapParams();
  p.bands.clear();
  EXPECT_FALSE(p.IsValid(&error));
}

// Through VelocityControl: law = step_map answers with the map, the rate limit still applies.
TEST(StepMapControlTest, VelocityControlUsesTheMap) {
  VelocityControlParams p;
  p.enabled = true;
  p.v_d_rate = 0.1;
  p.law = VelocityLaw::kStepMap;
  const StepMapBand m{0.6, 8.0 * kDeg, 0.55, 0.006 / kDeg};
  p.step_map = OneBand(m, 0.5);
  VelocityControl v(p, 0.2, 0.1, -0.1, 0.45, m.q_star, PitchMap());
  EXPECT_DOUBLE_EQ(v.Command(0.6), 0.6);
  StepMapControl reference(p.step_map);
  EXPECT_NEAR(v.Update(0.6, 0.5), reference.Update(0.6, 0.6, m.q_star, -0.1, 0.45), kTolerance);
  EXPECT_NEAR(v.Command(0.9), 0.7, kTolerance);  // rate-limited
}

class StepMapKeysTest : public testing::WalkerKeysTest {
 protected:
  StepMapKeysTest() : WalkerKeysTest("rabbit_step_map_control_test", "velocity_control") {}
};

TEST_F(StepMapKeysTest, ReadAndValidated) {
  EXPECT_EQ(LoadSuite(Write("")).scenarios[0].walker.velocity_control.law, VelocityLaw::kChapter);
  const Suite suite = LoadSuite(
      Write("law = \"step_map\"\nstep_map = { decay = 0.3, offset_gain = 0.2, offset_max = 0.1, "
            "max_change_deg = 4.0, fis_gain = 0.5, fis_max = 0.1, bands = [[0.4, -2.0, 0.5, "
            "0.005], [0.8, 16.0, 0.6, 0.007]] }\n"));
  const VelocityControlParams& v = suite.scenarios[0].walker.velocity_control;
  EXPECT_EQ(v.law, VelocityLaw::kStepMap);
  EXPECT_DOUBLE_EQ(v.step_map.decay, 0.3);
  EXPECT_DOUBLE_EQ(v.step_map.offset_gain, 0.2);
  EXPECT_DOUBLE_EQ(v.step_map.offset_max, 0.1);
  EXPECT_NEAR(v.step_map.max_change, 4.0 * kDeg, kTolerance);
  EXPECT_DOUBLE_EQ(v.step_map.fis_gain, 0.5);
  EXPECT_DOUBLE_EQ(v.step_map.fis_max, 0.1);
  ASSERT_EQ(v.step_map.bands.size(), 2u);
  EXPECT_NEAR(v.step_map.bands[1].q_star, 16.0 * kDeg, kTolerance);
  EXPECT_NEAR(v.step_map.bands[1].b, 0.007 / kDeg, kTolerance);
  ExpectError("law = \"fast\"\n", "scenario[1].controller.velocity_control.law");
  ExpectError("step_map = { decay = 1.5 }\n",
              "scenario[1].controller.velocity_control.step_map.decay");
  ExpectError("step_map = { bands = [[0.4, -2.0, 0.5, -0.005]] }\n",
              "scenario[1].controller.velocity_control.step_map.bands");
  ExpectError("step_map = { decai = 0.5 }\n",
              "scenario[1].controller.velocity_control.step_map.decai");
}

}  // namespace
}  // namespace rabbit
