// What the walker (rabbit/control/fuzzy_cmac_walker.h) asks of a gait pattern: the swing leg's
// four references [q_i1_d, q_i2_d, qd_i1_d, qd_i2_d] as a function of the stance leg's angle, in a
// context X = [V_M, d_obs] set once per step (at touchdown) and held during it.
//   Query(e)            the chapter's frame: e = q_st1 (stance hip, relative to the trunk), the
//                       swing hip relative to the trunk (eq. 13);
//   QueryThigh(th_st)   the thigh frame (docs/design/gait-pattern.md): the stance thigh's absolute
//   angle
//                       in, the swing thigh's absolute angle (and its rate) out.
// Two implementations: FuzzyCmacSwingPattern (below: the chapter's Fuzzy-CMAC, optionally rounded
// to nearest-gait switching) and MultiCmacSwingPattern (rabbit/learn/multi_cmac_pattern.h: the
// multi-input CMAC baseline). A pattern holds its context, so each walker owns its own.
#ifndef RABBIT_LEARN_SWING_PATTERN_H_
#define RABBIT_LEARN_SWING_PATTERN_H_

#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

#include "rabbit/learn/fuzzy_cmac.h"

namespace rabbit {

class SwingPattern {
 public:
  virtual ~SwingPattern() = default;

  // Sets the context for the coming step. Returns false (keeping the previous context) when the
  // pattern cannot use it (no fuzzy rule fires; a non-finite input).
  virtual bool SetContext(double v_m, double d_obs) = 0;
  // Sets the per-gait weights directly, in place of the context's (the step planner's); false
  // when the pattern has no per-gait weights (then nothing changes).
  virtual bool SetGaitWeights(const std::vector<double>& weights) = 0;
  // Whether Query (thigh_frame false) or QueryThigh (true) may be called.
  virtual bool Supports(bool thigh_frame) const = 0;
  virtual Eigen::Vector4d Query(double e) const = 0;
  virtual Eigen::Vector4d QueryThigh(double th_st) const = 0;

  // What the context selected, for the step records: per reference gait (empty when the pattern
  // has no per-gait weights) and per fuzzy rule (empty when it has no rules).
  virtual const std::vector<double>& GaitWeights() const = 0;
  virtual const std::vector<double>& RuleActivations() const = 0;
  // The memory of the learnt weights, bytes.
  virtual std::size_t MemoryBytes() const = 0;
};

// The Fuzzy-CMAC (eqs. 12-13). With nearest_gait, each SetContext is followed by
// FuzzyCmac::KeepStrongestRuleOnly (nearest-gait switching, a baseline).
class FuzzyCmacSwingPattern final : public SwingPattern {
 public:
  FuzzyCmacSwingPattern(FuzzyCmac pattern, bool nearest_gait)
      : pattern_(std::move(pattern)), nearest_gait_(nearest_gait) {}

  bool SetContext(double v_m, double d_obs) override {
    const bool fired = pattern_.SetContext(v_m, d_obs);  // no rule firing keeps the weights
    if (nearest_gait_) pattern_.KeepStrongestRuleOnly();
    return fired;
  }
  // Nearest-gait switching keeps only the largest weight (the first on a tie), as 1.
  bool SetGaitWeights(const std::vector<double>& weights) override {
    if (!nearest_gait_) {
      pattern_.SetGaitWeights(weights);
      return true;
    }
    std::vector<double> w(weights.size(), 0.0);
    if (!w.empty()) w[std::max_element(weights.begin(), weights.end()) - weights.begin()] = 1.0;
    pattern_.SetGaitWeights(w);
    return true;
  }
  bool Supports(bool thigh_frame) const override {
    return !thigh_frame || !pattern_.trunk_pitches().empty();
  }
  Eigen::Vector4d Query(double e) const override { return pattern_.Query(e); }
  Eigen::Vector4d QueryThigh(double th_st) const override { return pattern_.QueryThigh(th_st); }
  const std::vector<double>& GaitWeights() const override { return pattern_.gait_weights(); }
  const std::vector<double>& RuleActivations() const override {
    return pattern_.rule_activations().activation;
  }
  std::size_t MemoryBytes() const override { return pattern_.MemoryBytes(); }

  const FuzzyCmac& fuzzy_cmac() const { return pattern_; }

 private:
  FuzzyCmac pattern_;
  bool nearest_gait_;
};

}  // namespace rabbit

#endif  // RABBIT_LEARN_SWING_PATTERN_H_
