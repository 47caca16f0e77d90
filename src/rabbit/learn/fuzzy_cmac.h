// The Fuzzy-CMAC gait pattern (chapter sections 3.3 and 5.1, eqs. 12-13): N_r reference gaits,
// each learnt by four SISO CMACs O_1..O_4 = q_i1, q_i2, qd_i1, qd_i2 of the swing leg as functions
// of e (the stance hip angle), merged by a zero-order TS fuzzy system over X = [V_M, d_obs]:
//   Y(e) = sum_rules u_bar_r O^{k(r)}(e) = sum_k w_k O^k(e),  w_k = sum of u_bar over rules -> k.
// The FIS is evaluated once per step (SetContext) and held; Query(e) runs every control period.
#ifndef RABBIT_LEARN_FUZZY_CMAC_H_
#define RABBIT_LEARN_FUZZY_CMAC_H_

#include <Eigen/Core>
#include <array>
#include <vector>

#include "rabbit/learn/cmac.h"
#include "rabbit/learn/ts_fis.h"

namespace rabbit {

constexpr int kGaitOutputs = 4;       // q_i1, q_i2, qd_i1, qd_i2
using GaitCmacs = std::vector<Cmac>;  // kGaitOutputs CMACs of one reference gait

class FuzzyCmac {
 public:
  // The FIS has the inputs V_M and d_obs (by name, in any order). networks[k] serves the FIS
  // output value k + 1 (O^{k+1}); all CMACs must share one structure
  // (CmacOptions) so that the active detectors are computed once per query. Throws
  // std::invalid_argument when the pieces do not fit together.
  FuzzyCmac(TsFis fis, std::vector<GaitCmacs> networks);

  // Evaluates the FIS at X = [v_m, d_obs] and keeps the per-gait weights w_k. Returns false (and
  // keeps the previous weights) when no rule fires.
  bool SetContext(double v_m, double d_obs);
  // Nearest-gait switching (a baseline): the weights become 1 for the gait of the strongest rule
  // of the last SetContext and 0 for the others (the first such rule on a tie).
  void KeepStrongestRuleOnly();
  // Sets the per-gait weights directly (e.g. from another fuzzy system, the step planner's):
  // one finite weight >= 0 per gait (throws std::invalid_argument otherwise); kept until the
  // next SetContext or SetGaitWeights.
  void SetGaitWeights(const std::vector<double>& weights);
  // The four swing-leg references at e with the current weights (eq. 13).
  Eigen::Vector4d Query(double e) const;

  // The thigh frame (an addition to the chapter, see docs/design/gait-pattern.md): gait k was
  // learnt with the trunk held at pitch q0_k, so in terms of absolute thigh angles (th = q_i1 - q0)
  // its swing thigh is O^k_1(th_st + q0_k) - q0_k while knee angles and rates are unchanged. Given
  // every gait's pitch, QueryThigh(th_st) blends the gaits in that frame: its first output is the
  // swing thigh's absolute angle. Throws std::invalid_argument unless one finite pitch per gait.
  void SetTrunkPitches(std::vector<double> q0);
  Eigen::Vector4d QueryThigh(double th_st) const;
  const std::vector<double>& trunk_pitches() const { return pitches_; }

  const TsFis& fis() const { return fis_; }
  // The structure every CMAC of the pattern shares (input range, quantum, layers).
  const CmacOptions& cmac_options() const { return networks_[0][0].options(); }
  // The same networks and trunk pitches with another fuzzy system (e.g. a scenario's membership
  // sets). Throws std::invalid_argument as the constructor does.
  FuzzyCmac WithFis(TsFis fis) const;
  const TsFis::Result& rule_activations() const { return result_; }
  const std::vector<double>& gait_weights() const { return weights_; }
  std::size_t MemoryBytes() const;

 private:
  TsFis fis_;
  std::vector<GaitCmacs> networks_;
  TsFis::Result result_;
  std::vector<double> weights_;          // per reference gait
  std::vector<double> x_;                // FIS input scratch
  std::vector<double> pitches_;          // per gait, for QueryThigh (empty: not set)
  int v_m_input_ = 0, d_obs_input_ = 1;  // positions of V_M and d_obs among the FIS inputs
};

}  // namespace rabbit

#endif  // RABBIT_LEARN_FUZZY_CMAC_H_
