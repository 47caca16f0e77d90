// The multi-input CMAC gait pattern (the multi_cmac baseline): trained on the shipped Fuzzy-CMAC
// (the teacher) it reproduces the teacher on the training grid to a stated RMS and on the held-out
// grid within a measured bound of that; a grid coarser than the quanta generalises worse; training
// is deterministic (the same weights twice, and on two threads at once) and the cache trains once;
// the walker's view of it (MultiCmacSwingPattern) holds its context and answers in its own frame.
// Prints the numbers docs/results.md quotes (memory, RMS, training time).
#include "rabbit/learn/multi_cmac_pattern.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <thread>

#include "rabbit/learn/gait_pattern.h"
#include "rabbit/scenario/run.h"

namespace rabbit {
namespace {

constexpr double kDeg = M_PI / 180.0;
const std::string kRoot = std::string(RABBIT_SOURCE_DIR);
const char* const kOutputs[] = {"q_i1 deg", "q_i2 deg", "qd_i1 deg/s", "qd_i2 deg/s"};

std::shared_ptr<const GaitLibrary> ShippedLibrary() {
  static const std::shared_ptr<const GaitLibrary> library =
      LoadGaitLibrary({kRoot + "/gaits/gait_pattern.fll", kRoot + "/gaits/networks",
                       kRoot + "/gaits/reference", kRoot + "/gaits"});
  return library;
}

std::vector<double> Velocities() {
  std::vector<double> v;
  for (const GaitRecord& g : ShippedLibrary()->gaits) v.push_back(g.measured.v_m);
  return v;
}

MultiCmacPatternDomain ShippedDomain(bool thigh_frame) {
  return TeacherDomain(ShippedLibrary()->pattern, Velocities(), thigh_frame, 1.0,
                       MultiCmacPatternOptions{}.v_m_margin);
}

// Coarser quanta (a grid of an eighth of the points) for the tests that train several times.
MultiCmacPatternOptions SmallOptions() {
  MultiCmacPatternOptions o;
  o.e_quantum = o.grid_e_step = 0.5 * kDeg;
  o.v_m_quantum = o.grid_v_m_step = 0.02;
  o.d_obs_quantum = o.grid_d_obs_step = 0.04;
  o.hash_table_size = 1 << 14;
  return o;
}

// The shipped pattern with the default options, trained once for the tests below.
const MultiCmacPattern& DefaultPattern(MultiCmacTrainingSummary* summary = nullptr) {
  static MultiCmacTrainingSummary trained;
  static const MultiCmacPattern pattern = TrainMultiCmacPattern(
      ShippedLibrary()->pattern, ShippedDomain(true), MultiCmacPatternOptions{}, &trained);
  if (summary != nullptr) *summary = trained;
  return pattern;
}

void Print(const char* what, const MultiCmacPatternError& train,
           const MultiCmacPatternError& held) {
  std::printf("%s (%d training points, %d held-out points):\n", what, train.points, held.points);
  for (int o = 0; o < kGaitOutputs; ++o) {
    std::printf("  %-12s training RMS %7.3f max %7.2f | held-out RMS %7.3f max %7.2f\n",
                kOutputs[o], train.rms[o] / kDeg, train.max[o] / kDeg, held.rms[o] / kDeg,
                held.max[o] / kDeg);
  }
}

TEST(MultiCmacPatternTest, ReproducesTheTeacherOnTheTrainingAndHeldOutGrids) {
  MultiCmacTrainingSummary summary;
  const MultiCmacPattern& pattern = DefaultPattern(&summary);
  const FuzzyCmac& teacher = ShippedLibrary()->pattern;
  const MultiCmacPatternError train = CompareWithTeacher(pattern, teacher, false);
  const MultiCmacPatternError held = CompareWithTeacher(pattern, teacher, true);
  std::printf("%s\n", summary.BriefReport().c_str());
  Print("default options, thigh frame", train, held);
  // The training summary's RMS (from the least-squares residuals) is the comparison's.
  const double kSame = 1e-9;
  EXPECT_EQ(train.points, summary.points);
  for (int o = 0; o < kGaitOutputs; ++o) {
    EXPECT_NEAR(train.rms[o], summary.rms[o], kSame * summary.rms[o]) << kOutputs[o];
  }
  // Stated tolerances on the training grid (measured on the eight shipped gaits: 3.22 and 4.24
  // deg, 33.8 and 49.3 deg/s; on the earlier five, 2.45, 3.38, 14.0, 23.8): hashing the detectors
  // into 2^16 slots and the three-input tiles cost degrees, where the SISO CMACs reach their
  // gaits to well under a degree.
  const Eigen::Vector4d kTrainRms(4.0 * kDeg, 5.0 * kDeg, 40.0 * kDeg, 60.0 * kDeg);
  // Between the training points (the held-out grid, cell midpoints) the error grows by at most
  // this factor (measured: 1.06 to 1.10).
  const double kHeldOutGrowth = 1.2;
  for (int o = 0; o < kGaitOutputs; ++o) {
    EXPECT_LT(train.rms[o], kTrainRms[o]) << kOutputs[o];
    EXPECT_LT(held.rms[o], kHeldOutGrowth * train.rms[o]) << kOutputs[o];
  }
  EXPECT_GT(summary.collisions, 0);  // hashed: some detectors share slots
  EXPECT_LT(summary.iterations, MultiCmacPatternOptions{}.max_iterations);  // converged
}

TEST(MultiCmacPatternTest, NeedsFarMoreMemoryThanTheFuzzyCmac) {
  const MultiCmacPattern& pattern = DefaultPattern();
  const std::size_t fuzzy = ShippedLibrary()->pattern.MemoryBytes();
  EXPECT_EQ(pattern.MemoryBytes(), 4u * (1u << 16) * sizeof(double));
  std::printf(
      "memory: four multi-input CMACs %zu bytes; the Fuzzy-CMAC's 20 SISO CMACs %zu "
      "bytes (%.0fx)\n",
      pattern.MemoryBytes(), fuzzy,
      static_cast<double>(pattern.MemoryBytes()) / static_cast<double>(fuzzy));
  EXPECT_GT(pattern.MemoryBytes(), 20 * fuzzy);  // eight gaits' 32 SISO CMACs: 27x
}

// The chapter's second argument: a multi-input CMAC must see the whole input space. Trained on
// every other quantum, the cells in between are filled by local generalisation only, and the
// held-out error is several times the training error.
TEST(MultiCmacPatternTest, ACoarserGridGeneralisesWorse) {
  MultiCmacPatternOptions o;
  o.grid_e_step = 2 * o.e_quantum;
  o.grid_v_m_step = 2 * o.v_m_quantum;
  o.grid_d_obs_step = 2 * o.d_obs_quantum;
  const FuzzyCmac& teacher = ShippedLibrary()->pattern;
  const MultiCmacPattern coarse = TrainMultiCmacPattern(teacher, ShippedDomain(true), o);
  const MultiCmacPatternError train = CompareWithTeacher(coarse, teacher, false);
  const MultiCmacPatternError held = CompareWithTeacher(coarse, teacher, true);
  Print("training grid of every other quantum", train, held);
  const MultiCmacPatternError full = CompareWithTeacher(DefaultPattern(), teacher, true);
  EXPECT_GT(held.rms[0], full.rms[0]);  // held-out worse than with a point in every cell
  EXPECT_GT(held.rms[0], 1.5 * train.rms[0]);
}

TEST(MultiCmacPatternTest, TheChaptersFrameTrainsToo) {
  const FuzzyCmac& teacher = ShippedLibrary()->pattern;
  const MultiCmacPatternDomain domain = ShippedDomain(false);
  EXPECT_EQ(domain.e_min, teacher.cmac_options().x_min);
  EXPECT_EQ(domain.e_max, teacher.cmac_options().x_max);
  const MultiCmacPattern pattern = TrainMultiCmacPattern(teacher, domain, SmallOptions());
  const MultiCmacPatternError train = CompareWithTeacher(pattern, teacher, false);
  const MultiCmacPatternError held = CompareWithTeacher(pattern, teacher, true);
  Print("chapter's frame, coarser quanta", train, held);
  const double kMaxRms = 5.0 * kDeg;
  EXPECT_LT(train.rms[0], kMaxRms);
  EXPECT_LT(held.rms[0], kMaxRms);
  // Queried in the teacher's frame: at a grid point of d_obs = 1 and V_M of gait 3.
  FuzzyCmac t = teacher;
  const double v_m = Velocities()[2];
  t.SetContext(v_m, 1.0);
  const double e = 0.1;
  EXPECT_NEAR(pattern.Query(e, v_m, 1.0)[0], t.Query(e)[0], 10 * kDeg);
}

TEST(MultiCmacPatternTest, TheThighFrameDomainCoversEveryGaitsRange) {
  const FuzzyCmac& teacher = ShippedLibrary()->pattern;
  const MultiCmacPatternDomain d = ShippedDomain(true);
  for (double q0 : teacher.trunk_pitches()) {
    EXPECT_LE(d.e_min, teacher.cmac_options().x_min - q0);
    EXPECT_GE(d.e_max, teacher.cmac_options().x_max - q0);
  }
  const std::vector<double> v = Velocities();
  EXPECT_DOUBLE_EQ(d.v_m_min, *std::min_element(v.begin(), v.end()) - 0.1);
  EXPECT_DOUBLE_EQ(d.v_m_max, *std::max_element(v.begin(), v.end()) + 0.1);
  EXPECT_EQ(d.d_obs_max, 1.0);
  FuzzyCmac no_pitches(teacher.fis(), LoadGaitNetworks(kRoot + "/gaits/networks", nullptr));
  EXPECT_THROW(TeacherDomain(no_pitches, v, true, 1.0, 0.1), std::invalid_argument);
  EXPECT_THROW(TeacherDomain(teacher, {}, true, 1.0, 0.1), std::invalid_argument);
}

TEST(MultiCmacPatternTest, TrainingIsDeterministicOnAnyThread) {
  const FuzzyCmac& teacher = ShippedLibrary()->pattern;
  const MultiCmacPatternDomain domain = ShippedDomain(true);
  const MultiCmacPatternOptions o = SmallOptions();
  const MultiCmacPattern first = TrainMultiCmacPattern(teacher, domain, o);
  const MultiCmacPattern second = TrainMultiCmacPattern(teacher, domain, o);
  std::vector<MultiCmacPattern> threaded(2, MultiCmacPattern(domain, o));
  std::thread a([&] { threaded[0] = TrainMultiCmacPattern(teacher, domain, o); });
  std::thread b([&] { threaded[1] = TrainMultiCmacPattern(teacher, domain, o); });
  a.join();
  b.join();
  for (int k = 0; k < kGaitOutputs; ++k) {
    const std::vector<double>& w = first.cmacs()[k].weights();
    EXPECT_EQ(w, second.cmacs()[k].weights()) << k;  // bit for bit
    EXPECT_EQ(w, threaded[0].cmacs()[k].weights()) << k;
    EXPECT_EQ(w, threaded[1].cmacs()[k].weights()) << k;
  }
}

TEST(MultiCmacPatternTest, TheCacheTrainsEachSettingOnce) {
  const FuzzyCmac& teacher = ShippedLibrary()->pattern;
  const MultiCmacPatternDomain domain = ShippedDomain(true);
  MultiCmacPatternCache cache;
  std::shared_ptr<const MultiCmacPattern> a, b;
  std::thread one([&] { a = cache.Get(teacher, domain, SmallOptions()); });
  std::thread two([&] { b = cache.Get(teacher, domain, SmallOptions()); });
  one.join();
  two.join();
  EXPECT_EQ(a, b);
  EXPECT_EQ(cache.trainings(), 1);
  MultiCmacTrainingSummary summary;
  EXPECT_EQ(cache.Get(teacher, domain, SmallOptions(), &summary), a);
  EXPECT_GT(summary.points, 0);  // the first training's summary
  EXPECT_EQ(cache.trainings(), 1);
  // Another option, another fuzzy system: new trainings.
  MultiCmacPatternOptions other = SmallOptions();
  other.ridge = 2e-3;
  EXPECT_NE(cache.Get(teacher, domain, other), a);
  TsFis fis = teacher.fis();
  fis.inputs[1].sets[3].membership.b += 1e-9;
  EXPECT_NE(cache.Get(teacher.WithFis(fis), domain, SmallOptions()), a);
  EXPECT_EQ(cache.trainings(), 3);
  // Only the last kMaxPatterns settings are kept.
  for (size_t k = 0; k < MultiCmacPatternCache::kMaxPatterns; ++k) {
    MultiCmacPatternOptions o = SmallOptions();
    o.hash_seed = 100 + k;
    o.grid_e_step = 2 * o.e_quantum;  // quicker
    cache.Get(teacher, domain, o);
  }
  EXPECT_EQ(cache.trainings(), 3 + static_cast<int>(MultiCmacPatternCache::kMaxPatterns));
  cache.Get(teacher, domain, SmallOptions());  // trained again
  EXPECT_EQ(cache.trainings(), 4 + static_cast<int>(MultiCmacPatternCache::kMaxPatterns));
}

TEST(MultiCmacPatternTest, TheWalkersViewHoldsItsContextAndItsFrame) {
  const FuzzyCmac& teacher = ShippedLibrary()->pattern;
  auto pattern = std::make_shared<const MultiCmacPattern>(
      TrainMultiCmacPattern(teacher, ShippedDomain(true), SmallOptions()));
  MultiCmacSwingPattern view(pattern);
  EXPECT_TRUE(view.Supports(true));
  EXPECT_FALSE(view.Supports(false));
  EXPECT_THROW(view.Query(0.1), std::logic_error);
  EXPECT_TRUE(std::isnan(view.QueryThigh(0.1)[0]));  // no context yet
  ASSERT_TRUE(view.SetContext(0.6, 0.3));
  EXPECT_EQ(view.QueryThigh(0.1), pattern->Query(0.1, 0.6, 0.3));
  EXPECT_FALSE(view.SetContext(std::nan(""), 0.3));  // kept
  EXPECT_FALSE(view.SetContext(0.6, std::nan("")));
  EXPECT_EQ(view.QueryThigh(0.1), pattern->Query(0.1, 0.6, 0.3));
  EXPECT_TRUE(view.GaitWeights().empty());
  EXPECT_TRUE(view.RuleActivations().empty());
  EXPECT_EQ(view.MemoryBytes(), pattern->MemoryBytes());
  EXPECT_THROW(MultiCmacSwingPattern(nullptr), std::invalid_argument);
}

TEST(MultiCmacPatternTest, InvalidSettingsAreRefused) {
  const MultiCmacPatternDomain domain = ShippedDomain(true);
  auto refused = [&](void (*change)(MultiCmacPatternOptions*), const std::string& fragment) {
    MultiCmacPatternOptions o;
    change(&o);
    std::string error;
    EXPECT_FALSE(o.IsValid(&error)) << fragment;
    EXPECT_NE(error.find(fragment), std::string::npos) << error;
    EXPECT_THROW(MultiCmacPattern(domain, o), std::invalid_argument) << fragment;
  };
  refused([](MultiCmacPatternOptions* o) { o->layers = 0; }, "layers");
  refused([](MultiCmacPatternOptions* o) { o->v_m_width = 5; }, "v_m_width");
  refused([](MultiCmacPatternOptions* o) { o->e_quantum = -1; }, "e_quantum");
  refused([](MultiCmacPatternOptions* o) { o->grid_d_obs_step = 0; }, "grid_d_obs_step");
  refused([](MultiCmacPatternOptions* o) { o->ridge = std::nan(""); }, "ridge");
  refused([](MultiCmacPatternOptions* o) { o->hash_table_size = 0; }, "hash_table_size");
  refused([](MultiCmacPatternOptions* o) { o->tolerance = 1; }, "tolerance");
  refused([](MultiCmacPatternOptions* o) { o->v_m_margin = -0.1; }, "v_m_margin");
  MultiCmacPatternOptions fine;
  fine.grid_e_step = fine.grid_v_m_step = fine.grid_d_obs_step = 1e-4;  // 10^10 points
  EXPECT_THROW(TrainMultiCmacPattern(ShippedLibrary()->pattern, domain, fine),
               std::invalid_argument);
  MultiCmacPatternDomain empty = domain;
  empty.v_m_max = empty.v_m_min;
  EXPECT_THROW(MultiCmacPattern(empty, MultiCmacPatternOptions{}), std::invalid_argument);
}

}  // namespace
}  // namespace rabbit
