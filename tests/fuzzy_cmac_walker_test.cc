// The closed-loop walker (eqs. 19-24): velocity profiles at hand-computed points; the PD laws equal
// a hand computation on a gait pattern of constant CMACs; the velocity law on a scripted contact
// sequence (step lengths and times known); perception of obstacles; seeded noise; the clearance
// reflex's activation; any SwingPattern in the Fuzzy-CMAC's place, and nearest-gait switching.
#include "rabbit/control/fuzzy_cmac_walker.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include "rabbit/learn/ts_fis.h"

namespace rabbit {
namespace {

constexpr double kTolerance = 1e-12;
const std::vector<double> kVelocities = {0.4, 0.5, 0.6, 0.7, 0.8};

// A gait pattern whose gait k outputs the constants c_k = (0.1 k, -0.05 k, 0.5 k, -0.2 k) for any
// e: CMAC weights all c / layers.
FuzzyCmac ConstantPattern() {
  CmacOptions o;
  o.x_min = -1.0;
  o.x_max = 1.0;
  std::vector<GaitCmacs> networks;
  for (int k = 1; k <= 5; ++k) {
    GaitCmacs gait;
    const double c[4] = {0.1 * k, -0.05 * k, 0.5 * k, -0.2 * k};
    for (double value : c) {
      Cmac cmac(o);
      for (double& w : *cmac.mutable_weights()) w = value / o.layers;
      gait.push_back(cmac);
    }
    networks.push_back(gait);
  }
  FuzzyCmac pattern(DefaultGaitPattern(kVelocities), networks);
  pattern.SetTrunkPitches({0.01, 0.02, 0.03, 0.04, 0.05});
  return pattern;
}

Observation Standing(double t, bool foot0, bool foot1, double x0, double x1) {
  Observation obs;
  obs.t = t;
  obs.q << 0.0, 0.85, 0.05, 0.2, -0.1, -0.15, -0.3;
  obs.qd << 0.6, 0.0, 0.1, -0.5, 0.3, 0.8, -0.4;
  obs.foot_contact = {foot0, foot1};
  obs.foot_pos = {Vec2(x0, 0.0), Vec2(x1, 0.0)};
  return obs;
}

// The scripted contact sequence of the velocity tests: leg 1 (index 1) lifts off at t = 0.1 and
// lands at 0.6 s, 0.30 m ahead of leg 0 (V_M = 0.6 m/s); leg 0 lifts off at 0.7 s and lands at
// 1.1 s, 0.36 m ahead (V_M = 0.9 m/s): its observation at t. WalkTwoSteps feeds 1.2 s of them at
// 1 kHz.
Observation TwoStepsAt(double t, const Terrain* terrain) {
  const bool air1 = t >= 0.1 - 1e-9 && t < 0.6 - 1e-9;
  const bool air0 = t >= 0.7 - 1e-9 && t < 1.1 - 1e-9;
  Observation obs =
      Standing(t, !air0, !air1, t < 1.1 - 1e-9 ? -0.1 : 0.56, t < 0.6 - 1e-9 ? -0.1 : 0.2);
  obs.terrain = terrain;
  return obs;
}

void WalkTwoSteps(FuzzyCmacWalker* walker, const Terrain* terrain = nullptr) {
  for (int k = 0; k <= 1200; ++k) walker->Compute(TwoStepsAt(k * 1e-3, terrain));
}

TEST(VelocityProfileTest, ConstantRampAndSteps) {
  VelocityProfile v;
  v.points = {{0.0, 0.4}, {10.0, 0.8}, {20.0, 1.0}};
  v.kind = VelocityProfile::Kind::kConstant;
  EXPECT_DOUBLE_EQ(v.At(15.0), 0.4);
  v.kind = VelocityProfile::Kind::kRamp;
  EXPECT_DOUBLE_EQ(v.At(-1.0), 0.4);
  EXPECT_NEAR(v.At(5.0), 0.6, kTolerance);
  EXPECT_NEAR(v.At(15.0), 0.9, kTolerance);
  EXPECT_DOUBLE_EQ(v.At(30.0), 1.0);
  v.kind = VelocityProfile::Kind::kSteps;
  EXPECT_DOUBLE_EQ(v.At(9.999), 0.4);
  EXPECT_DOUBLE_EQ(v.At(10.0), 0.8);
  EXPECT_DOUBLE_EQ(v.At(25.0), 1.0);
  std::string error;
  EXPECT_TRUE(v.IsValid(&error)) << error;
  VelocityProfile empty;
  empty.points.clear();
  EXPECT_FALSE(empty.IsValid(&error));
  EXPECT_NE(error.find("no points"), std::string::npos);
  VelocityProfile backwards = v;
  backwards.points = {{5.0, 0.5}, {1.0, 0.6}};
  EXPECT_FALSE(backwards.IsValid(&error));
  VelocityProfile nan = v;
  nan.points = {{0.0, std::nan("")}};
  EXPECT_FALSE(nan.IsValid(&error));
  VelocityProfile negative = v;
  negative.points = {{0.0, -0.2}};
  EXPECT_FALSE(negative.IsValid(&error));
}

TEST(FuzzyCmacWalkerTest, PdLawsOfEquations21To24) {
  WalkerParams p;
  p.warmup_steps = 0;  // the walker's own laws from t = 0
  p.q0_d_initial = 0.07;
  p.v_m_initial = 0.6;  // the 0.6 m/s gait alone (k = 3) before any step
  VelocityProfile v;
  for (bool thigh : {true, false}) {
    p.thigh_frame = thigh;
    FuzzyCmacWalker walker(p, ConstantPattern(), v, 0);
    const Observation obs = Standing(0.0, true, false, 0.0, -0.2);
    const Vec4 tau = walker.Compute(obs);
    const Vec7& q = obs.q;
    const Vec7& qd = obs.qd;
    // Gait 3: (0.3, -0.15, 1.5, -0.6); in the thigh frame its hip output is 0.3 - 0.03 + q0.
    const double hip_ref = thigh ? 0.3 - 0.03 + q[kQ0] : 0.3;
    const double hip_rate_ref = thigh ? 1.5 + qd[kQ0] : 1.5;
    EXPECT_NEAR(tau[2], p.hip_kp * (hip_ref - q[kQ21]) + p.hip_kd * (hip_rate_ref - qd[kQ21]),
                1e-9);
    EXPECT_NEAR(tau[3], p.knee_kp * (-0.15 - q[kQ22]) + p.knee_kd * (-0.6 - qd[kQ22]), 1e-9);
    EXPECT_NEAR(tau[1], -p.stance_knee_kp * q[kQ12] - p.stance_knee_kd * qd[kQ12], 1e-9);
    EXPECT_NEAR(tau[0], p.trunk_kp * (0.07 - q[kQ0]) - p.trunk_kd * qd[kQ0], 1e-9);
  }
}

// The stance knee's landing. In WalkTwoSteps's script leg 0 swings from 0.7 to 1.1 s and lands
// 0.56 m ahead; here with its knee at -0.5 rad. When that swing was lifted (an obstacle 0.1 m
// ahead of leg 1's foot when it landed at 0.6 s: d_obs below lift.d_obs) and the landing is flexed
// below stance_knee_flexed, the stance knee's reference rises from -0.5 at stance_knee_rate to 0
// (eq. 23's target); otherwise it is 0 at once.
TEST(FuzzyCmacWalkerTest, AKneeLandingFlexedFromALiftedSwingStraightensAtTheStanceKneeRate) {
  WalkerParams p;
  p.warmup_steps = 0;
  p.thigh_frame = false;
  p.stance_knee_rate = 2.0;
  Terrain obstacle;
  obstacle.obstacles = {{0.3, 0.1, 0.02}};
  VelocityProfile v;
  for (const Terrain* terrain : std::vector<const Terrain*>{&obstacle, nullptr}) {
    for (double flexed : {-0.3, -0.6}) {
      p.stance_knee_flexed = flexed;
      FuzzyCmacWalker walker(p, ConstantPattern(), v, 0);
      for (int k = 0; k <= 1400; ++k) {
        const double t = k * 1e-3;
        Observation obs = TwoStepsAt(t, terrain);
        if (t >= 1.1 - 1e-9) obs.q[kQ12] = -0.5;  // leg 0 lands flexed
        const Vec4 tau = walker.Compute(obs);
        if (k == 1150 || k == 1400) {
          ASSERT_EQ(walker.steps().size(), 2u);  // leg 0 has landed and is the stance leg
          const bool ramp = terrain != nullptr && -0.5 < flexed;
          const double ref = ramp ? std::min(-0.5 + 2.0 * (t - 1.1), 0.0) : 0.0;
          EXPECT_NEAR(tau[1],
                      p.stance_knee_kp * (ref - obs.q[kQ12]) - p.stance_knee_kd * obs.qd[kQ12],
                      1e-9)
              << "obstacle " << (terrain != nullptr) << ", flexed " << flexed << ", t " << t;
        }
      }
    }
  }
  EXPECT_EQ(WalkerParams().stance_knee_rate, 0.0);  // off by default: eq. 23 as it is
}

// A gait pattern of constant references that records the contexts it was given.
class RecordingPattern final : public SwingPattern {
 public:
  explicit RecordingPattern(bool thigh_frame) : thigh_frame_(thigh_frame) {}
  bool SetContext(double v_m, double d_obs) override {
    contexts->push_back({v_m, d_obs});
    return true;
  }
  bool SetGaitWeights(const std::vector<double>&) override { return false; }
  bool Supports(bool thigh_frame) const override { return thigh_frame == thigh_frame_; }
  Eigen::Vector4d Query(double) const override { return {0.2, -0.1, 1.0, -0.4}; }
  Eigen::Vector4d QueryThigh(double) const override { return {0.2, -0.1, 1.0, -0.4}; }
  const std::vector<double>& GaitWeights() const override { return none_; }
  const std::vector<double>& RuleActivations() const override { return none_; }
  std::size_t MemoryBytes() const override { return 7; }
  std::shared_ptr<std::vector<std::pair<double, double>>> contexts =
      std::make_shared<std::vector<std::pair<double, double>>>();

 private:
  bool thigh_frame_;
  std::vector<double> none_;
};

TEST(FuzzyCmacWalkerTest, AnySwingPatternTakesTheFuzzyCmacsPlace) {
  WalkerParams p;
  p.warmup_steps = 0;
  p.thigh_frame = false;
  p.v_m_initial = 0.55;
  VelocityProfile v;
  FuzzyCmacWalker walker(p, std::make_unique<RecordingPattern>(false), v, 0);
  EXPECT_EQ(walker.gait_pattern().MemoryBytes(), 7u);
  const Observation obs = Standing(0.0, true, false, 0.0, -0.2);
  const Vec4 tau = walker.Compute(obs);
  EXPECT_NEAR(tau[2], p.hip_kp * (0.2 - obs.q[kQ21]) + p.hip_kd * (1.0 - obs.qd[kQ21]), 1e-9);
  EXPECT_NEAR(tau[3], p.knee_kp * (-0.1 - obs.q[kQ22]) + p.knee_kd * (-0.4 - obs.qd[kQ22]), 1e-9);
  // The context: before the first step (the assumed V_M, no obstacle), then at each touchdown.
  auto recording = std::make_unique<RecordingPattern>(false);
  const auto seen = recording->contexts;
  FuzzyCmacWalker two(p, std::move(recording), v, 0);
  WalkTwoSteps(&two);
  ASSERT_EQ(two.steps().size(), 2u);
  ASSERT_EQ(seen->size(), 3u);
  EXPECT_EQ((*seen)[0], std::make_pair(0.55, p.d_obs_max));
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ((*seen)[k + 1], std::make_pair(two.steps()[k].v_m_used, two.steps()[k].d_obs));
    EXPECT_TRUE(two.steps()[k].weights.empty());
    EXPECT_TRUE(two.steps()[k].activation.empty());
  }
  // The pattern must serve the walker's frame.
  p.thigh_frame = true;
  EXPECT_THROW(FuzzyCmacWalker(p, std::make_unique<RecordingPattern>(false), v, 0),
               std::invalid_argument);
  p.thigh_frame = false;
  EXPECT_THROW(FuzzyCmacWalker(p, std::make_unique<RecordingPattern>(true), v, 0),
               std::invalid_argument);
  EXPECT_THROW(FuzzyCmacWalker(p, std::unique_ptr<SwingPattern>(), v, 0), std::invalid_argument);
}

TEST(FuzzyCmacWalkerTest, NearestGaitSwitchingKeepsOneGait) {
  WalkerParams p;
  p.warmup_steps = 0;
  p.thigh_frame = false;
  p.v_m_average_steps = 1;
  VelocityProfile v;
  for (bool nearest : {false, true}) {
    FuzzyCmacWalker walker(p, std::make_unique<FuzzyCmacSwingPattern>(ConstantPattern(), nearest),
                           v, 0);
    WalkTwoSteps(&walker);
    ASSERT_EQ(walker.steps().size(), 2u);
    // The first step's V_M = 0.6 m/s is gait 3's centre; the second's 0.9 m/s beyond gait 5's;
    // only at a V_M between two centres would the blend and the switching differ.
    for (const WalkerStep& s : walker.steps()) {
      int ones = 0;
      for (double w : s.weights) ones += w == 1.0 ? 1 : 0;
      EXPECT_EQ(ones, 1);
    }
  }
  // Between centres (0.75 m/s after a stride): blended, or switched to the nearer gait.
  p.v_m_average_steps = 2;
  FuzzyCmacWalker blended(p, std::make_unique<FuzzyCmacSwingPattern>(ConstantPattern(), false), v,
                          0);
  FuzzyCmacWalker switched(p, std::make_unique<FuzzyCmacSwingPattern>(ConstantPattern(), true), v,
                           0);
  WalkTwoSteps(&blended);
  WalkTwoSteps(&switched);
  EXPECT_NEAR(blended.steps()[1].weights[3], 0.5, 1e-9);
  EXPECT_NEAR(blended.steps()[1].weights[4], 0.5, 1e-9);
  const std::vector<double>& w = switched.steps()[1].weights;
  EXPECT_EQ(w[3] + w[4], 1.0);
  EXPECT_TRUE(w[3] == 1.0 || w[4] == 1.0);
}

// Rule share (docs/design/walker.md, "The walker"): gait 3 alone (weight 1) with share r gives the
// swing (1 - r) PD + r (its rules' torques), and the stance knee the mix of the walker's and the
// gait's gains. At t = 0.1 s of the swing the rules' hip is in its pulse and the knee free; once
// the thighs open past qr1_dsw, the hip locks with the gait's PD.
TEST(FuzzyCmacWalkerTest, RuleShareMixesTrackingAndTheGaitsOwnRules) {
  WalkerParams p;
  p.warmup_steps = 0;
  p.v_m_initial = 0.6;  // gait 3 alone
  p.thigh_frame = false;
  PragmaticParams rules;
  rules.pulse_torque = 40.0;
  rules.pulse_start = 0.0;
  rules.pulse_duration = 0.3;
  rules.qr1_dsw = 0.2;
  rules.qi2_dsw = -0.5;  // the swing knee (-0.3) has not flexed past it: free
  rules.hip_kp = 600.0;
  rules.hip_kd = 30.0;
  rules.knee_kp = 120.0;
  rules.knee_kd = 6.0;
  p.gait_rules.assign(5, rules);
  VelocityProfile v;
  for (double r : {0.0, 0.25, 1.0}) {
    p.rule_share = {0.0, 0.0, r, 0.0, 0.0};
    FuzzyCmacWalker walker(p, ConstantPattern(), v, 0);
    Observation obs = Standing(0.1, true, false, 0.0, -0.2);
    obs.q[kQ21] = 0.1;  // qr1 = q21 - q11 = -0.1 < qr1_dsw: the hip is not locked
    const Vec4 tau = walker.Compute(obs);
    const Vec7& q = obs.q;
    const Vec7& qd = obs.qd;
    const double hip_pd = p.hip_kp * (0.3 - q[kQ21]) + p.hip_kd * (1.5 - qd[kQ21]);
    const double knee_pd = p.knee_kp * (-0.15 - q[kQ22]) + p.knee_kd * (-0.6 - qd[kQ22]);
    EXPECT_NEAR(tau[2], (1.0 - r) * hip_pd + r * 40.0, 1e-9) << "r = " << r;
    EXPECT_NEAR(tau[3], (1.0 - r) * knee_pd, 1e-9) << "r = " << r;
    const double kp = (1.0 - r) * p.stance_knee_kp + r * 120.0;
    const double kd = (1.0 - r) * p.stance_knee_kd + r * 6.0;
    EXPECT_NEAR(tau[1], -kp * q[kQ12] - kd * qd[kQ12], 1e-9) << "r = " << r;
    // The thighs open past qr1_dsw: the rules lock the hip there (and the knee with it).
    obs.t = 0.101;
    obs.q[kQ21] = 0.5;  // qr1 = 0.5 - 0.2 = 0.3 > qr1_dsw
    const Vec4 locked = walker.Compute(obs);
    const double qr1_rate = qd[kQ21] - qd[kQ11];
    const double hip_lock = 600.0 * (0.2 - 0.3) - 30.0 * qr1_rate;
    const double knee_lock = 120.0 * (-0.5 - q[kQ22]) - 6.0 * qd[kQ22];
    const double hip_pd2 = p.hip_kp * (0.3 - 0.5) + p.hip_kd * (1.5 - qd[kQ21]);
    EXPECT_NEAR(locked[2], (1.0 - r) * hip_pd2 + r * hip_lock, 1e-9) << "r = " << r;
    EXPECT_NEAR(locked[3], (1.0 - r) * knee_pd + r * knee_lock, 1e-9) << "r = " << r;
  }
  // One factor per gait, each in [0, 1], and the rules of every gait.
  p.rule_share = {0.0, 0.0, 1.5, 0.0, 0.0};
  std::string error;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("rule_share"), std::string::npos) << error;
  p.rule_share = {1.0, 1.0};
  EXPECT_THROW(FuzzyCmacWalker(p, ConstantPattern(), v, 0), std::invalid_argument);
}

TEST(FuzzyCmacWalkerTest, VelocityControlOfEquations19And20) {
  // WalkTwoSteps: V_M = 0.6 then 0.9 m/s, the second step 0.4 s. With v_m_average_steps = 1:
  //   after step 1: q0_d = 0.07 + K_P (0.8 - 0.6)
  //   after step 2: q0_d += K_P (0.8 - 0.9) + K_V ((0.8 - 0.9) - (0.8 - 0.6)) / 0.4
  WalkerParams p;
  p.warmup_steps = 0;
  p.k_p = 0.1;
  p.k_v = 0.02;
  p.q0_d_initial = 0.07;
  p.v_m_average_steps = 1;
  p.thigh_frame = false;
  VelocityProfile v;
  v.points = {{0.0, 0.8}};
  FuzzyCmacWalker walker(p, ConstantPattern(), v, 0);
  WalkTwoSteps(&walker);
  ASSERT_EQ(walker.steps().size(), 2u);
  const WalkerStep& s1 = walker.steps()[0];
  const WalkerStep& s2 = walker.steps()[1];
  EXPECT_NEAR(s1.step.v_m, 0.6, 1e-9);
  EXPECT_NEAR(s2.step.v_m, 0.9, 1e-9);
  const double q1 = 0.07 + 0.1 * (0.8 - 0.6);
  EXPECT_NEAR(s1.q0_d, q1, 1e-9);
  const double q2 = q1 + 0.1 * (0.8 - 0.9) + 0.02 * ((0.8 - 0.9) - (0.8 - 0.6)) / 0.4;
  EXPECT_NEAR(s2.q0_d, q2, 1e-9);
  EXPECT_NEAR(walker.q0_d(), q2, 1e-9);
  // The fuzzy system saw V_M = 0.9 at the second touchdown: only the fastest gait.
  EXPECT_NEAR(s2.weights[4], 1.0, 1e-9);
}

TEST(FuzzyCmacWalkerTest, PitchIsClampedAndStrideAveraged) {
  WalkerParams p;
  p.warmup_steps = 0;
  p.k_p = 5.0;
  p.q0_d_max = 0.2;
  p.q0_d_initial = 0.07;
  p.v_m_average_steps = 2;
  p.thigh_frame = false;
  VelocityProfile v;
  v.points = {{0.0, 2.0}};
  FuzzyCmacWalker walker(p, ConstantPattern(), v, 0);
  WalkTwoSteps(&walker);
  ASSERT_EQ(walker.steps().size(), 2u);
  EXPECT_DOUBLE_EQ(walker.q0_d(), 0.2);
  EXPECT_NEAR(walker.steps()[1].v_m_used, 0.75, 1e-9);  // mean of 0.6 and 0.9
}

TEST(FuzzyCmacWalkerTest, ObstacleDistanceSaturates) {
  Terrain terrain;
  terrain.obstacles = {{1.0, 0.2, 0.05}, {3.0, 0.2, 0.05}};
  EXPECT_DOUBLE_EQ(ObstacleDistance(terrain, 0.7, 1.0), 0.3);
  EXPECT_DOUBLE_EQ(ObstacleDistance(terrain, 1.1, 1.0), 1.0);  // 1.9 m to the next: saturated
  EXPECT_DOUBLE_EQ(ObstacleDistance(terrain, 2.5, 1.0), 0.5);
  EXPECT_DOUBLE_EQ(ObstacleDistance(terrain, 3.5, 1.0), 1.0);  // none ahead
}

TEST(FuzzyCmacWalkerTest, NoiseIsSeededAndZeroNoiseChangesNothing) {
  auto run = [](double noise, std::uint64_t seed) {
    WalkerParams p;
    p.warmup_steps = 0;
    p.v_m_noise = noise;
    p.d_obs_noise = noise;
    p.seed = seed;
    p.thigh_frame = false;
    VelocityProfile v;
    FuzzyCmacWalker walker(p, ConstantPattern(), v, 0);
    Terrain terrain;
    terrain.obstacles = {{0.5, 0.2, 0.05}};
    WalkTwoSteps(&walker, &terrain);
    std::vector<double> seen;
    for (const WalkerStep& s : walker.steps()) {
      seen.push_back(s.v_m_used);
      seen.push_back(s.d_obs);
    }
    return seen;
  };
  const std::vector<double> clean = run(0.0, 1);
  ASSERT_EQ(clean.size(), 4u);
  EXPECT_NEAR(clean[1], 0.3, 1e-12);  // foot at 0.2, obstacle at 0.5
  EXPECT_EQ(run(0.0, 7), clean);
  EXPECT_EQ(run(0.05, 3), run(0.05, 3));
  EXPECT_NE(run(0.05, 3), run(0.05, 4));
  EXPECT_NE(run(0.05, 3), clean);
}

TEST(FuzzyCmacWalkerTest, InvalidParametersAreRefused) {
  WalkerParams p;
  std::string error;
  EXPECT_TRUE(p.IsValid(&error)) << error;
  WalkerParams bad = p;
  bad.hip_kp = -1.0;
  EXPECT_FALSE(bad.IsValid(&error));
  bad = p;
  bad.q0_d_min = 0.3;
  bad.q0_d_max = 0.1;
  EXPECT_FALSE(bad.IsValid(&error));
  bad = p;
  bad.k_p = std::nan("");
  EXPECT_FALSE(bad.IsValid(&error));
  bad = p;
  bad.rule_gait_choice_mixed_below = std::nan("");
  EXPECT_FALSE(bad.IsValid(&error));
  EXPECT_NE(error.find("rule_gait_choice_mixed_below"), std::string::npos) << error;
  bad.rule_gait_choice_mixed_below = 3.0;
  EXPECT_TRUE(bad.IsValid(&error)) << error;
  bad.rule_gait_choice_mixed_point = 1.2;
  EXPECT_FALSE(bad.IsValid(&error));
  EXPECT_NE(error.find("rule_gait_choice_mixed_point"), std::string::npos) << error;
  bad.rule_gait_choice_mixed_point = 1.0;
  EXPECT_TRUE(bad.IsValid(&error)) << error;
  // The thigh frame needs the gaits' trunk pitches.
  CmacOptions o;
  std::vector<GaitCmacs> networks(5, GaitCmacs(4, Cmac(o)));
  FuzzyCmac without(DefaultGaitPattern(kVelocities), networks);
  EXPECT_THROW(FuzzyCmacWalker(p, without, VelocityProfile{}, 0), std::invalid_argument);
}

// lift_release_rate: while the obstacle lift offsets the swing references, their rates are the
// lifted references' own. With a constant pattern and a still robot the lifted references do not
// move, so the swing's rate references are 0 instead of the pattern's rates: the swing torques
// differ by kd times those rates; without an obstacle (no lift) the walker is the same.
TEST(FuzzyCmacWalkerTest, TheLiftedReferencesRatesAreTheirOwnWithAReleaseRate) {
  Terrain terrain;
  terrain.obstacles = {{0.0, 0.1, 0.05}};  // between the feet at the 0.6 s touchdown: lift armed
  Terrain flat;
  for (const Terrain* t : {&terrain, &flat}) {
    std::vector<Vec4> tau[2];
    for (int on = 0; on < 2; ++on) {
      WalkerParams p;
      p.warmup_steps = 0;
      p.v_m_initial = 0.6;
      p.lift.release_rate = on ? 7.0 : 0.0;
      FuzzyCmacWalker walker(p, ConstantPattern(), VelocityProfile{}, 0);
      for (int k = 0; k <= 800; ++k) {
        const double time = k * 1e-3;
        const bool air1 = time >= 0.1 - 1e-9 && time < 0.6 - 1e-9;
        const bool air0 = time >= 0.7 - 1e-9;  // leg 0 swings from 0.7 s, behind the obstacle
        Observation obs = Standing(time, !air0, !air1, -0.1, time < 0.6 - 1e-9 ? -0.1 : 0.2);
        obs.terrain = t;
        tau[on].push_back(walker.Compute(obs));
      }
    }
    for (int k = 0; k < 700; ++k) EXPECT_EQ(tau[0][k], tau[1][k]) << k;  // before the swing
    // The swing's first lifted period (no previous one): as without the key.
    EXPECT_EQ(tau[0][700], tau[1][700]);
    for (int k = 701; k <= 800; k += 33) {
      if (t == &flat) {
        EXPECT_EQ(tau[0][k], tau[1][k]) << k;
      } else {
        // Swing leg 0: hip tau[0], knee tau[1]; the pattern's rates (0.5 w, -0.2 w; k = 3: 1.5
        // and -0.6 rad/s, the hip's 0.1 more in the thigh frame) are replaced by 0.
        EXPECT_NEAR(tau[0][k][0] - tau[1][k][0], 25.0 * 1.6, 1e-6) << k;  // hip_kd 25
        EXPECT_NEAR(tau[0][k][1] - tau[1][k][1], 20.0 * -0.6, 1e-6) << k;  // knee_kd 20
      }
    }
  }
}

}  // namespace
}  // namespace rabbit
