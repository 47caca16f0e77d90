#include "rabbit/control/approach_watch.h"

#include <cmath>

namespace rabbit {

int ApproachWatch::Bin(double t) const {
  if (t_touchdown_ < 0.0 || !(t_ref_[leg_] > 0.0)) return -1;
  const double s = (t - t_touchdown_) / t_ref_[leg_];
  if (!(s >= 0.0)) return -1;
  const int bin = static_cast<int>(s / 1.5 * kPhaseBins);
  return bin < kPhaseBins ? bin : -1;
}

void ApproachWatch::Observe(double t, double v_orb, bool own) {
  if (!enabled()) return;
  if (own != own_) {
    own_ = own;
    for (int leg = 0; leg < 2; ++leg) {
      has_ref_[leg].fill(false);
      t_ref_[leg] = 0.0;
      disturbed_[leg] = 0;
    }
  }
  if (!own || !std::isfinite(v_orb)) return;
  const int bin = Bin(t);
  if (bin < 0) return;
  sum_[bin] += v_orb;
  ++samples_[bin];
  // A bin is compared with the reference's when it is complete (v_orb varies within a bin).
  const int done = bin_;
  bin_ = bin;
  if (unjudged_ > 0 || done < kFirstBin || done > kLastBin || done == bin ||
      samples_[done] == 0 || !has_ref_[leg_][done]) {
    return;
  }
  const double d = sum_[done] / samples_[done] - ref_[leg_][done];
  if (std::abs(d) > dead_) {
    disturbed_step_ = true;
    if (std::abs(d) > std::abs(extreme_)) extreme_ = d;
  }
}

void ApproachWatch::OnTouchdown(double t, double t_step) {
  if (!enabled()) return;
  last_disturbed_ = disturbed_step_;
  last_d_ = extreme_;
  if (own_ && t_touchdown_ >= 0.0 && t_step > 0.0) {
    disturbed_[leg_] = disturbed_step_ ? disturbed_[leg_] + 1 : 0;
    if (!(t_ref_[leg_] > 0.0)) {
      t_ref_[leg_] = t_step;  // the leg's timebase: its next step is sampled on it
    } else if (!disturbed_step_ || disturbed_[leg_] > kMaxDisturbed || unjudged_ > 0) {
      for (int b = 0; b < kPhaseBins; ++b) {
        has_ref_[leg_][b] = samples_[b] > 0;
        if (samples_[b] > 0) ref_[leg_][b] = sum_[b] / samples_[b];
      }
      disturbed_[leg_] = 0;
    }
  }
  if (unjudged_ > 0) --unjudged_;
  leg_ = 1 - leg_;
  sum_.fill(0.0);
  samples_.fill(0);
  bin_ = -1;
  extreme_ = 0.0;
  disturbed_step_ = false;
  t_touchdown_ = t;
}

void ApproachWatch::Command(double v_c, bool level) {
  if (!enabled()) return;
  if (v_c != v_c_ || !level) unjudged_ = kSettleSteps;
  v_c_ = v_c;
}

}  // namespace rabbit
