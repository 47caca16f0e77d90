// The Fuzzy-CMAC gait pattern (eqs. 12-13) assembled from the shipped networks and FLL: its
// output equals the activation-weighted sum of the reference gaits' CMAC outputs computed
// independently, it reproduces each reference gait where one rule fires, and mismatched pieces are
// refused.
#include "rabbit/learn/fuzzy_cmac.h"

#include <gtest/gtest.h>

#include <random>

#include "rabbit/gait/gait_database.h"
#include "rabbit/learn/fll.h"
#include "rabbit/learn/gait_pattern.h"

namespace rabbit {
namespace {

const std::string kRoot = RABBIT_SOURCE_DIR;

// The shipped speed gaits' networks, in index order: the walker's, those the gait pattern's rules
// name (the shipped networks folder also holds the library gaits', which no rule names).
std::vector<GaitCmacs> SpeedGaitNetworks() {
  std::vector<std::string> names;
  std::vector<GaitCmacs> all = LoadGaitNetworks(kRoot + "/gaits/networks", &names);
  const std::vector<GaitIndexEntry> speed =
      GaitsOfRole(ReadGaitIndex(kRoot + "/gaits/reference/index.csv"), GaitRole::kSpeed);
  std::vector<GaitCmacs> out;
  for (size_t k = 0; k < all.size(); ++k) {
    for (const GaitIndexEntry& e : speed) {
      if (e.name == names[k]) out.push_back(all[k]);
    }
  }
  return out;
}

FuzzyCmac SpeedGaitPattern() {
  return FuzzyCmac(LoadFll(kRoot + "/gaits/gait_pattern.fll"), SpeedGaitNetworks());
}

TEST(FuzzyCmacTest, EqualsActivationWeightedSumOfCmacOutputs) {
  const TsFis fis = LoadFll(kRoot + "/gaits/gait_pattern.fll");
  const std::vector<GaitCmacs> networks = SpeedGaitNetworks();
  FuzzyCmac pattern(fis, networks);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> v(0.3, 0.9), d(0.0, 0.8), e(-0.1, 0.5);
  const double kTolerance = 1e-12;
  for (int n = 0; n < 2000; ++n) {
    const double vm = v(rng), dobs = d(rng), x = e(rng);
    ASSERT_TRUE(pattern.SetContext(vm, dobs));
    TsFis::Result r;
    fis.Evaluate({vm, dobs}, &r);
    Eigen::Vector4d expected = Eigen::Vector4d::Zero();
    for (size_t rule = 0; rule < fis.rules.size(); ++rule) {
      const int k = static_cast<int>(fis.output_values[fis.rules[rule].consequent]) - 1;
      for (int o = 0; o < kGaitOutputs; ++o) {
        expected[o] += r.activation[rule] * networks[k][o].Query(x);
      }
    }
    EXPECT_LE((pattern.Query(x) - expected).cwiseAbs().maxCoeff(),
              kTolerance * (1.0 + expected.cwiseAbs().maxCoeff()));
  }
}

TEST(FuzzyCmacTest, ReproducesEachReferenceGaitAtItsVelocity) {
  // No obstacle and V_M at a gait's own velocity: one rule fires and the pattern is that gait's
  // trained CMACs, which fit its stored swing trajectory.
  FuzzyCmac pattern = SpeedGaitPattern();
  // The speed gaits (the pattern's; the index lists them first, so k is also their networks'
  // place), not the library gaits, which no rule names.
  const std::vector<GaitIndexEntry> index =
      GaitsOfRole(ReadGaitIndex(kRoot + "/gaits/reference/index.csv"), GaitRole::kSpeed);
  ASSERT_EQ(index.size(), pattern.gait_weights().size());
  for (size_t k = 0; k < index.size(); ++k) {
    SCOPED_TRACE(index[k].name);
    ASSERT_TRUE(pattern.SetContext(index[k].measured_v_m, 1.0));
    EXPECT_NEAR(pattern.gait_weights()[k], 1.0, 1e-9);
    const GaitRecord gait = ReadGaitFile(kRoot + "/gaits/reference/" + index[k].file);
    double sum = 0.0;
    for (const SwingSample& s : gait.swing) {
      const Eigen::Vector4d y = pattern.Query(s.e);
      sum += (y[0] - s.q1) * (y[0] - s.q1);
    }
    const double rms_deg = std::sqrt(sum / static_cast<double>(gait.swing.size())) * 180.0 / M_PI;
    // The steep hip pulses of vm_0.40 (0.57 deg) and vm_0.30 (2.1 deg) are the worst
    // (docs/results.md).
    const double kLimitDeg = index[k].name == "vm_0.30" ? 2.5 : 1.0;
    EXPECT_LT(rms_deg, kLimitDeg);
  }
}

TEST(FuzzyCmacTest, MismatchedPiecesAreRefused) {
  const TsFis fis = LoadFll(kRoot + "/gaits/gait_pattern.fll");
  std::vector<GaitCmacs> networks = SpeedGaitNetworks();
  std::vector<GaitCmacs> four(networks.begin(), networks.begin() + 4);
  EXPECT_THROW(FuzzyCmac(fis, four), std::invalid_argument);  // rules name O5
  std::vector<GaitCmacs> short_gait = networks;
  short_gait[2].pop_back();
  EXPECT_THROW(FuzzyCmac(fis, short_gait), std::invalid_argument);
  CmacOptions other = networks[0][0].options();
  other.x_max += 0.1;
  std::vector<GaitCmacs> mixed = networks;
  mixed[1][0] = Cmac(other);
  EXPECT_THROW(FuzzyCmac(fis, mixed), std::invalid_argument);
}

TEST(FuzzyCmacTest, ThighFrameShiftsEachGaitByItsTrunkPitch) {
  // QueryThigh(th) = sum_k w_k [O^k(th + p_k) - (p_k, 0, 0, 0)], computed here gait by gait.
  const TsFis fis = LoadFll(kRoot + "/gaits/gait_pattern.fll");
  const std::vector<GaitCmacs> networks = SpeedGaitNetworks();
  FuzzyCmac pattern(fis, networks);
  EXPECT_THROW(pattern.QueryThigh(0.1), std::logic_error);
  EXPECT_THROW(pattern.SetTrunkPitches({0.1, 0.2}), std::invalid_argument);
  const std::vector<double> pitches = {-0.026, 0.0, -0.087, 0.156, 0.124, 0.262, 0.436, 0.436};
  pattern.SetTrunkPitches(pitches);
  const double kTolerance = 1e-12;
  for (double v : {0.42, 0.55, 0.73}) {
    for (double d : {1.0, 0.33, 0.1}) {
      ASSERT_TRUE(pattern.SetContext(v, d));
      for (double th : {-0.3, -0.05, 0.2}) {
        Eigen::Vector4d expected = Eigen::Vector4d::Zero();
        for (size_t k = 0; k < networks.size(); ++k) {
          const double w = pattern.gait_weights()[k];
          for (int o = 0; o < kGaitOutputs; ++o) {
            expected[o] +=
                w * (networks[k][o].Query(th + pitches[k]) - (o == 0 ? pitches[k] : 0.0));
          }
        }
        EXPECT_LE((pattern.QueryThigh(th) - expected).cwiseAbs().maxCoeff(), kTolerance);
      }
    }
  }
}

TEST(FuzzyCmacTest, StrongestRuleOnlyKeepsOneGait) {
  FuzzyCmac pattern = SpeedGaitPattern();
  // Between the 0.5 and 0.6 m/s gaits, nearer the 0.6 one; no obstacle: V3 and V4 fire.
  ASSERT_TRUE(pattern.SetContext(0.56, 1.0));
  // (Gaits vm_0.30 ... vm_1.00: the 0.5 and 0.6 m/s gaits are the third and fourth.)
  EXPECT_GT(pattern.gait_weights()[2], 0.0);
  EXPECT_GT(pattern.gait_weights()[3], pattern.gait_weights()[2]);
  pattern.KeepStrongestRuleOnly();
  const std::vector<double> expected = {0, 0, 0, 1, 0, 0, 0, 0};
  EXPECT_EQ(pattern.gait_weights(), expected);
}

}  // namespace
}  // namespace rabbit
