// Ceres and LMS fits of CMACs: they agree on the same data to within what the regulariser and
// the LMS epochs leave; the Ceres fit of a shipped gait's swing angles has RMS error below 0.1 deg;
// hashed storage with collisions fits too. And the memory comparison: 20 SISO CMACs
// versus one multi-input CMAC over (e, V_M, d_obs) reaching the same training RMS, with their
// errors on held-out gaits.
#include "cmac_fit.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "rabbit/gait/gait_database.h"
#include "rabbit/learn/cmac_training.h"
#include "rabbit/learn/multi_cmac.h"

namespace rabbit {
namespace {

constexpr double kDeg = M_PI / 180.0;
const std::string kGaits = std::string(RABBIT_SOURCE_DIR) + "/gaits/reference/";

CmacOptions GaitStructure() {
  CmacOptions o;
  o.x_min = -0.3;
  o.x_max = 0.7;
  return o;
}

TEST(CmacFitTest, CeresFitOfAShippedGaitIsBelowATenthOfADegree) {
  const GaitRecord g = ReadGaitFile(kGaits + "vm_0.60.csv");
  std::vector<double> x, q1, q2;
  for (const SwingSample& s : g.swing) {
    x.push_back(s.e);
    q1.push_back(s.q1);
    q2.push_back(s.q2);
  }
  for (const std::vector<double>* y : {&q1, &q2}) {
    Cmac ceres_fit(GaitStructure()), lms_fit(GaitStructure());
    const CmacFitSummary summary = FitCmacCeres(x, *y, CmacFitOptions{}, &ceres_fit);
    const double kMaxRms = 0.1 * kDeg;
    EXPECT_LT(summary.rms, kMaxRms) << summary.brief;
    LmsOptions lms;
    lms.epochs = 2000;
    TrainCmacLms(x, *y, lms, &lms_fit);
    // Both fit the same samples; where the data decide the outputs they agree to within the
    // smoothness regulariser's pull plus LMS's residual (0.1 deg).
    const double kAgreement = 0.1 * kDeg;
    for (double xi : x) EXPECT_NEAR(ceres_fit.Query(xi), lms_fit.Query(xi), kAgreement);
  }
}

TEST(CmacFitTest, HashedStorageWithCollisionsStillFits) {
  CmacOptions o = GaitStructure();
  o.hash_table_size = 200;  // fewer weights than detectors: collisions
  Cmac cmac(o);
  ASSERT_GT(cmac.NumCollisions(), 0);
  std::vector<double> x, y;
  for (int i = 0; i <= 200; ++i) {
    x.push_back(-0.2 + 0.8 * i / 200.0);
    y.push_back(0.3 * std::sin(4.0 * x.back()));
  }
  const CmacFitSummary s = FitCmacCeres(x, y, CmacFitOptions{}, &cmac);
  EXPECT_LT(s.rms, 0.02);
}

// The memory comparison, printed: trained on the gaits at 0.4, 0.6 and 0.8 m/s, tested on
// 0.5 and 0.7 (d_obs = 1 m, no obstacle). The Fuzzy-CMAC blends its SISO CMACs with the FIS
// weights at the held-out velocity; the multi-input CMAC answers from its own generalisation.
TEST(CmacFitTest, MemoryComparisonWithAMultiInputCmac) {
  const char* train[] = {"vm_0.40", "vm_0.60", "vm_0.80"};
  const char* held_out[] = {"vm_0.50", "vm_0.70"};
  // Multi-input CMAC over (e, V_M, d_obs), hashed; learns q_i1 only (one of the four outputs).
  MultiCmacOptions mo;
  mo.layers = 6;
  mo.inputs = {{0.25 * kDeg, 6, -0.3, 0.7}, {0.01, 6, 0.2, 1.0}, {0.05, 6, 0.0, 1.0}};
  mo.hash_table_size = 1 << 16;
  MultiCmac multi(mo);
  std::vector<std::array<double, 3>> points;
  std::vector<double> targets;
  for (const char* name : train) {
    const GaitRecord g = ReadGaitFile(kGaits + name + ".csv");
    for (const SwingSample& s : g.swing) {
      points.push_back({s.e, g.measured.v_m, 1.0});
      targets.push_back(s.q1);
    }
  }
  double rms = 0.0;
  for (int epoch = 0; epoch < 3000; ++epoch) {
    for (size_t i = 0; i < points.size(); ++i) multi.Update(points[i].data(), targets[i], 0.5);
  }
  for (size_t i = 0; i < points.size(); ++i) {
    const double d = multi.Query(points[i].data()) - targets[i];
    rms += d * d;
  }
  rms = std::sqrt(rms / static_cast<double>(points.size()));
  // SISO side: 20 CMACs (4 outputs x 5 gaits) of this structure.
  const std::size_t siso_bytes = 20 * Cmac(GaitStructure()).MemoryBytes();
  // Held-out error of the multi-input CMAC on q_i1.
  double held = 0.0;
  int count = 0;
  for (const char* name : held_out) {
    const GaitRecord g = ReadGaitFile(kGaits + name + ".csv");
    for (const SwingSample& s : g.swing) {
      const std::array<double, 3> p = {s.e, g.measured.v_m, 1.0};
      const double d = multi.Query(p.data()) - s.q1;
      held += d * d;
      ++count;
    }
  }
  held = std::sqrt(held / count);
  // Fuzzy-CMAC side with the same three training gaits: one SISO CMAC per gait (q_i1), blended
  // at a held-out velocity with the weights the V_M triangles give (linear between neighbours).
  std::vector<Cmac> siso;
  std::vector<double> velocities;
  double siso_rms = 0.0;
  for (const char* name : train) {
    const GaitRecord g = ReadGaitFile(kGaits + name + ".csv");
    std::vector<double> x, y;
    for (const SwingSample& s : g.swing) {
      x.push_back(s.e);
      y.push_back(s.q1);
    }
    siso.emplace_back(GaitStructure());
    siso_rms = std::max(siso_rms, FitCmacCeres(x, y, CmacFitOptions{}, &siso.back()).rms);
    velocities.push_back(g.measured.v_m);
  }
  double fuzzy_held = 0.0;
  int fuzzy_count = 0;
  for (const char* name : held_out) {
    const GaitRecord g = ReadGaitFile(kGaits + name + ".csv");
    const size_t k = g.measured.v_m < velocities[1] ? 0 : 1;
    const double w = (g.measured.v_m - velocities[k]) / (velocities[k + 1] - velocities[k]);
    for (const SwingSample& s : g.swing) {
      const double d = (1 - w) * siso[k].Query(s.e) + w * siso[k + 1].Query(s.e) - s.q1;
      fuzzy_held += d * d;
      ++fuzzy_count;
    }
  }
  fuzzy_held = std::sqrt(fuzzy_held / fuzzy_count);
  std::printf(
      "memory: 20 SISO CMACs (5 gaits x 4 outputs) %zu bytes; one multi-input CMAC over "
      "(e, V_M, d_obs) for q_i1 alone %zu bytes\n",
      siso_bytes, multi.MemoryBytes());
  std::printf(
      "q_i1, trained on 0.4/0.6/0.8 m/s: multi-input CMAC training RMS %.3f deg, held-out "
      "(0.5/0.7) RMS %.2f deg; SISO CMACs training RMS %.3f deg, blended held-out RMS "
      "%.2f deg\n",
      rms / kDeg, held / kDeg, siso_rms / kDeg, fuzzy_held / kDeg);
  EXPECT_LT(fuzzy_held, held);  // the blend generalises between gaits; the multi-input CMAC less
  EXPECT_LT(rms, 0.5 * kDeg);   // it does learn the training gaits
  EXPECT_GT(multi.MemoryBytes(), siso_bytes / 4);  // one output alone needs a large table
}

}  // namespace
}  // namespace rabbit
