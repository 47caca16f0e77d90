// SISO CMAC (Albus; chapter section 3.1).
//
// N_l layers of binary detectors over a quantized scalar input. The input x (clamped to
// [x_min, x_max]) is quantized to the integer quantum k = floor((x - x_min) / dq). Each layer's
// detectors are `width` quanta wide (receptive field / dq; chapter: 1.5 deg / 0.25 deg = 6 = N_l),
// and layer j is offset by j quanta: in layer j the active detector is floor((k + j) / width).
// Exactly one detector per layer is active; the output is the sum of the N_l active weights
// (eq. 6), and LMS training adds beta (O_d - O) / N_l to each active weight (eq. 7).
//
// Storage is direct (one weight per detector of each layer) or hashed into a table of
// `hash_table_size` weights (with a seeded hash of (layer, detector)); collisions are counted.
// Query and update allocate nothing.
//
// Quanta: with u = x - x_min, quantum k covers u in [k dq, (k + 1) dq); there are
// NumQuanta() = the smallest Q with Q dq >= x_max - x_min, and x_max belongs to the last one (the
// last quantum may reach past x_max when the range is not a multiple of dq). Layer j then has
// floor((Q - 1 + j) / width) + 1 detectors; layers <= width (beyond, the offsets would repeat).
// Direct storage keeps layer j's weights contiguous, after those of layers 0..j-1. Hashed storage
// puts detector d of layer j at CmacHashStep(CmacHashStep(seed, j), d) mod hash_table_size.
//
// A NaN input has no active detector: Active gives count 0 and Query NaN. Update changes nothing
// when x is NaN or target or beta is not finite (it still returns the output before it).
#ifndef RABBIT_LEARN_CMAC_H_
#define RABBIT_LEARN_CMAC_H_

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace rabbit {

struct CmacOptions {
  int layers = 6;                                          // N_l
  double quantum = 0.25 * 3.14159265358979323846 / 180.0;  // dq, input units (rad): 0.25 deg
  int width = 6;                     // detector width in quanta (receptive field / dq)
  double x_min = -1.0, x_max = 1.0;  // input range; outside it the input clamps to the edge
  int hash_table_size = 0;           // 0: direct storage; > 0: hashed into this many weights
  std::uint64_t hash_seed = 1;
  bool IsValid(std::string* error) const;
};

// The addresses (weight indices) of the N_l active detectors for one input.
constexpr int kMaxCmacLayers = 32;
struct CmacActive {
  int count = 0;                            // = layers
  std::array<int, kMaxCmacLayers> index{};  // into weights()
};

class Cmac {
 public:
  explicit Cmac(const CmacOptions& options);  // throws std::invalid_argument if invalid

  const CmacOptions& options() const { return options_; }
  // Active detectors' weight indices for input x (clamped).
  void Active(double x, CmacActive* active) const;
  // O(x) = sum of the active weights (eq. 6).
  double Query(double x) const;
  // One LMS step toward target (eq. 7): w_i += beta (target - O) / N_l on the active weights.
  // Returns the output before the update.
  double Update(double x, double target, double beta);

  const std::vector<double>& weights() const { return weights_; }
  std::vector<double>* mutable_weights() { return &weights_; }
  // Number of detectors over the input range (all layers), i.e. the direct table's size.
  int NumDetectors() const;
  // Hashed storage: number of (layer, detector) pairs that share a weight with another pair.
  int NumCollisions() const;
  std::size_t MemoryBytes() const { return weights_.size() * sizeof(double); }

  // Number of quanta over the range (Q above).
  int NumQuanta() const { return quanta_; }
  // The quantum of x after clamping, in [0, NumQuanta()); -1 for NaN.
  int Quantize(double x) const;
  // Number of detectors of layer `layer` (in [0, layers)).
  int NumDetectorsInLayer(int layer) const;
  // Weight index of detector `detector` of layer `layer` (both in range).
  int Address(int layer, int detector) const { return DetectorAddress(layer, detector); }

 private:
  int DetectorAddress(int layer, int detector) const;
  CmacOptions options_;
  int quanta_ = 0;                 // number of quanta over the range
  std::vector<int> layer_offset_;  // direct storage: first weight of each layer
  std::vector<double> weights_;
  int num_collisions_ = 0;  // computed once: the structure never changes
};

// Quantization of one input, shared with the multi-input CMAC: the number of quanta Q over a
// range (the smallest Q with Q quantum >= range), and the quantum of x clamped to [x_min, x_max]
// (u = x - x_min in [k quantum, (k + 1) quantum), the last one closed at x_max; -1 for NaN).
int CmacNumQuanta(double range, double quantum);
inline int CmacQuantize(double x, double x_min, double x_max, double quantum, int quanta) {
  if (std::isnan(x)) return -1;
  const double u = (x < x_min ? x_min : (x > x_max ? x_max : x)) - x_min;
  int k = static_cast<int>(u / quantum);  // u >= 0: truncation is floor
  if (k > quanta - 1) k = quanta - 1;
  // The division can round across a boundary: settle k by the products that define the quanta.
  if (k + 1 < quanta && (k + 1) * quantum <= u) {
    ++k;
  } else if (k > 0 && k * quantum > u) {
    --k;
  }
  return k;
}

// The 64-bit hashing behind hashed storage: splitmix64's finaliser (a bijection), and a chaining
// step that folds one more part (layer, detector index) into a running hash started from the
// seed. Stable across platforms and runs; shared with the multi-input CMAC.
inline std::uint64_t CmacMix64(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xBF58476D1CE4E5B9ULL;
  x ^= x >> 27;
  x *= 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}
inline std::uint64_t CmacHashStep(std::uint64_t hash, std::uint64_t part) {
  return CmacMix64(hash + 0x9E3779B97F4A7C15ULL + part);
}

}  // namespace rabbit

#endif  // RABBIT_LEARN_CMAC_H_
