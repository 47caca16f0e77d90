#include "rabbit/learn/cmac.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rabbit {
namespace {

// Keeps every detector count and weight index well inside int: at most 32 layers of
// 2^24 / width + 2 detectors.
constexpr double kMaxQuanta = 16777216.0;  // 2^24
// 4M weights (32 MB): far beyond any gait pattern, small enough that a file cannot exhaust memory.
constexpr int kMaxHashTable = 1 << 22;

}  // namespace

bool CmacOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (layers < 1 || layers > kMaxCmacLayers) {
    return fail("layers must be in [1, " + std::to_string(kMaxCmacLayers) + "], got " +
                std::to_string(layers));
  }
  if (!std::isfinite(quantum) || !(quantum > 0.0)) return fail("quantum must be finite and > 0");
  if (width < 1) return fail("width must be >= 1 quantum, got " + std::to_string(width));
  if (layers > width) {
    // Layer j is offset by j quanta: from j = width on the partitions repeat, and detector 0 of
    // such a layer would lie wholly before the range.
    return fail("layers (" + std::to_string(layers) + ") must be <= width (" +
                std::to_string(width) + ")");
  }
  if (!std::isfinite(x_min) || !std::isfinite(x_max) || !(x_min < x_max)) {
    return fail("the input range needs finite x_min < x_max");
  }
  const double quanta = (x_max - x_min) / quantum;
  if (!(quanta <= kMaxQuanta)) {
    return fail("too many quanta over the range ((x_max - x_min) / quantum must be <= 2^24)");
  }
  if (hash_table_size < 0) return fail("hash_table_size must be >= 0 (0: direct storage)");
  if (hash_table_size > kMaxHashTable) {
    return fail("hash_table_size must be at most " + std::to_string(kMaxHashTable));
  }
  return true;
}

Cmac::Cmac(const CmacOptions& options) : options_(options) {
  std::string error;
  if (!options_.IsValid(&error)) throw std::invalid_argument("Cmac: " + error);
  quanta_ = CmacNumQuanta(options_.x_max - options_.x_min, options_.quantum);

  const int layers = options_.layers;
  layer_offset_.assign(static_cast<size_t>(layers) + 1, 0);
  for (int j = 0; j < layers; ++j) layer_offset_[j + 1] = layer_offset_[j] + NumDetectorsInLayer(j);
  if (options_.hash_table_size == 0) {
    weights_.assign(static_cast<size_t>(NumDetectors()), 0.0);
    return;
  }
  weights_.assign(static_cast<size_t>(options_.hash_table_size), 0.0);
  // Every (layer, detector) pair over the range, by slot; a pair collides when another shares
  // its slot.
  std::vector<int> slots;
  slots.reserve(static_cast<size_t>(NumDetectors()));
  for (int j = 0; j < layers; ++j) {
    for (int d = 0; d < NumDetectorsInLayer(j); ++d) slots.push_back(DetectorAddress(j, d));
  }
  std::sort(slots.begin(), slots.end());
  for (size_t i = 0; i < slots.size(); ++i) {
    const bool same_as_previous = i > 0 && slots[i - 1] == slots[i];
    const bool same_as_next = i + 1 < slots.size() && slots[i + 1] == slots[i];
    if (same_as_previous || same_as_next) ++num_collisions_;
  }
}

int Cmac::NumDetectorsInLayer(int layer) const {
  return (quanta_ - 1 + layer) / options_.width + 1;
}

int Cmac::NumDetectors() const { return layer_offset_.back(); }

int Cmac::NumCollisions() const { return num_collisions_; }

int Cmac::DetectorAddress(int layer, int detector) const {
  if (options_.hash_table_size == 0) return layer_offset_[layer] + detector;
  std::uint64_t h = CmacHashStep(options_.hash_seed, static_cast<std::uint64_t>(layer));
  h = CmacHashStep(h, static_cast<std::uint64_t>(detector));
  return static_cast<int>(h % static_cast<std::uint64_t>(options_.hash_table_size));
}

int CmacNumQuanta(double range, double quantum) {
  // Evaluated with the same products that define the quanta.
  int quanta = std::max(1, static_cast<int>(std::ceil(range / quantum)));
  while (quanta > 1 && (quanta - 1) * quantum >= range) --quanta;
  while (quanta * quantum < range) ++quanta;
  return quanta;
}

int Cmac::Quantize(double x) const {
  return CmacQuantize(x, options_.x_min, options_.x_max, options_.quantum, quanta_);
}

void Cmac::Active(double x, CmacActive* active) const {
  const int k = Quantize(x);
  if (k < 0) {
    active->count = 0;
    return;
  }
  const int layers = options_.layers;
  active->count = layers;
  for (int j = 0; j < layers; ++j) active->index[j] = DetectorAddress(j, (k + j) / options_.width);
}

double Cmac::Query(double x) const {
  const int k = Quantize(x);
  if (k < 0) return std::numeric_limits<double>::quiet_NaN();
  double sum = 0.0;
  for (int j = 0; j < options_.layers; ++j)
    sum += weights_[DetectorAddress(j, (k + j) / options_.width)];
  return sum;
}

double Cmac::Update(double x, double target, double beta) {
  CmacActive active;
  Active(x, &active);
  if (active.count == 0) return std::numeric_limits<double>::quiet_NaN();
  double output = 0.0;
  for (int j = 0; j < active.count; ++j) output += weights_[active.index[j]];
  if (!std::isfinite(target) || !std::isfinite(beta)) return output;
  const double step = beta * (target - output) / options_.layers;
  for (int j = 0; j < active.count; ++j) weights_[active.index[j]] += step;
  return output;
}

}  // namespace rabbit
