// One step's samples in phase bins: the pendulum's hip speed v_orb as the push recovery, the push
// response and the approach watch measure it (push_recovery.h, push_response.h,
// approach_watch.h). The step's phase s = (t - t_touchdown) / T, T a reference step's duration,
// runs over [0, 1.5) in kBins equal bins (a step may last longer than its reference). A bin is
// complete once a sample falls in another bin: v_orb varies too much within a bin (impacts) for
// single samples to be compared.
#ifndef RABBIT_CONTROL_STEP_PHASE_BINS_H_
#define RABBIT_CONTROL_STEP_PHASE_BINS_H_

#include <array>

namespace rabbit {

class StepPhaseBins {
 public:
  static constexpr int kBins = 15;

  // The bin of phase s (-1: outside [0, 1.5), or not a number).
  static int Of(double s) {
    if (!(s >= 0.0)) return -1;
    const int bin = static_cast<int>(s / 1.5 * kBins);
    return bin < kBins ? bin : -1;
  }

  // Adds v in the bin of phase s; false (nothing added) when s is outside the bins. *completed
  // (when given): the bin the step's previous sample fell in, if this one falls in another (that
  // bin is complete), else -1.
  bool Add(double s, double v, int* completed = nullptr) {
    const int bin = Of(s);
    if (bin < 0) return false;
    sum_[bin] += v;
    ++samples_[bin];
    if (completed != nullptr) *completed = last_ >= 0 && last_ != bin ? last_ : -1;
    last_ = bin;
    return true;
  }

  bool has(int bin) const { return samples_[bin] > 0; }
  // The mean of the bin's samples (has(bin) must hold).
  double mean(int bin) const { return sum_[bin] / samples_[bin]; }

  // A new step: no samples.
  void Clear() {
    sum_.fill(0.0);
    samples_.fill(0);
    last_ = -1;
  }

 private:
  std::array<double, kBins> sum_{};
  std::array<int, kBins> samples_{};
  int last_ = -1;  // the bin of the step's last sample (-1: none yet)
};

}  // namespace rabbit

#endif  // RABBIT_CONTROL_STEP_PHASE_BINS_H_
