#include "rabbit/control/approach_watch.h"

#include <cmath>

namespace rabbit {

double ApproachWatch::Phase(double t) const {
  if (t_touchdown_ < 0.0 || !(t_ref_[leg_] > 0.0)) return -1.0;
  return (t - t_touchdown_) / t_ref_[leg_];
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
  int done = -1;
  if (!bins_.Add(Phase(t), v_orb, &done)) return;
  // A bin is compared with the reference's when it is complete (step_phase_bins.h).
  if (unjudged_ > 0 || done < kFirstBin || done > kLastBin || !has_ref_[leg_][done]) return;
  const double d = bins_.mean(done) - ref_[leg_][done];
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
        has_ref_[leg_][b] = bins_.has(b);
        if (bins_.has(b)) ref_[leg_][b] = bins_.mean(b);
      }
      disturbed_[leg_] = 0;
    }
  }
  if (unjudged_ > 0) --unjudged_;
  leg_ = 1 - leg_;
  bins_.Clear();
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
