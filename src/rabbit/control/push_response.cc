#include "rabbit/control/push_response.h"

#include <algorithm>
#include <cmath>

#include "rabbit/model/model.h"

namespace rabbit {

double PushResponse::Phase(double t) const {
  if (t_touchdown_ < 0.0 || !(t_ref_step_[leg_] > 0.0)) return -1.0;
  return (t - t_touchdown_) / t_ref_step_[leg_];
}

double PushResponse::Clamp(double v) const {
  return std::clamp(v, -p_.response_fis_max, p_.response_fis_max);
}

double PushResponse::Excess() const {
  const double excess = std::abs(d_) - p_.response_dead;
  return enabled() && armed_ && excess > 0.0 ? std::copysign(excess, d_) : 0.0;
}

double PushResponse::SwingOffset(double t) const {
  if (p_.response_place_gain == 0.0 || !(t_ref_step_[leg_] > 0.0) || t_touchdown_ < 0.0) {
    return 0.0;
  }
  const double dv = Excess() * (d_ < 0.0 ? p_.response_place_back : 1.0);
  if (dv == 0.0) return 0.0;
  const double fade =
      PlacementFade((t - t_touchdown_) / t_ref_step_[leg_], p_.placement_start, p_.placement_full);
  return fade *
         std::clamp(p_.response_place_gain * dv, -p_.response_place_max, p_.response_place_max);
}

double PushResponse::TrunkOffset() const {
  if (p_.response_trunk_gain == 0.0) return 0.0;
  return std::clamp(p_.response_trunk_gain * Excess(), -p_.response_trunk_max,
                    p_.response_trunk_max);
}

void PushResponse::Command(double v_c, bool level) {
  steady_ = v_c == v_c_ && level ? steady_ + 1 : 0;
  v_c_ = v_c;
}

void PushResponse::CatchCheck(double t, double v_orb, double xd) {
  // Latched until the touchdown: a backward disturbance seen in this step and the pendulum
  // falling back, the hip moving backward, past response_catch_from of the step.
  if (p_.response_catch_back > 0.0 && !catching_ && min_d_ < -p_.response_dead && v_orb < 0.0 &&
      xd < 0.0 && (t - t_touchdown_) / t_ref_step_[leg_] >= p_.response_catch_from) {
    catching_ = true;
  }
}

void PushResponse::ReachCheck(double t) {
  // The current bin's running mean against the reference's same bin (past s = 1, a long step,
  // the reference's last bin compared): the reach acts within the step, not a bin late.
  if (p_.response_reach <= 0.0 || reach_step_) return;
  const int bin = StepPhaseBins::Of(Phase(t));
  if (bin < kFirstBin || !bins_.has(bin)) return;
  const int ref_bin = std::min(bin, kLastBin);
  if (!has_ref_[leg_][ref_bin]) return;
  // Near the pendulum's apex a small difference of energy is a large one of v_orb.
  if (std::abs(ref_[leg_][ref_bin]) < p_.response_reach_ref_min) return;
  if (bins_.mean(bin) - ref_[leg_][ref_bin] > p_.response_reach_dead) reach_step_ = true;
}

bool PushResponse::Observe(double t, double v_orb, bool plain, double xd) {
  if (!enabled()) return false;
  const bool armed = plain && steady_ >= kSteadySteps;
  if (armed != armed_) {
    // The walk changes hands (the warm-up's end): the reference is learnt afresh.
    armed_ = armed;
    for (int leg = 0; leg < 2; ++leg) {
      has_ref_[leg].fill(false);
      has_prev_[leg].fill(false);
    }
    disturbed_run_ = 0;
    fis_offset_ = 0.0;
    d_ = 0.0;
    catching_ = false;
    reach_step_ = reach_next_ = false;
  }
  if (!armed) return false;
  int done = -1;
  if (!std::isfinite(v_orb) || !bins_.Add(Phase(t), v_orb, &done)) return false;
  CatchCheck(t, v_orb, xd);
  ReachCheck(t);
  // A bin is compared with the reference's when it is complete (step_phase_bins.h).
  if (done < kFirstBin || done > kLastBin || !has_ref_[leg_][done]) return false;
  d_ = bins_.mean(done) - ref_[leg_][done];
  if (std::abs(d_) <= p_.response_dead) return false;
  step_disturbed_ = true;
  dev_sum_ += d_;
  ++dev_n_;
  min_d_ = std::min(min_d_, d_);
  CatchCheck(t, v_orb, xd);
  // The gait pattern follows the disturbance in the first response_fis_steps disturbed steps.
  if (p_.response_fis_gain == 0.0 || disturbed_run_ >= p_.response_fis_steps) return false;
  const double offset = Clamp(p_.response_fis_gain * d_);
  if (std::abs(offset - fis_offset_) < p_.response_fis_step) return false;
  fis_offset_ = offset;
  return true;
}

double PushResponse::StraightLegAngle(const Observation& obs, double xd, double offset,
                                      double leg) const {
  // The pendulum's height is the hip's above the ground under it.
  const double ground = obs.terrain != nullptr ? obs.terrain->HeightAt(obs.q[kX]) : 0.0;
  const double y = std::max(obs.q[kY] - ground, 1e-3);
  const double dx = xd * std::sqrt(y / p_.gravity) + offset;
  // The hip joint's angle is the thigh's absolute angle (forward positive) plus the trunk's pitch.
  return std::asin(std::clamp(dx / leg, -1.0, 1.0)) + obs.q[kQ0];
}

void PushResponse::CatchReference(const Observation& obs, double leg, Eigen::Vector4d* ref) const {
  *ref << StraightLegAngle(obs, std::min(obs.qd[kX], 0.0), -p_.response_catch_back, leg),
      -kCatchKnee, obs.qd[kQ0], 0.0;
}

double PushResponse::ReachReference(const Observation& obs, double leg) const {
  return StraightLegAngle(obs, std::max(obs.qd[kX], 0.0), 0.0, leg);
}

void PushResponse::ApplyReach(const Observation& obs, int swing, double leg,
                              Eigen::Vector4d* ref) const {
  if (!Reaching() || obs.foot_contact[swing]) return;
  // Raised response_reach of the way toward the capture point's straight leg, never lowered.
  (*ref)[0] += p_.response_reach * std::max(ReachReference(obs, leg) - (*ref)[0], 0.0);
}

void PushResponse::OnTouchdown(double t, double t_step) {
  if (!enabled()) return;
  catching_ = false;
  // The reach lasts the disturbed step and the one after it.
  reach_next_ = reach_step_;
  reach_step_ = false;
  const bool disturbed = step_disturbed_;
  disturbed_run_ = disturbed ? disturbed_run_ + 1 : 0;
  // A step disturbed backward beyond response_rules_dead: the rules walk from this touchdown.
  rules_pending_ = p_.response_rules_steps > 0 && min_d_ < -p_.response_rules_dead;
  // The gait pattern's offset for the coming step: the mean disturbance of this step's disturbed
  // bins, in the first response_fis_steps disturbed steps in a row.
  fis_offset_ = disturbed && dev_n_ > 0 && disturbed_run_ <= p_.response_fis_steps
                    ? Clamp(p_.response_fis_gain * dev_sum_ / dev_n_)
                    : 0.0;
  // The pitch is held at the response_hold_steps touchdowns from the end of a disturbed step.
  if (disturbed) {
    hold_ = p_.response_hold_steps > 0;
    hold_left_ = std::max(p_.response_hold_steps - 1, 0);
  } else {
    hold_ = hold_left_ > 0;
    if (hold_left_ > 0) --hold_left_;
  }
  // The reference: a step of plain walking whose v_orb agrees with the leg's step before it, bin
  // by bin over the bins compared, within the dead zone (a settled walk, at whatever speed).
  if (armed_ && t_touchdown_ >= 0.0 && t_step > 0.0) {
    std::array<double, kPhaseBins> mean{};
    int common = 0;
    bool agrees = true;
    for (int b = 0; b < kPhaseBins; ++b) {
      if (!bins_.has(b)) continue;
      mean[b] = bins_.mean(b);
      if (!has_prev_[leg_][b] || b < kFirstBin || b > kLastBin) continue;
      ++common;
      if (std::abs(mean[b] - prev_[leg_][b]) > p_.response_dead) agrees = false;
    }
    if (agrees && common >= (kLastBin - kFirstBin) / 2) {
      for (int b = 0; b < kPhaseBins; ++b) has_ref_[leg_][b] = bins_.has(b);
      ref_[leg_] = mean;
      disturbed_run_ = 0;
    }
    for (int b = 0; b < kPhaseBins; ++b) has_prev_[leg_][b] = bins_.has(b);
    prev_[leg_] = mean;
  }
  leg_ = 1 - leg_;  // the coming step's
  if (t_ref_step_[leg_] <= 0.0 && t_step > 0.0) t_ref_step_[leg_] = t_step;
  bins_.Clear();
  step_disturbed_ = false;
  min_d_ = 0.0;
  dev_sum_ = 0.0;
  dev_n_ = 0;
  t_touchdown_ = t;
}

}  // namespace rabbit
