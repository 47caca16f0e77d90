// Multi-input CMAC (Albus), the baseline the chapter argues against (section 3,
// section 4): one network over an n-dimensional input instead of SISO CMACs merged by a fuzzy
// system.
//
// Each input dimension i is quantized as in the SISO CMAC (cmac.h): quantum dq_i over
// [x_min_i, x_max_i] (the input clamped to it), k_i = the quantum of x_i. There are N_l layers;
// layer j is offset by j quanta in every dimension, its detectors are width_i quanta wide in
// dimension i, and its one active detector is the tuple (floor((k_i + j) / width_i))_i. The
// output is the sum of the N_l active weights (eq. 6) and LMS adds beta (O_d - O) / N_l to each
// (eq. 7), as in the SISO CMAC. As there, layers <= width_i in every dimension.
//
// The virtual detector space (the product of the per-dimension detector counts, per layer) grows
// exponentially with n, so storage is always hashed: the tuple (layer j, d_0, ..., d_{n-1}) goes
// to slot h mod hash_table_size, h = CmacHashStep(...CmacHashStep(CmacHashStep(seed, j), d_0)...,
// d_{n-1}). Distinct detectors that share a slot collide and interfere; NumCollisions counts them
// over the detectors that a given set of inputs addresses (e.g. the training set),
// NumCollisionsOverRange over the whole virtual space when it is small enough to enumerate.
//
// A NaN in any coordinate: no active detector (Active count 0), Query NaN, Update changes
// nothing; Update also changes nothing for a non-finite target or beta. Query, Update and Active
// allocate nothing.
#ifndef RABBIT_LEARN_MULTI_CMAC_H_
#define RABBIT_LEARN_MULTI_CMAC_H_

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rabbit/learn/cmac.h"

namespace rabbit {

constexpr int kMaxMultiCmacInputs = 8;

// One input dimension.
struct MultiCmacInput {
  double quantum = 0.25 * 3.14159265358979323846 / 180.0;  // dq_i, input units
  int width = 6;                                           // detector width in quanta
  double x_min = -1.0, x_max = 1.0;                        // range; the input clamps to it
};

struct MultiCmacOptions {
  int layers = 6;                      // N_l
  std::vector<MultiCmacInput> inputs;  // 1 to kMaxMultiCmacInputs dimensions
  int hash_table_size = 1 << 16;       // weights actually stored (> 0)
  std::uint64_t hash_seed = 1;
  bool IsValid(std::string* error) const;
};

class MultiCmac {
 public:
  explicit MultiCmac(const MultiCmacOptions& options);  // throws std::invalid_argument if invalid

  const MultiCmacOptions& options() const { return options_; }
  int num_inputs() const { return num_inputs_; }

  // x points to num_inputs() values.
  void Active(const double* x, CmacActive* active) const;
  double Query(const double* x) const;  // eq. 6
  // One LMS step toward target (eq. 7); returns the output before the update.
  double Update(const double* x, double target, double beta);

  const std::vector<double>& weights() const { return weights_; }
  std::vector<double>* mutable_weights() { return &weights_; }
  std::size_t MemoryBytes() const { return weights_.size() * sizeof(double); }

  // Number of quanta of dimension i.
  int NumQuanta(int i) const { return quanta_[i]; }
  // Size of the virtual detector space: sum over layers of the product of the per-dimension
  // detector counts (a double: it overflows integers quickly). A direct table would need this
  // many weights.
  double NumVirtualDetectors() const;
  // Distinct detectors (layer, tuple) activated by any of the `count` points (row-major,
  // num_inputs() values each; NaN points skipped) that share a table slot with another such
  // detector. Allocates; not for the hot path.
  int NumCollisions(const double* points, int count) const;
  // The same over every detector of the virtual space; -1 when that has more than
  // kMaxEnumeratedDetectors detectors.
  static constexpr double kMaxEnumeratedDetectors = 1 << 22;
  int NumCollisionsOverRange() const;

 private:
  // Quantizes x into k; false when some coordinate is NaN.
  bool Quantize(const double* x, int* k) const;
  int Slot(int layer, const int* detector) const;
  // The active detector tuple of `layer` for quanta k.
  void LayerDetectors(int layer, const int* k, int* detector) const;

  MultiCmacOptions options_;
  int num_inputs_ = 0;
  std::array<int, kMaxMultiCmacInputs> quanta_{};
  std::vector<double> weights_;
};

}  // namespace rabbit

#endif  // RABBIT_LEARN_MULTI_CMAC_H_
