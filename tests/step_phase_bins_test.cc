// The phase bins of a step's samples (step_phase_bins.h): the bin of a phase against its closed
// form at the edges of [0, 1.5), a bin's mean, a bin completed only when a sample falls in
// another, and a new step with no samples.
#include "rabbit/control/step_phase_bins.h"

#include <gtest/gtest.h>

#include <cmath>

namespace rabbit {
namespace {

TEST(StepPhaseBinsTest, BinOfAPhase) {
  // kBins = 15 bins over [0, 1.5): bin b holds s in [b / 10, (b + 1) / 10).
  EXPECT_EQ(StepPhaseBins::Of(0.0), 0);
  EXPECT_EQ(StepPhaseBins::Of(0.0999), 0);
  EXPECT_EQ(StepPhaseBins::Of(0.2), 2);
  EXPECT_EQ(StepPhaseBins::Of(0.95), 9);
  EXPECT_EQ(StepPhaseBins::Of(1.4999), 14);
  EXPECT_EQ(StepPhaseBins::Of(1.5), -1);
  EXPECT_EQ(StepPhaseBins::Of(-1e-9), -1);
  EXPECT_EQ(StepPhaseBins::Of(std::nan("")), -1);
}

TEST(StepPhaseBinsTest, ABinIsCompleteWhenASampleFallsInAnother) {
  StepPhaseBins bins;
  int done = 7;
  ASSERT_TRUE(bins.Add(0.21, 1.0, &done));
  EXPECT_EQ(done, -1);  // the step's first sample completes nothing
  ASSERT_TRUE(bins.Add(0.25, 2.0, &done));
  EXPECT_EQ(done, -1);  // the same bin
  ASSERT_TRUE(bins.Add(0.31, 5.0, &done));
  EXPECT_EQ(done, 2);  // bin 2 is complete
  EXPECT_TRUE(bins.has(2));
  EXPECT_DOUBLE_EQ(bins.mean(2), 1.5);
  EXPECT_FALSE(bins.has(4));
  // Outside the bins nothing is added and nothing is completed.
  done = 7;
  EXPECT_FALSE(bins.Add(1.6, 9.0, &done));
  EXPECT_EQ(done, 7);
  EXPECT_DOUBLE_EQ(bins.mean(3), 5.0);
  // A skipped bin: the sample in bin 6 completes bin 3, and bin 4 stays empty.
  ASSERT_TRUE(bins.Add(0.65, 1.0, &done));
  EXPECT_EQ(done, 3);
  EXPECT_FALSE(bins.has(4));
}

TEST(StepPhaseBinsTest, ANewStepHasNoSamples) {
  StepPhaseBins bins;
  int done = -1;
  bins.Add(0.21, 1.0, &done);
  bins.Add(0.31, 1.0, &done);
  bins.Clear();
  for (int b = 0; b < StepPhaseBins::kBins; ++b) EXPECT_FALSE(bins.has(b)) << b;
  // The last step's last bin is not completed by the new step's first sample.
  bins.Add(0.05, 2.0, &done);
  EXPECT_EQ(done, -1);
  EXPECT_DOUBLE_EQ(bins.mean(0), 2.0);
}

}  // namespace
}  // namespace rabbit
