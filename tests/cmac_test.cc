// The SISO CMAC (cmac.h): active detectors against a brute-force enumeration, clamping, LMS
// convergence on a smooth function, hashed against direct storage, collision counts, no
// allocation on the hot paths.
#include "rabbit/learn/cmac.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <new>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace rabbit {
namespace {

// Counts global allocations, to check that the hot paths make none.
std::atomic<long> g_allocations{0};

}  // namespace
}  // namespace rabbit

void* operator new(std::size_t size) {
  ++rabbit::g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
// GCC cannot tell that the replaced operator new above is malloc-based.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

namespace rabbit {
namespace {

constexpr double kDeg = M_PI / 180.0;

CmacOptions ChapterOptions() {
  CmacOptions o;  // the defaults are the chapter's: 6 layers, 0.25 deg quanta, 1.5 deg fields
  o.x_min = -1.0;
  o.x_max = 1.0;
  return o;
}

// Brute-force reference, from the definitions alone: the quantum of x is the k whose interval
// [k dq, (k + 1) dq) holds u = clamp(x) - x_min (the last one closed at x_max); detector d of
// layer j covers quanta [d width - j, d width - j + width - 1]; a layer's detectors are those
// whose quanta meet [0, Q); the direct table stores layer after layer.
struct Reference {
  explicit Reference(const CmacOptions& o) : options(o) {
    const double range = o.x_max - o.x_min;
    quanta = 1;
    while (quanta * o.quantum < range) ++quanta;
    for (int j = 0; j < o.layers; ++j) {
      int count = 0;
      for (int d = 0;; ++d) {
        const int first = d * o.width - j;
        const int last = first + o.width - 1;
        if (first > quanta - 1) break;
        if (last >= 0) ++count;
      }
      layer_offset.push_back(total);
      detectors.push_back(count);
      total += count;
    }
  }
  int Quantum(double x) const {
    const double u = std::clamp(x, options.x_min, options.x_max) - options.x_min;
    for (int k = 0; k < quanta; ++k) {
      const double lo = k * options.quantum;
      const double hi =
          k == quanta - 1 ? std::numeric_limits<double>::infinity() : (k + 1) * options.quantum;
      if (lo <= u && u < hi) return k;
    }
    return -1;
  }
  // The detectors of layer j holding quantum k (there must be exactly one).
  std::vector<int> Holding(int j, int k) const {
    std::vector<int> out;
    for (int d = 0; d < detectors[j]; ++d) {
      const int first = d * options.width - j;
      if (first <= k && k <= first + options.width - 1) out.push_back(d);
    }
    return out;
  }
  CmacOptions options;
  int quanta = 0;
  int total = 0;
  std::vector<int> detectors, layer_offset;
};

// Inputs over and beyond the range: a fine grid whose step is incommensurate with dq, every
// quantum boundary exactly, the edges and points just past them.
std::vector<double> TestInputs(const CmacOptions& o) {
  const double range = o.x_max - o.x_min;
  std::vector<double> xs;
  for (double x = o.x_min - 0.1 * range; x <= o.x_max + 0.1 * range; x += 0.1373 * o.quantum) {
    xs.push_back(x);
  }
  for (int k = 0; k * o.quantum <= range; ++k) xs.push_back(o.x_min + k * o.quantum);
  const double inf = std::numeric_limits<double>::infinity();
  for (double x : {o.x_min, o.x_max, std::nextafter(o.x_min, -inf), std::nextafter(o.x_min, inf),
                   std::nextafter(o.x_max, -inf), std::nextafter(o.x_max, inf), -inf, inf}) {
    xs.push_back(x);
  }
  return xs;
}

class CmacStructureTest : public ::testing::TestWithParam<CmacOptions> {};

TEST_P(CmacStructureTest, ActiveDetectorsMatchBruteForce) {
  const CmacOptions o = GetParam();
  const Cmac cmac(o);
  const Reference ref(o);
  ASSERT_EQ(cmac.NumQuanta(), ref.quanta);
  ASSERT_EQ(cmac.NumDetectors(), ref.total);
  for (int j = 0; j < o.layers; ++j) EXPECT_EQ(cmac.NumDetectorsInLayer(j), ref.detectors[j]);
  EXPECT_EQ(cmac.weights().size(),
            static_cast<size_t>(o.hash_table_size > 0 ? o.hash_table_size : ref.total));

  CmacActive active;
  for (double x : TestInputs(o)) {
    const int k = ref.Quantum(x);
    ASSERT_GE(k, 0) << x;
    ASSERT_EQ(cmac.Quantize(x), k) << "x = " << x;
    cmac.Active(x, &active);
    ASSERT_EQ(active.count, o.layers);
    for (int j = 0; j < o.layers; ++j) {
      const std::vector<int> holding = ref.Holding(j, k);
      ASSERT_EQ(holding.size(), 1u) << "layer " << j << ", quantum " << k;
      const int expected =
          o.hash_table_size > 0 ? cmac.Address(j, holding[0]) : ref.layer_offset[j] + holding[0];
      ASSERT_EQ(active.index[j], expected) << "x = " << x << ", layer " << j;
      ASSERT_GE(active.index[j], 0);
      ASSERT_LT(active.index[j], static_cast<int>(cmac.weights().size()));
    }
  }
}

TEST_P(CmacStructureTest, OutsideTheRangeClampsToTheEdge) {
  const CmacOptions o = GetParam();
  Cmac cmac(o);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> weight(-1.0, 1.0);
  for (double& w : *cmac.mutable_weights()) w = weight(rng);
  const double range = o.x_max - o.x_min;
  const double inf = std::numeric_limits<double>::infinity();
  for (double beyond : {1e-12, 1e-3 * range, 0.5 * range, 1e300, inf}) {
    EXPECT_EQ(cmac.Query(o.x_min - beyond), cmac.Query(o.x_min)) << beyond;
    EXPECT_EQ(cmac.Query(o.x_max + beyond), cmac.Query(o.x_max)) << beyond;
  }
  // And the edges are distinct quanta from their neighbours inside (no wrap-around).
  EXPECT_EQ(cmac.Quantize(o.x_min - 1.0), 0);
  EXPECT_EQ(cmac.Quantize(o.x_max + 1.0), cmac.NumQuanta() - 1);
}

CmacOptions Make(int layers, double quantum, int width, double x_min, double x_max, int table) {
  CmacOptions o;
  o.layers = layers;
  o.quantum = quantum;
  o.width = width;
  o.x_min = x_min;
  o.x_max = x_max;
  o.hash_table_size = table;
  o.hash_seed = 5;
  return o;
}

INSTANTIATE_TEST_SUITE_P(
    Layouts, CmacStructureTest,
    ::testing::Values(ChapterOptions(),                               // 459 quanta, 464 weights
                      Make(6, 0.25 * kDeg, 6, -0.3, 0.6, 0),          // another range
                      Make(3, 0.1, 5, 0.0, 1.0, 0),                   // layers < width
                      Make(4, 0.25, 4, -1.0, 1.0, 0),                 // range a multiple of dq
                      Make(1, 0.3, 1, 0.0, 1.0, 0),                   // a plain lookup table
                      Make(6, 0.25 * kDeg, 6, -1.0, 1.0, 97),         // hashed, small table
                      Make(6, 0.25 * kDeg, 6, -1.0, 1.0, 1 << 20)));  // hashed, large table

TEST(CmacTest, ChapterSizes) {
  const Cmac cmac(ChapterOptions());
  // 2 rad / 0.25 deg = 458.4: 459 quanta; layer j has floor((458 + j) / 6) + 1 detectors.
  EXPECT_EQ(cmac.NumQuanta(), 459);
  EXPECT_EQ(cmac.NumDetectors(), 77 + 77 + 77 + 77 + 78 + 78);
  EXPECT_EQ(cmac.MemoryBytes(), 464 * sizeof(double));
  EXPECT_EQ(cmac.NumCollisions(), 0);
}

TEST(CmacTest, OutputIsTheSumOfTheActiveWeights) {
  Cmac cmac(ChapterOptions());
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (double& w : *cmac.mutable_weights()) w = uniform(rng);
  CmacActive active;
  for (int i = 0; i < 100; ++i) {
    const double x = 1.2 * uniform(rng);
    cmac.Active(x, &active);
    double sum = 0.0;
    for (int j = 0; j < active.count; ++j) sum += cmac.weights()[active.index[j]];
    EXPECT_EQ(cmac.Query(x), sum);
  }
}

TEST(CmacTest, OneUpdateWithBetaOneReachesTheTarget) {
  const double kTolerance = 1e-12;
  Cmac cmac(ChapterOptions());
  const double x = 0.3, target = 0.7;
  EXPECT_EQ(cmac.Update(x, target, 1.0), 0.0);  // returns the output before the update
  EXPECT_NEAR(cmac.Query(x), target, kTolerance);
  // Each of the N_l active weights moved by beta (target - O) / N_l.
  CmacActive active;
  cmac.Active(x, &active);
  for (int j = 0; j < active.count; ++j) {
    EXPECT_NEAR(cmac.weights()[active.index[j]], target / 6.0, kTolerance);
  }
  // Half a step (beta 0.5) halves the remaining error.
  const double before = cmac.Update(x, 1.0, 0.5);
  EXPECT_NEAR(before, target, kTolerance);
  EXPECT_NEAR(cmac.Query(x), target + 0.5 * (1.0 - target), kTolerance);
}

TEST(CmacTest, NanInputHasNoDetectorsAndNonFiniteTargetsChangeNothing) {
  Cmac cmac(ChapterOptions());
  cmac.Update(0.1, 1.0, 1.0);
  const std::vector<double> before = cmac.weights();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CmacActive active;
  cmac.Active(nan, &active);
  EXPECT_EQ(active.count, 0);
  EXPECT_TRUE(std::isnan(cmac.Query(nan)));
  EXPECT_TRUE(std::isnan(cmac.Update(nan, 1.0, 1.0)));
  EXPECT_EQ(cmac.Update(0.1, nan, 1.0), cmac.Query(0.1));
  EXPECT_EQ(cmac.Update(0.1, std::numeric_limits<double>::infinity(), 1.0), cmac.Query(0.1));
  EXPECT_EQ(cmac.Update(0.1, 2.0, nan), cmac.Query(0.1));
  EXPECT_EQ(cmac.weights(), before);
}

// Trains on f = sin over [-1, 1] rad with the chapter's structure: seeded uniform samples, beta
// 0.5 falling to 0.02 (LMS with a constant beta keeps jittering by ~beta times the sample noise).
void TrainSine(Cmac* cmac, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const int kEpochs = 60, kSamplesPerEpoch = 5000;
  for (int epoch = 0; epoch < kEpochs; ++epoch) {
    const double beta = std::max(0.02, 0.5 * std::pow(0.9, epoch));
    for (int i = 0; i < kSamplesPerEpoch; ++i) {
      const double x = uniform(rng);
      cmac->Update(x, std::sin(x), beta);
    }
  }
}

TEST(CmacTest, LmsLearnsASineToTheQuantizationLimit) {
  Cmac cmac(ChapterOptions());
  TrainSine(&cmac, 42);
  const double dq = cmac.options().quantum;
  // The output is constant over each quantum, so no training can beat the best constant per
  // quantum, the mean of f over it: with |f'| <= 1 (sin) its error is at most dq / 2 and its RMS
  // at most dq / sqrt(12) (a ramp of slope 1 about its mean). A 1-D CMAC with N_l = width can
  // take any value per quantum, so LMS must come close to that: allow 1.5 times the RMS bound and
  // 3 times the maximum (the slowest LMS modes, patterns alternating from quantum to quantum,
  // still carry some residual after 3e5 samples; measured: RMS 0.0012, max 0.0045 at x_max,
  // whose quantum is the shortest and least sampled).
  const double kRmsBound = 1.5 * dq / std::sqrt(12.0);
  const double kMaxBound = 3.0 * dq / 2.0;
  double sum_sq = 0.0, worst = 0.0;
  const int kTestPoints = 20001;
  for (int i = 0; i < kTestPoints; ++i) {
    const double x = -1.0 + 2.0 * i / (kTestPoints - 1);
    const double error = cmac.Query(x) - std::sin(x);
    sum_sq += error * error;
    worst = std::max(worst, std::abs(error));
  }
  const double rms = std::sqrt(sum_sq / kTestPoints);
  EXPECT_LT(rms, kRmsBound) << "RMS floor " << dq / std::sqrt(12.0);
  EXPECT_LT(worst, kMaxBound);
}

TEST(CmacTest, HashedEqualsDirectWhenTheTableIsLargeEnough) {
  CmacOptions hashed_options = ChapterOptions();
  hashed_options.hash_table_size = 1 << 20;
  hashed_options.hash_seed = 1;
  Cmac direct(ChapterOptions());
  Cmac hashed(hashed_options);
  // 464 detectors in 2^20 slots: this seed happens to place them all apart (the chance of any
  // collision is about 464^2 / 2^21 = 10 %, so other seeds may not).
  ASSERT_EQ(hashed.NumCollisions(), 0);
  TrainSine(&direct, 7);
  TrainSine(&hashed, 7);
  // Without collisions both sum the same weights in the same (layer) order: bit-identical.
  for (double x = -1.2; x <= 1.2; x += 1e-3) ASSERT_EQ(direct.Query(x), hashed.Query(x)) << x;
  EXPECT_EQ(hashed.MemoryBytes(), (1u << 20) * sizeof(double));
}

// Independent count: pairs (layer, detector) per slot from Address, over the whole range.
int BruteForceCollisions(const Cmac& cmac) {
  std::map<int, int> per_slot;
  for (int j = 0; j < cmac.options().layers; ++j) {
    for (int d = 0; d < cmac.NumDetectorsInLayer(j); ++d) ++per_slot[cmac.Address(j, d)];
  }
  int collisions = 0;
  for (const auto& [slot, count] : per_slot) {
    if (count > 1) collisions += count;
  }
  return collisions;
}

TEST(CmacTest, SmallTablesReportCollisions) {
  for (int table : {16, 97, 256, 1024, 1 << 20}) {
    CmacOptions o = ChapterOptions();
    o.hash_table_size = table;
    o.hash_seed = 9;
    const Cmac cmac(o);
    const int n = cmac.NumDetectors();
    EXPECT_EQ(cmac.NumCollisions(), BruteForceCollisions(cmac)) << table;
    // Pigeonholes: n pairs in table < n slots leave at most table - 1 of them alone.
    if (table < n) {
      EXPECT_GE(cmac.NumCollisions(), n - table + 1) << table;
    }
  }
}

TEST(CmacTest, CollisionsDegradeLearning) {
  CmacOptions o = ChapterOptions();
  o.hash_table_size = 64;  // 464 detectors share 64 weights
  Cmac small(o);
  Cmac direct(ChapterOptions());
  TrainSine(&small, 5);
  TrainSine(&direct, 5);
  double small_sq = 0.0, direct_sq = 0.0;
  for (double x = -1.0; x <= 1.0; x += 1e-3) {
    small_sq += std::pow(small.Query(x) - std::sin(x), 2);
    direct_sq += std::pow(direct.Query(x) - std::sin(x), 2);
  }
  EXPECT_GT(small_sq, 10.0 * direct_sq);
}

TEST(CmacTest, RefusesInvalidOptions) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<CmacOptions> bad(9, ChapterOptions());
  bad[0].layers = 0;
  bad[1].layers = kMaxCmacLayers + 1;
  bad[1].width = kMaxCmacLayers + 1;
  bad[2].quantum = 0.0;
  bad[3].quantum = nan;
  bad[4].width = 0;
  bad[5].x_max = bad[5].x_min;
  bad[6].hash_table_size = -1;
  bad[7].layers = 7;       // > width 6
  bad[8].quantum = 1e-12;  // 2e12 quanta
  for (size_t i = 0; i < bad.size(); ++i) {
    std::string error;
    EXPECT_FALSE(bad[i].IsValid(&error)) << i;
    EXPECT_FALSE(error.empty()) << i;
    EXPECT_THROW(Cmac{bad[i]}, std::invalid_argument) << i;
  }
  std::string error;
  EXPECT_TRUE(ChapterOptions().IsValid(&error)) << error;
}

TEST(CmacTest, HotPathsDoNotAllocate) {
  CmacOptions hashed = ChapterOptions();
  hashed.hash_table_size = 1000;
  for (const CmacOptions& o : {ChapterOptions(), hashed}) {
    Cmac cmac(o);
    CmacActive active;
    double sum = 0.0;
    const long before = g_allocations.load();
    for (double x = -1.5; x <= 1.5; x += 1e-3) {
      cmac.Active(x, &active);
      sum += cmac.Query(x) + cmac.Update(x, std::sin(x), 0.5);
    }
    EXPECT_EQ(g_allocations.load(), before);
    EXPECT_TRUE(std::isfinite(sum));
  }
}

}  // namespace
}  // namespace rabbit
