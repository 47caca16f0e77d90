// The multi-input CMAC gait pattern, a baseline of the walker (controller.baselines =
// ["multi_cmac"]): instead of the Fuzzy-CMAC's SISO CMACs merged by a fuzzy system (eqs. 12-13),
// four multi-input CMACs (rabbit/learn/multi_cmac.h), one per output q_i1, q_i2, qd_i1, qd_i2,
// each over the three inputs (e, V_M, d_obs): the alternative that the chapter (section 3) argues
// needs far more memory and generalises worse.
//
// Training (TrainMultiCmacPattern): the CMACs learn what a Fuzzy-CMAC (the teacher: the scenario's
// own gait pattern, the same FLL, networks and frame as the walker's) outputs, so both patterns
// hold the same information in two representations. The teacher is sampled on a regular grid over
// the domain (e or the stance thigh angle th_st, V_M, d_obs); the four CMACs share one structure
// (options, hash seed), so a grid point activates the same table slots in all four, and the fit is
// one sparse linear least-squares problem with four right-hand sides:
//   minimise  sum_points (O(x_p) - Y(x_p))^2 + ridge |w|^2
// (O = sum of the active weights, eq. 6), solved through its normal equations
// (A^T A + ridge I) w = A^T y, by Eigen's conjugate gradients (a sparse Cholesky factorisation
// fills in badly: hashing joins detectors far apart; the Ceres fit of optimizers/cmac_fit.h is not
// linked by rabbit_core). Slots no grid point reaches stay 0.
// Deterministic: the same weights for the same teacher, domain and options, on any thread.
//
// Grids: along each input, n points evenly spaced over [lo, hi] with both ends and a spacing of at
// most the grid step. The held-out grid (CompareWithTeacher) is the midpoints between neighbouring
// training points in every input: the points farthest from every training point.
#ifndef RABBIT_LEARN_MULTI_CMAC_PATTERN_H_
#define RABBIT_LEARN_MULTI_CMAC_PATTERN_H_

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rabbit/learn/fuzzy_cmac.h"
#include "rabbit/learn/multi_cmac.h"
#include "rabbit/learn/swing_pattern.h"

namespace rabbit {

// The largest hash table of one CMAC: 2^22 weights (32 MB).
constexpr int kMaxMultiCmacTable = 1 << 22;

// Every setting of the baseline: [controller.multi_cmac] in a scenario (docs/formats/scenario.md,
// "The multi_cmac baseline"). Quanta in input units (rad, m/s, m); widths in quanta (receptive field / quantum).
struct MultiCmacPatternOptions {
  // Structure. In e as the SISO CMACs of the Fuzzy-CMAC (0.25 deg quanta, 1.5 deg receptive
  // fields, 6 layers); V_M and d_obs resolved finely enough for the fuzzy sets' slopes.
  int layers = 6;                                            // N_l (<= every width)
  double e_quantum = 0.25 * 3.14159265358979323846 / 180.0;  // rad
  int e_width = 6;                                           // quanta: 1.5 deg
  double v_m_quantum = 0.01;                                 // m/s
  int v_m_width = 6;                                         // quanta: 0.06 m/s
  double d_obs_quantum = 0.02;                               // m
  int d_obs_width = 6;                                       // quanta: 0.12 m
  // Weights stored per output CMAC (4 of them). The default domain's virtual detector space has
  // 33,111 detectors per output; 2^16 slots leave 40% of them sharing a slot.
  int hash_table_size = 1 << 16;
  std::uint64_t hash_seed = 1;
  // V_M range: the reference gaits' measured velocities widened by this margin on both sides
  // (beyond it the input clamps, as the FIS's shoulders hold their gait).
  double v_m_margin = 0.1;  // m/s
  // Training grid steps (at most; see above). The defaults put a point in every quantum cell: a
  // coarser grid leaves cells that only the CMAC's local generalisation fills (docs/results.md).
  double grid_e_step = 0.25 * 3.14159265358979323846 / 180.0;  // rad
  double grid_v_m_step = 0.01;                                 // m/s
  double grid_d_obs_step = 0.02;                               // m
  // Least squares: the per-weight regulariser (in units of one grid point's squared residual),
  // and the conjugate-gradient solve of the normal equations (relative residual, iteration
  // limit).
  double ridge = 1e-3;
  double tolerance = 1e-8;
  int max_iterations = 2000;
  bool IsValid(std::string* error) const;
};

// Where the pattern is trained and queried: its first input is e (thigh_frame false) or th_st
// (true) over [e_min, e_max]; V_M over [v_m_min, v_m_max]; d_obs over [0, d_obs_max]. Inputs
// outside clamp.
struct MultiCmacPatternDomain {
  bool thigh_frame = true;
  double e_min = -1.0, e_max = 1.0;  // rad
  double v_m_min = 0.3, v_m_max = 0.9;
  double d_obs_max = 1.0;
  bool IsValid(std::string* error) const;
};

// The domain over which a teacher varies: e over its CMACs' input range (thigh frame: the union
// over the gaits of that range shifted by minus the gait's trunk pitch, where QueryThigh reaches
// it), V_M over the gait velocities widened by v_m_margin, d_obs up to d_obs_max. Throws
// std::invalid_argument without velocities or, for the thigh frame, without trunk pitches.
MultiCmacPatternDomain TeacherDomain(const FuzzyCmac& teacher,
                                     const std::vector<double>& gait_velocities, bool thigh_frame,
                                     double d_obs_max, double v_m_margin);

// Four CMACs over (e, V_M, d_obs) with one structure.
class MultiCmacPattern {
 public:
  // Zero weights. Throws std::invalid_argument for invalid options or domain.
  MultiCmacPattern(const MultiCmacPatternDomain& domain, const MultiCmacPatternOptions& options);

  const MultiCmacPatternDomain& domain() const { return domain_; }
  const MultiCmacPatternOptions& options() const { return options_; }
  // [q_i1, q_i2, qd_i1, qd_i2] (thigh frame: the swing thigh's absolute angle and rate first) at
  // (e or th_st, V_M, d_obs); NaN when an input is NaN. Allocates nothing.
  Eigen::Vector4d Query(double e, double v_m, double d_obs) const;

  const std::vector<MultiCmac>& cmacs() const { return cmacs_; }
  std::vector<MultiCmac>* mutable_cmacs() { return &cmacs_; }
  // The four tables' bytes.
  std::size_t MemoryBytes() const;

 private:
  MultiCmacPatternDomain domain_;
  MultiCmacPatternOptions options_;
  std::vector<MultiCmac> cmacs_;  // kGaitOutputs
};

struct MultiCmacTrainingSummary {
  int points = 0;      // training grid points (teacher evaluations)
  int unknowns = 0;    // table slots the grid reaches (per CMAC; the same in all four)
  int iterations = 0;  // conjugate-gradient iterations (the most of the four outputs)
  // Detectors of the virtual space that share a slot with another (-1: too many to enumerate,
  // MultiCmac::NumCollisionsOverRange).
  int collisions = 0;
  double virtual_detectors = 0.0;  // what a direct (unhashed) table would hold, per CMAC
  Eigen::Vector4d rms = Eigen::Vector4d::Zero();  // per output, on the training grid
  double seconds = 0.0;                           // wall time of the whole training
  std::string BriefReport() const;                // one line
};

// Trains the pattern on the teacher (see the file comment). A grid point where the teacher fires
// no rule is skipped. Throws std::invalid_argument for invalid options or domain, or when the
// teacher lacks trunk pitches for the thigh frame; std::runtime_error when the solve fails.
MultiCmacPattern TrainMultiCmacPattern(const FuzzyCmac& teacher,
                                       const MultiCmacPatternDomain& domain,
                                       const MultiCmacPatternOptions& options,
                                       MultiCmacTrainingSummary* summary = nullptr);

// The pattern against its teacher on the training grid (held_out false) or the held-out grid of
// midpoints (true): RMS and largest absolute error per output, over the points where the teacher
// fires.
struct MultiCmacPatternError {
  Eigen::Vector4d rms = Eigen::Vector4d::Zero(), max = Eigen::Vector4d::Zero();
  int points = 0;
};
MultiCmacPatternError CompareWithTeacher(const MultiCmacPattern& pattern, const FuzzyCmac& teacher,
                                         bool held_out);

// The trained pattern as the walker's gait pattern: SetContext holds (V_M, d_obs) for the step
// (a non-finite V_M or a NaN d_obs keeps the previous context and returns false); Query or
// QueryThigh, whichever frame it was trained in, evaluates the CMACs at (e, V_M, d_obs). No
// per-gait weights and no rules (GaitWeights and RuleActivations are empty).
class MultiCmacSwingPattern final : public SwingPattern {
 public:
  explicit MultiCmacSwingPattern(std::shared_ptr<const MultiCmacPattern> pattern);

  bool SetContext(double v_m, double d_obs) override;
  bool SetGaitWeights(const std::vector<double>&) override { return false; }  // none to set
  bool Supports(bool thigh_frame) const override {
    return thigh_frame == pattern_->domain().thigh_frame;
  }
  // Throw std::logic_error in the frame the pattern was not trained in.
  Eigen::Vector4d Query(double e) const override;
  Eigen::Vector4d QueryThigh(double th_st) const override;
  const std::vector<double>& GaitWeights() const override { return none_; }
  const std::vector<double>& RuleActivations() const override { return none_; }
  std::size_t MemoryBytes() const override { return pattern_->MemoryBytes(); }

 private:
  std::shared_ptr<const MultiCmacPattern> pattern_;
  double v_m_, d_obs_;  // NaN until the first SetContext
  std::vector<double> none_;
};

}  // namespace rabbit

#endif  // RABBIT_LEARN_MULTI_CMAC_PATTERN_H_
