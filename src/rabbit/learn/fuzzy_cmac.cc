#include "rabbit/learn/fuzzy_cmac.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rabbit {

FuzzyCmac::FuzzyCmac(TsFis fis, std::vector<GaitCmacs> networks)
    : fis_(std::move(fis)), networks_(std::move(networks)) {
  std::string error;
  if (!fis_.IsValid(&error)) throw std::invalid_argument("fuzzy system: " + error);
  if (fis_.inputs.size() != 2) throw std::invalid_argument("the gait pattern takes V_M and d_obs");
  if (fis_.inputs[0].name == "d_obs" && fis_.inputs[1].name == "V_M") {
    v_m_input_ = 1;
    d_obs_input_ = 0;
  } else if (fis_.inputs[0].name != "V_M" || fis_.inputs[1].name != "d_obs") {
    throw std::invalid_argument("the gait pattern's inputs must be named V_M and d_obs");
  }
  if (networks_.empty()) throw std::invalid_argument("no reference gait networks");
  const CmacOptions& first = networks_[0].at(0).options();
  for (const GaitCmacs& gait : networks_) {
    if (gait.size() != kGaitOutputs) throw std::invalid_argument("each gait needs 4 CMACs");
    for (const Cmac& c : gait) {
      const CmacOptions& o = c.options();
      if (o.layers != first.layers || o.quantum != first.quantum || o.width != first.width ||
          o.x_min != first.x_min || o.x_max != first.x_max ||
          o.hash_table_size != first.hash_table_size || o.hash_seed != first.hash_seed) {
        throw std::invalid_argument("all CMACs of the gait pattern must share one structure");
      }
    }
  }
  for (double v : fis_.output_values) {
    const double k = std::round(v);
    if (k != v || k < 1 || k > static_cast<double>(networks_.size())) {
      throw std::invalid_argument("FIS output term value " + std::to_string(v) +
                                  " names no reference gait (1.." +
                                  std::to_string(networks_.size()) + ")");
    }
  }
  weights_.assign(networks_.size(), 0.0);
  weights_[0] = 1.0;
  x_.resize(2);
}

bool FuzzyCmac::SetContext(double v_m, double d_obs) {
  x_[v_m_input_] = v_m;
  x_[d_obs_input_] = d_obs;
  fis_.Evaluate(x_, &result_);
  if (!result_.fired) return false;
  std::fill(weights_.begin(), weights_.end(), 0.0);
  for (size_t r = 0; r < fis_.rules.size(); ++r) {
    const int k = static_cast<int>(fis_.output_values[fis_.rules[r].consequent]) - 1;
    weights_[k] += result_.activation[r];
  }
  return true;
}

void FuzzyCmac::KeepStrongestRuleOnly() {
  if (!result_.fired) return;
  size_t best = 0;
  for (size_t r = 1; r < fis_.rules.size(); ++r) {
    if (result_.activation[r] > result_.activation[best]) best = r;
  }
  std::fill(weights_.begin(), weights_.end(), 0.0);
  weights_[static_cast<size_t>(fis_.output_values[fis_.rules[best].consequent]) - 1] = 1.0;
}

void FuzzyCmac::SetGaitWeights(const std::vector<double>& weights) {
  if (weights.size() != weights_.size()) {
    throw std::invalid_argument("SetGaitWeights: need one weight per reference gait");
  }
  for (double w : weights) {
    if (!(std::isfinite(w) && w >= 0.0)) {
      throw std::invalid_argument("SetGaitWeights: weights must be finite and >= 0");
    }
  }
  weights_ = weights;
}

Eigen::Vector4d FuzzyCmac::Query(double e) const {
  CmacActive active;
  networks_[0][0].Active(e, &active);  // shared structure: one active set for all
  if (active.count == 0) return Eigen::Vector4d::Constant(std::nan(""));  // e is NaN
  Eigen::Vector4d y = Eigen::Vector4d::Zero();
  for (size_t k = 0; k < networks_.size(); ++k) {
    const double w = weights_[k];
    if (w == 0.0) continue;
    for (int o = 0; o < kGaitOutputs; ++o) {
      const std::vector<double>& weights = networks_[k][o].weights();
      double sum = 0.0;
      for (int i = 0; i < active.count; ++i) sum += weights[active.index[i]];
      y[o] += w * sum;
    }
  }
  return y;
}

FuzzyCmac FuzzyCmac::WithFis(TsFis fis) const {
  FuzzyCmac copy(std::move(fis), networks_);
  copy.pitches_ = pitches_;
  return copy;
}

void FuzzyCmac::SetTrunkPitches(std::vector<double> q0) {
  if (q0.size() != networks_.size()) {
    throw std::invalid_argument("need one trunk pitch per reference gait");
  }
  for (double v : q0) {
    if (!std::isfinite(v)) throw std::invalid_argument("trunk pitches must be finite");
  }
  pitches_ = std::move(q0);
}

Eigen::Vector4d FuzzyCmac::QueryThigh(double th_st) const {
  if (pitches_.empty()) throw std::logic_error("FuzzyCmac::QueryThigh before SetTrunkPitches");
  Eigen::Vector4d y = Eigen::Vector4d::Zero();
  CmacActive active;
  for (size_t k = 0; k < networks_.size(); ++k) {
    const double w = weights_[k];
    if (w == 0.0) continue;
    networks_[k][0].Active(th_st + pitches_[k], &active);
    if (active.count == 0) return Eigen::Vector4d::Constant(std::nan(""));
    for (int o = 0; o < kGaitOutputs; ++o) {
      const std::vector<double>& weights = networks_[k][o].weights();
      double sum = 0.0;
      for (int i = 0; i < active.count; ++i) sum += weights[active.index[i]];
      y[o] += w * (o == 0 ? sum - pitches_[k] : sum);
    }
  }
  return y;
}

std::size_t FuzzyCmac::MemoryBytes() const {
  std::size_t bytes = 0;
  for (const GaitCmacs& gait : networks_) {
    for (const Cmac& c : gait) bytes += c.MemoryBytes();
  }
  return bytes;
}

}  // namespace rabbit
